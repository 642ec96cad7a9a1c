#include "sim/collision/shape_table.hpp"

#include <algorithm>
#include <cmath>
#include <map>

#include <simreel/error.hpp>
#include "sim/geometry/convex_hull.hpp"
#include "sim/geometry/trimesh.hpp"

namespace simreel {

namespace {

double bounding_radius(const CollideShape& g) {
  switch (g.kind) {
    case CollideKind::plane:
      return 0;
    case CollideKind::sphere:
      return g.radius;
    case CollideKind::capsule:
      return g.half_length + g.radius;
    case CollideKind::cylinder:
      return std::hypot(g.half_length, g.radius);
    case CollideKind::ellipsoid:
      return g.radii.maxCoeff();
    case CollideKind::box:
      return g.half_extents.norm();
    case CollideKind::hull: {
      double r = 0;
      for (const Vec3& v : g.hull->vertices) r = std::max(r, v.norm());
      return r;
    }
    case CollideKind::mesh: {
      double r = 0;
      for (const Vec3& v : g.mesh->vertices) r = std::max(r, v.norm());
      return r;
    }
    case CollideKind::count:
      break;
  }
  return 0;
}

}  // namespace

ShapeTable::ShapeTable(const std::vector<BodyDef>& defs, const std::vector<BodyModel>& models,
                       std::vector<std::string>& notes) {
  std::map<const TriangleMesh*, std::shared_ptr<const TriMeshShape>> trimeshes;  // one per mesh
  for (int b = 0; b < (int)defs.size(); ++b) {
    const BodyDef& d = defs[b];
    const BodyModel& m = models[b];
    // Collider frame C in the principal frame P: X_PC = X_PB X_BC, with X_BP = (q_BP, c_B).
    const Quat q_PB = m.q_BP.conjugate();
    for (int k = 0; k < (int)d.colliders.size(); ++k) {
      const Collider& c = d.colliders[k];
      if (!c.collide) continue;
      if (c.shape == ShapeKind::plane && d.type != BodyType::static_body)
        throw InputError("body '" + d.name + "': a plane collider needs a static body");
      ShapeRecord r;
      r.body = b;
      r.collider = k;
      r.R_PC = (q_PB * c.q_BC).toRotationMatrix();
      r.p_PC = q_PB * (c.p_BC - m.c_B);
      r.classify();
      r.friction = c.friction;
      r.restitution = c.restitution;
      r.group = c.group;
      r.mask = c.mask;
      CollideShape& g = r.geom;
      switch (c.shape) {
        case ShapeKind::plane:
          g.kind = CollideKind::plane;
          break;
        case ShapeKind::sphere:
          g.kind = CollideKind::sphere;
          g.radius = c.radius;
          break;
        case ShapeKind::capsule:
          g.kind = CollideKind::capsule;
          g.radius = c.radius;
          g.half_length = 0.5 * c.height - c.radius;
          break;
        case ShapeKind::cylinder:
          g.kind = CollideKind::cylinder;
          g.radius = c.radius;
          g.half_length = 0.5 * c.height;
          break;
        case ShapeKind::ellipsoid:
          g.kind = CollideKind::ellipsoid;
          g.radii = c.radii;
          break;
        case ShapeKind::box: {
          g.kind = CollideKind::box;
          g.half_extents = 0.5 * c.size;
          auto p = std::make_shared<const ConvexPolyhedron>(make_box_polyhedron(g.half_extents));
          g.hull = p.get();
          owned_.push_back(std::move(p));
          break;
        }
        case ShapeKind::mesh: {
          if (d.type == BodyType::static_body) {
            // A static body's mesh collides as its triangles (sim/geometry/trimesh.hpp), not a hull.
            if (!c.mesh) throw InputError("body '" + d.name + "': mesh collider without a mesh");
            std::shared_ptr<const TriMeshShape>& tm = trimeshes[c.mesh.get()];
            if (!tm) {
              try {
                tm = std::make_shared<const TriMeshShape>(make_trimesh_shape(*c.mesh));
              } catch (const InputError& e) {
                throw InputError("body '" + d.name + "': " + e.what());
              }
            }
            g.kind = CollideKind::mesh;
            g.mesh = tm.get();
            owned_meshes_.push_back(tm);
            break;
          }
          g.kind = CollideKind::hull;
          std::vector<std::shared_ptr<const ConvexPolyhedron>> hulls = c.hulls;
          if (hulls.empty()) {
            if (!c.mesh) throw InputError("body '" + d.name + "': mesh collider without a mesh");
            hulls.push_back(std::make_shared<const ConvexPolyhedron>(convex_polyhedron(c.mesh->vertices)));
          }
          // One record per convex piece.
          for (size_t h = 0; h < hulls.size(); ++h) {
            ShapeRecord rh = r;
            rh.geom.hull = hulls[h].get();
            rh.geom.bounding_radius = bounding_radius(rh.geom);
            shapes_.push_back(rh);
            owned_.push_back(hulls[h]);
          }
          (void)notes;
          continue;
        }
      }
      g.bounding_radius = bounding_radius(g);
      shapes_.push_back(r);
    }
  }
}

double rounding_radius(const CollideShape& g) {
  switch (g.kind) {
    case CollideKind::sphere:
    case CollideKind::capsule:
    case CollideKind::cylinder:
      return g.radius;
    case CollideKind::ellipsoid:
      return g.radii.minCoeff();
    default:
      return 0;
  }
}

void ShapeRecord::classify() {
  centred = p_PC == Vec3::Zero();
  int8_t p[3] = {0, 0, 0};
  for (int j = 0; j < 3; ++j) {
    int nonzero = 0;
    for (int i = 0; i < 3; ++i) {
      if (R_PC(i, j) == 0) continue;
      ++nonzero;
      if (R_PC(i, j) == 1) p[j] = (int8_t)(1 + i);
      if (R_PC(i, j) == -1) p[j] = (int8_t)(-1 - i);
    }
    if (nonzero != 1 || p[j] == 0) {
      perm[0] = perm[1] = perm[2] = 0;
      return;
    }
  }
  for (int j = 0; j < 3; ++j) perm[j] = p[j];
}

Aabb ShapeTable::bounds(const CollideShape& g, const Pose& x) {
  Vec3 e = Vec3::Zero();  // half extents about x.p
  Vec3 c = x.p;
  const Mat3& R = x.R;
  switch (g.kind) {
    case CollideKind::plane:
      e = Vec3::Constant(INFINITY);
      break;
    case CollideKind::sphere:
      e = Vec3::Constant(g.radius);
      break;
    case CollideKind::capsule:
      e = g.half_length * R.col(2).cwiseAbs() + Vec3::Constant(g.radius);
      break;
    case CollideKind::cylinder:
      // Disk of radius r with normal a: extent along axis i is r sqrt(1 - a_i^2).
      for (int i = 0; i < 3; ++i) {
        const double a = R(i, 2);
        e[i] = g.half_length * std::fabs(a) + g.radius * std::sqrt(std::max(0.0, 1.0 - a * a));
      }
      break;
    case CollideKind::ellipsoid:
      // Support of R diag(r) unit-ball along e_i: |row_i(R) diag(r)|.
      for (int i = 0; i < 3; ++i) e[i] = R.row(i).cwiseProduct(g.radii.transpose()).norm();
      break;
    case CollideKind::box:
      e = R.cwiseAbs() * g.half_extents;
      break;
    case CollideKind::mesh: {
      const Vec3 mc = 0.5 * (g.mesh->lo + g.mesh->hi), me = 0.5 * (g.mesh->hi - g.mesh->lo);
      c = x.apply(mc);
      e = R.cwiseAbs() * me;
      break;
    }
    case CollideKind::hull: {
      Vec3 lo = Vec3::Constant(INFINITY), hi = Vec3::Constant(-INFINITY);
      const ConvexPolyhedron& H = *g.hull;
      if ((int)H.vertices.size() > ConvexPolyhedron::kScanVertices && !H.vertex_edge.empty()) {
        // Six support points (climbed: ~sqrt(n) vertices each) instead of every vertex: a
        // 3,000-vertex hull's box cost 10 us a step.
        for (int k = 0; k < 3; ++k) {
          const Vec3 d = R.row(k).transpose();
          lo[k] = d.dot(H.vertices[H.support(-d)]);
          hi[k] = d.dot(H.vertices[H.support(d)]);
        }
        return Aabb{c + lo, c + hi};
      }
      for (const Vec3& v : g.hull->vertices) {
        const Vec3 w = R * v;
        lo = lo.cwiseMin(w);
        hi = hi.cwiseMax(w);
      }
      return Aabb{c + lo, c + hi};
    }
    case CollideKind::count:
      break;
  }
  return Aabb{c - e, c + e};
}

}  // namespace simreel
