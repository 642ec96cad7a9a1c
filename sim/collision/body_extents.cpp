#include "sim/collision/body_extents.hpp"

#include <algorithm>

#include "sim/collision/time_of_impact.hpp"

namespace simreel {

void BodyExtents::build(const ShapeTable& st, int n) {
  shape_begin.assign(n + 1, 0);
  shape_body.resize(st.size());
  for (int k = 0; k < st.size(); ++k) shape_begin[st[k].body + 1]++, shape_body[k] = st[k].body;
  for (int b = 0; b < n; ++b) shape_begin[b + 1] += shape_begin[b];
  shape_reach.assign(st.size(), 0.0);
  shape_width.assign(st.size(), kInfinity);
  reach.assign(n, 0.0);
  swept_reach.assign(n, 0.0);
  width.assign(n, kInfinity);
  for (int k = 0; k < st.size(); ++k) {
    const ShapeRecord& r = st[k];
    shape_reach[k] = r.p_PC.norm() + r.geom.bounding_radius;
    reach[r.body] = std::max(reach[r.body], shape_reach[k]);
    if (r.geom.kind == CollideKind::plane || r.geom.kind == CollideKind::mesh || r.group == 0 || r.mask == 0)
      continue;
    shape_width[k] = min_width(r.geom);
    swept_reach[r.body] = std::max(swept_reach[r.body], shape_reach[k]);
    width[r.body] = std::min(width[r.body], shape_width[k]);
  }
}

}  // namespace simreel
