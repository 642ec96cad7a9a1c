// Mesh files read once per scene, whoever places them (a scene's `colliders:`, an imported URDF or
// MJCF file): the file at each scale, its analysis at density 1 per mass mode, and its collision
// hulls per hull mode and cap. A pile of a thousand copies of one file took 1.8 s a copy, nearly
// all in building and checking its hull, before these were shared.
#pragma once
#include <map>
#include <memory>
#include <string>
#include <vector>

#include <simreel/mesh.hpp>
#include "app/scene/mesh_import.hpp"
#include "sim/geometry/convex_decomposition.hpp"
#include "sim/geometry/convex_hull.hpp"
#include "sim/geometry/polyhedron.hpp"

namespace simreel {

class MeshLibrary {
 public:
  using Hulls = std::vector<std::shared_ptr<const ConvexPolyhedron>>;
  // `notes` receives each file's reader notes once, as "FILE: note".
  explicit MeshLibrary(std::vector<std::string>& notes) : notes_(notes) {}

  // The key of a file at a scale, exact to the bit (hexadecimal: std::to_string's six decimals
  // made 1e-7 and 2e-7 one mesh).
  static std::string key(const std::string& file, const Vec3& scale);
  // The file read at `scale`; throws InputError naming the file.
  std::shared_ptr<const ImportedMesh> file(const std::string& file, const Vec3& scale);
  // Its surface, owned with the file (one allocation, one owner).
  std::shared_ptr<const TriangleMesh> surface(const std::string& file, const Vec3& scale);
  // Its analysis at density 1 (opt.density is ignored); throws InputError for a mesh that cannot
  // be a solid of that mode.
  const MeshReport& analysis(const std::string& file, const Vec3& scale, const MeshMassOptions& opt);
  // Its collision hulls (one, or one per connected part), each capped at `cap` vertices (0: none);
  // `reductions` gets what the cap did when the hulls are first built.
  const Hulls& hulls(const std::string& file, const Vec3& scale, bool parts, int cap,
                     std::vector<HullReduction>* reductions = nullptr);

  // Its approximate convex decomposition (sim/geometry/convex_decomposition.hpp), each part capped
  // at `cap` hull vertices (0: 64). Kept on disk too, keyed by a hash of the file's bytes, the
  // scale and the options: in SIMREEL_CACHE_DIR, else $XDG_CACHE_HOME/simreel, else
  // ~/.cache/simreel (a folder that cannot be written is skipped). A cached decomposition is the
  // same to the bit: the parts are rebuilt from the points they were made from.
  const Decomposition& decomposition(const std::string& file, const Vec3& scale, int cap);
  // Every mesh file read so far and the image files their materials name (resolved paths), for
  // what a scene depends on.
  std::vector<std::string> files() const;

 private:
  std::vector<std::string>& notes_;
  std::map<std::string, Decomposition> decompositions_;
  std::map<std::string, std::shared_ptr<const ImportedMesh>> files_;
  std::map<std::string, MeshReport> reports_;
  std::map<std::string, Hulls> hulls_;
};

}  // namespace simreel
