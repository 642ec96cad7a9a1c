// Simreel's import and solid mass properties over the public meshes in
// SIMREEL_REAL_MESHES_DIR (../shared/meshes/real; this test is only built when it exists, label
// real_meshes), against exact references: GMP integer sums on the very doubles simreel weighed
// (tests/sim/mass/exact_mass.hpp). Closed meshes must match to 1e-12 relative; open ones (SOURCES.md
// says which) must be refused as open. Each mesh prints one line of figures.
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>

#include "app/scene/mesh_import.hpp"
#include <simreel/error.hpp>
#include "tests/sim/mass/exact_mass.hpp"

namespace simreel {
namespace {

namespace fs = std::filesystem;

std::vector<std::string> mesh_files() {
  std::vector<std::string> out;
  for (const auto& e : fs::directory_iterator(SIMREEL_REAL_MESHES_DIR))
    if (e.is_regular_file() && e.path().extension() != ".md") out.push_back(e.path().filename().string());
  std::sort(out.begin(), out.end());
  return out;
}

// "closed" or "open" per file, from the last column of SOURCES.md's table.
std::map<std::string, std::string> sources_table() {
  std::map<std::string, std::string> out;
  std::ifstream f(fs::path(SIMREEL_REAL_MESHES_DIR) / "SOURCES.md");
  std::string line;
  while (std::getline(f, line)) {
    if (line.rfind("| ", 0) != 0) continue;
    std::vector<std::string> cells;
    std::stringstream ss(line.substr(1));
    std::string c;
    while (std::getline(ss, c, '|')) {
      c.erase(0, c.find_first_not_of(' '));
      c.erase(c.find_last_not_of(' ') + 1);
      cells.push_back(c);
    }
    if (cells.size() >= 2 && (cells.back() == "closed" || cells.back() == "open"))
      out[cells[0]] = cells.back();
  }
  return out;
}

class RealMesh : public ::testing::TestWithParam<std::string> {};

TEST_P(RealMesh, ImportAndSolidMassMatchExactReference) {
  const std::string name = GetParam();
  const auto table = sources_table();
  ASSERT_TRUE(table.count(name)) << name << " is not in SOURCES.md";
  const bool closed = table.at(name) == "closed";
  const ImportedMesh im = import_mesh((fs::path(SIMREEL_REAL_MESHES_DIR) / name).string());
  MeshMassOptions opt;
  opt.density = 1.0;
  MeshReport rep;
  std::string error;
  try {
    rep = analyze_mesh(im.mesh, opt);
  } catch (const InputError& e) {
    error = e.what();
  }
  const char* precision = im.double_precision() ? "double" : "float32 (assimp)";
  if (!closed) {
    EXPECT_NE(error.find("mesh is open"), std::string::npos)
        << name << ": " << (error.empty() ? "accepted" : error);
    std::printf("[real] %-40s %-10s %-16s refused: %s\n", name.c_str(), im.reader.c_str(), precision,
                error.substr(0, 60).c_str());
    return;
  }
  // A closed surface whose exact signed volume is zero (every face twice, once per winding)
  // must be refused too.
  const test::ExactMass as_given = test::exact_mass(im.mesh);
  if (as_given.zero_volume) {
    EXPECT_NE(error.find("encloses no volume"), std::string::npos) << name << ": " << error;
    std::printf("[real] %-40s %-10s %-16s refused (exact volume 0): %s\n", name.c_str(), im.reader.c_str(),
                precision, error.substr(0, 40).c_str());
    return;
  }
  ASSERT_TRUE(error.empty()) << name << ": " << error;
  // The reference is the surface simreel weighed: welded (exact), winding repaired and slivers
  // dropped by repaired_mesh, which only reorders indices.
  const TriangleMesh weighed = repaired_mesh(im.mesh);
  const test::ExactMass ex = test::exact_mass(weighed);
  ASSERT_FALSE(ex.zero_volume);
  // With no repair reported, the as-given volume must agree in size too.
  if (rep.reoriented_faces == 0 && !rep.inverted) {
    EXPECT_NEAR(std::fabs(as_given.volume), ex.volume, 1e-12 * ex.volume) << name;
  }
  double diag = 0;
  {
    Vec3 lo = weighed.vertices[0], hi = lo;
    for (const Vec3& v : weighed.vertices) {
      lo = lo.cwiseMin(v);
      hi = hi.cwiseMax(v);
    }
    diag = (hi - lo).norm();
  }
  const double e_mass = std::fabs(rep.props.mass - ex.volume) / ex.volume;
  const double e_com = (rep.props.com - ex.centroid).norm() / diag;
  const double e_inertia = (rep.props.inertia - ex.inertia).norm() / ex.inertia.norm();
  const double worst = std::max({e_mass, e_com, e_inertia});
  EXPECT_LT(worst, 1e-12) << name << ": mass " << e_mass << ", centroid " << e_com << ", inertia "
                          << e_inertia;
  std::printf("[real] %-40s %-10s %-16s mass %.1e  centroid %.1e  inertia %.1e  (%zu faces)\n", name.c_str(),
              im.reader.c_str(), precision, e_mass, e_com, e_inertia, weighed.triangles.size());
}

std::string test_name(const ::testing::TestParamInfo<std::string>& i) {
  std::string s = i.param;
  for (char& c : s)
    if (!std::isalnum((unsigned char)c)) c = '_';
  return s;
}

INSTANTIATE_TEST_SUITE_P(Shared, RealMesh, ::testing::ValuesIn(mesh_files()), test_name);

}  // namespace
}  // namespace simreel
