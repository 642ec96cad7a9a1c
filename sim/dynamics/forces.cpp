#include "sim/dynamics/forces.hpp"

#include <string>

#include <simreel/error.hpp>
#include "sim/base/enum_names.hpp"

namespace simreel {

namespace {
constexpr EnumNames<ForceKind, 6> kForceKinds{{"force", "torque", "impulse", "angular_impulse", "spring", "drag"}};
static_assert(kForceKinds.complete());
}  // namespace

const char* to_string(ForceKind k) {
  return kForceKinds(k);
}

namespace {
bool finite(const Vec3& v) {
  return std::isfinite(v.x()) && std::isfinite(v.y()) && std::isfinite(v.z());
}
}  // namespace

void validate_forces(const std::vector<ForceDef>& forces, const std::vector<BodyModel>& models,
                     const std::vector<std::string>& names) {
  const int n = (int)models.size();
  for (size_t k = 0; k < forces.size(); ++k) {
    const ForceDef& f = forces[k];
    const std::string what = std::string("force ") + std::to_string(k) + " (" + to_string(f.kind) + ")";
    auto fail = [&](const std::string& why) { throw InputError(what + ": " + why); };
    if (f.body < 0 || f.body >= n) fail("body index out of range");
    const BodyModel& m = models[f.body];
    if (m.is_static || m.is_kinematic)
      fail("body '" + names[f.body] + "' is " + (m.is_static ? "static" : "kinematic") +
           ": forces act on dynamic bodies only");
    if (f.kind == ForceKind::spring && f.body_b >= n) fail("second body index out of range");
    if (f.kind == ForceKind::spring && f.body_b == f.body) fail("a spring needs two different bodies");
    if (!finite(f.vector) || !finite(f.at_B) || !finite(f.at_b_B) || !finite(f.anchor_W) ||
        !std::isfinite(f.time) || !std::isfinite(f.stiffness) || !std::isfinite(f.rest_length) ||
        !std::isfinite(f.damping) || !std::isfinite(f.linear) || !std::isfinite(f.quadratic) ||
        std::isnan(f.from) || std::isnan(f.to))
      fail("values must be finite");
    if (f.stiffness < 0 || f.damping < 0 || f.linear < 0 || f.quadratic < 0 || f.rest_length < 0)
      fail("stiffness, damping, rest length and drag coefficients must not be negative");
    if (f.from > f.to) fail("the window's start (from) is after its end (to)");
  }
}

void force_rates(const ForceDef& f, const MotionState* st, const BodyModel* mo, double* rate2,
                 double* rate1) {
  switch (f.kind) {
    case ForceKind::drag: {
      const int i = f.body;
      rate1[i] += (f.linear + 2.0 * f.quadratic * st[i].v_W.norm()) * mo[i].inv_mass;
      break;
    }
    case ForceKind::spring: {
      // Compliance of each end along the line: 1/m + r^2 / I_min (a lever arm r turns the body).
      auto compliance = [&](int i, bool centroid, const Vec3& p_B) {
        const BodyModel& m = mo[i];
        if (m.inv_mass == 0) return 0.0;
        const double r2 = centroid ? 0.0 : (p_B - m.c_B).squaredNorm();
        return m.inv_mass + r2 * m.inv_I_P.maxCoeff();
      };
      double inv_m = compliance(f.body, f.at_centroid, f.at_B);
      if (f.body_b >= 0) inv_m += compliance(f.body_b, f.at_b_centroid, f.at_b_B);
      for (int i : {f.body, f.body_b}) {
        if (i < 0 || mo[i].inv_mass == 0) continue;
        rate2[i] += f.stiffness * inv_m;
        rate1[i] += f.damping * inv_m;
      }
      break;
    }
    default:
      break;
  }
}

}  // namespace simreel
