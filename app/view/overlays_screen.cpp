// The 2D screen layer of a scene's overlays (app/view/overlays.hpp): title, HUD, captions, labels,
// legend and inset plots, laid out in pixels over the finished frame. Text is in the TeX subset of
// render/tex.hpp throughout.
#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <numbers>

#include "app/view/overlays.hpp"
#include "app/view/quantities.hpp"
#include "render/camera.hpp"

namespace simreel {

namespace {

const Rgba8 kPanel{16, 20, 28, 150}, kInk{255, 255, 255, 255};

uint8_t encode(float linear) {
  const double x = std::clamp((double)linear, 0.0, 1.0);
  const double s = x <= 0.0031308 ? 12.92 * x : 1.055 * std::pow(x, 1 / 2.4) - 0.055;
  return (uint8_t)std::lround(255 * s);
}

Rgba8 faded(Rgba8 c, double a) {
  c[3] = (uint8_t)std::lround(c[3] * std::clamp(a, 0.0, 1.0));
  return c;
}

// Plot curves' default colours: Okabe-Ito, those that read on the dark panel first.
const int kPlotColors[8] = {6, 3, 2, 4, 1, 7, 5, 0};

}  // namespace

Rgba8 to_display(const Rgba& c) {
  return {encode(c[0]), encode(c[1]), encode(c[2]), (uint8_t)std::lround(255 * std::clamp(c[3], 0.0f, 1.0f))};
}

void SceneOverlays::make_screen(const Scene& scene, const World& world) {
  has_screen_ = !hud_.empty() || !title_.empty() || !captions_.empty() || !labels_.empty() || legend_.shown ||
                !plots_.empty();
  if (!has_screen_) return;
  const std::string path = default_font_path();
  const int px = std::max(10, (int)std::lround(height_ * 0.032 * scene.overlays.text_size));
  font_ = std::make_unique<Typeface>(path, px);
  small_font_ = std::make_unique<Typeface>(path, std::max(8, (int)std::lround(0.8 * px)));
  lines_.resize(hud_.size());
  label_boxes_.reserve(labels_.size());
  if (!title_.empty()) {
    // A title wider than the frame is set smaller until it fits (with its panel and a margin).
    int tp = std::max(12, (int)std::lround(px * 1.4));
    title_font_ = std::make_unique<Typeface>(path, tp);
    for (int tries = 0; tries < 40; ++tries) {
      const int avail = width_ - 2 * (tp / 2) - 2 * (px / 2);
      const int tw = title_font_->width(title_);
      if (tw <= avail || tp <= 6) break;
      tp = std::max(6, std::min(tp - 1, (int)std::floor(tp * (double)avail / tw)));
      title_font_ = std::make_unique<Typeface>(path, tp);
    }
  }
  if (legend_.shown && legend_.items.empty()) fill_legend(scene);
  if (hud_corner_ == "auto") {
    if (hud_camera_ && !hud_bodies_.empty())
      choose_hud_corner(world);
    else
      hud_corner_ = "top_left";
  }
  for (Plot& p : plots_) {
    const PlotSpec& ps = p.spec;
    PlotLayout L;
    L.x = (int)std::lround(ps.rect[0] * width_);
    L.y = (int)std::lround(ps.rect[1] * height_);
    L.width = (int)std::lround(ps.rect[2] * width_);
    L.height = (int)std::lround(ps.rect[3] * height_);
    L.t0 = 0;
    L.t1 = duration_;
    if (ps.auto_range) {
      double lo = 1e300, hi = -1e300;
      for (const auto& v : p.values)
        for (float x : v)
          if (std::isfinite(x)) lo = std::min(lo, (double)x), hi = std::max(hi, (double)x);
      if (!(hi >= lo)) lo = -1, hi = 1;
      if (hi - lo < 1e-12 * std::max(1.0, std::fabs(hi))) lo -= 0.5, hi += 0.5;
      const double m = 0.08 * (hi - lo);
      L.v0 = lo - m, L.v1 = hi + m;
    } else {
      L.v0 = ps.y_min, L.v1 = ps.y_max;
    }
    L.labels = ps.labels;
    for (size_t q = 0; q < ps.quantities.size(); ++q)
      L.colors.push_back(ps.colors[q]
                             ? to_display({(*ps.colors[q])[0], (*ps.colors[q])[1], (*ps.colors[q])[2], 1})
                             : to_display(okabe_ito(kPlotColors[q % 8])));
    L.title = ps.title;
    L.line_width = std::max(1.5f, 2.0f * height_ / 720.0f);
    p.plot = std::make_unique<InsetPlot>(L, *small_font_);
    p.series.clear();
    for (const auto& v : p.values) p.series.push_back(v.data());
    p.now.assign(p.values.size(), 0.0f);
    // Lines a frame can hold: the fixed ones (under 200 for a plot), every segment of every curve, the
    // cursor.
    max_lines_ += 256 + p.values.size() * (p.t.size() + 1) + 1;
  }
  (void)world;
}

// The HUD's box at the start (10% wider: its numbers change) in each corner, scored by how much of
// it the moving bodies cover over the clip: the sum over the pre-pass's samples of the overlap of
// each body's projected square (its drawn radius about its centre of mass) with the box (without a
// pre-pass, which the HUD alone does not run, the bodies' start positions are the one sample). The least
// covered corner wins; on a tie, one without the legend (whose box would stack there), then
// top_left, top_right, bottom_left, bottom_right in that order.
void SceneOverlays::choose_hud_corner(const World& world) {
  Typeface& f = *font_;
  std::string line;
  int widest = 0;
  for (const HudLine& l : hud_) {
    format_hud_line(l, world, 0, E0_, L0_, line, fps_, &meters_);
    widest = std::max(widest, f.width(line));
  }
  const int pad = f.pixel_size() / 2, lh = f.line_height(), margin = pad;
  const double bw = 1.1 * widest + 2 * pad,
               bh = (double)hud_.size() * lh + 2 * pad - (lh - f.ascent() - f.descent());
  int top = 0;
  if (title_font_) {
    const int tp = title_font_->pixel_size() / 2;
    top = tp + title_font_->ascent() + tp / 2 + title_font_->descent() + tp / 2;
  }
  const char* names[4] = {"top_left", "top_right", "bottom_left", "bottom_right"};
  double score[4] = {0, 0, 0, 0};
  const CameraView& cam = *hud_camera_;
  const size_t n = hud_bodies_.size();
  for (size_t s = 0; s + n <= hud_samples_.size(); s += n)
    for (size_t k = 0; k < n; ++k) {
      double depth = 0;
      const Eigen::Vector2d p = project_to_pixel(cam, width_, height_, hud_samples_[s + k], &depth);
      if (!(depth > 0)) continue;
      const double r = body_radius_[hud_bodies_[k]] / pixel_size_at(cam, height_, depth);
      for (int c = 0; c < 4; ++c) {
        const double x0 = c % 2 ? width_ - margin - bw : margin,
                     y0 = c < 2 ? top + margin : height_ - margin - bh;
        const double ox = std::min(x0 + bw, p.x() + r) - std::max(x0, p.x() - r);
        const double oy = std::min(y0 + bh, p.y() + r) - std::max(y0, p.y() - r);
        if (ox > 0 && oy > 0) score[c] += ox * oy;
      }
    }
  // Least covered; on a tie, a corner without the legend, then the order of `names`.
  auto key = [&](int c) { return std::make_pair(score[c], legend_.shown && legend_.corner == names[c]); };
  int best = 0;
  for (int c = 1; c < 4; ++c)
    if (key(c) < key(best)) best = c;
  hud_corner_ = names[best];
}

void SceneOverlays::fill_legend(const Scene& scene) {
  struct E {
    std::string text;
    Rgba c;
    int body;
  };
  std::vector<E> all;
  for (size_t b = 0; b < show_.size(); ++b)
    for (const ShowItem& s : show_[b]) {
      const Rgba c = item_color(s);
      auto add = [&](const std::string& t, const Rgba& col) {
        all.push_back({t, {col[0], col[1], col[2], 1}, (int)b});
      };
      switch (s.kind) {
        case ShowKind::axes:
          add("e_1", okabe_ito(6)), add("e_2", okabe_ito(3)), add("e_3", okabe_ito(5));
          break;
        case ShowKind::angular_velocity:
          add("angular velocity \\omega", c);
          break;
        case ShowKind::angular_momentum:
          add("angular momentum L", c);
          break;
        case ShowKind::velocity:
          add("velocity v", c);
          break;
        case ShowKind::momentum:
          add("momentum p = m v", c);
          break;
        case ShowKind::angular_momentum_about:
          add("angular momentum about O, L_O", c);
          break;
        case ShowKind::snapshot: {
          std::string t = "translucent: as it was at t =";
          char buf[32];
          for (size_t k = 0; k < s.at.size(); ++k) {
            std::snprintf(buf, sizeof buf, "%s %g", k ? "," : "", s.at[k]);
            t += buf;
          }
          add(t + " s", {0.75f, 0.75f, 0.78f, 1});  // each body's copy is its own colour, lightened
          break;
        }
        case ShowKind::center_of_mass:
          add("centre of mass", c);
          break;
        case ShowKind::trail:
          add("trail", c);
          break;
        case ShowKind::inertia_box:
          add("inertia box", c);
          break;
        case ShowKind::inertia_ellipsoid:
          add("inertia ellipsoid", c);
          break;
        case ShowKind::cones:
          add("body cone", okabe_ito(1)), add("space cone", okabe_ito(5));
          break;
        case ShowKind::poinsot:
          add("energy ellipsoid", okabe_ito(2)), add("polhode", okabe_ito(1)),
              add("herpolhode", okabe_ito(0));
          break;
        case ShowKind::forces: {
          bool force = false, torque = false, drag = false, spring = false;
          for (const ForceDef& f : scene.forces) {
            const bool mine = f.body == (int)b;
            force = force || (mine && f.kind == ForceKind::force);
            torque = torque || (mine && f.kind == ForceKind::torque);
            drag = drag || (mine && f.kind == ForceKind::drag);
            spring = spring || (f.kind == ForceKind::spring && (mine || f.body_b == (int)b));
          }
          if (s.arrows && (force || spring)) add("force", c);
          if (s.arrows && torque) add("torque", c);
          if (s.arrows && drag) add("drag", okabe_ito(2));
          if (s.gravity) add("weight mg", okabe_ito(0));
          if (s.springs && spring) add("spring", {0.06f, 0.06f, 0.07f, 1});
          break;
        }
        case ShowKind::contacts:
          if (s.arrows) add("contact force", c);
          if (s.points || s.normals) add("contact point, normal", okabe_ito(0));
          break;
        case ShowKind::joints: {
          // The joint holding body b (its range drawn with limits), and the ropes it hangs on.
          bool held = false, limited = false, rope = false, rod = false;
          for (const JointDef& j : scene.joints) {
            if (j.type == JointType::distance || j.type == JointType::pulley) {
              if (j.parent != (int)b && j.child != (int)b) continue;
              const bool is_rod =
                  j.type == JointType::distance && !j.min_length && !j.max_length && !j.spring;
              rod = rod || is_rod;
              rope = rope || !is_rod;
              continue;
            }
            int parent, child;
            if (!held && joint_sides(j, scene.bodies, parent, child) && child == (int)b) {
              held = true;
              limited = j.limits.has_value();
            }
          }
          if (held) add(limited ? "joint: pivot, axis, range" : "joint: pivot, axis", c);
          if (rope) add("rope", rope_color(s, false));
          if (rod) add("rod", rope_color(s, true));
          break;
        }
        case ShowKind::joint_forces:
          add("joint reaction: force, torque", c);
          break;
      }
    }
  for (const SystemLook& y : systems_)
    for (const ShowItem& s : y.spec.show) {
      const Rgba c = item_color(s);
      const std::string of = y.spec.name == "system" ? "" : " (" + y.spec.name + ")";
      const std::string t =
          s.kind == ShowKind::momentum   ? "total momentum P" + of
          : s.kind == ShowKind::velocity ? "velocity of the centre of mass" + of
          : s.kind == ShowKind::angular_momentum
              ? "total angular momentum about the centre of mass" + of
              : "centre of mass of the " + (of.empty() ? std::string("system") : y.spec.name);
      all.push_back({t, {c[0], c[1], c[2], 1}, y.spec.bodies[0]});
    }
  for (size_t k = 0; k < scene.views.variants.size(); ++k)
    if (scene.views.variants[k].overlay) {
      const Rgba c = variant_color(scene.views, k);
      all.push_back({"variant " + scene.views.variants[k].name, {c[0], c[1], c[2], 1}, 0});
    }
  // One entry per text and colour; a text drawn in several colours names each body.
  for (size_t k = 0; k < all.size(); ++k) {
    bool seen = false, several = false;
    for (size_t j = 0; j < all.size(); ++j) {
      if (all[j].text != all[k].text) continue;
      if (j < k && all[j].c == all[k].c) seen = true;
      if (all[j].c != all[k].c) several = true;
    }
    if (seen) continue;
    std::string t = all[k].text;
    if (several) t += " (" + scene.bodies[all[k].body].name + ")";
    legend_.items.push_back({t, {all[k].c[0], all[k].c[1], all[k].c[2]}});
  }
}

void SceneOverlays::build_screen(const World& w, long frame, const CameraView& cam, ScreenLayer& out) {
  const double t = w.time();
  int top = 0;  // px: what is in the top corners goes below the title
  if (!title_.empty()) {
    Typeface& f = *title_font_;
    const int tw = f.width(title_), pad = f.pixel_size() / 2;
    const int x = (width_ - tw) / 2, base = pad + f.ascent() + pad / 2;
    top = base + f.descent() + pad / 2;
    out.rects.push_back({x - pad, pad / 2, x + tw + pad, top, kPanel});
    f.draw(title_, x, base, kInk, &out);
  }
  const int margin = font_->pixel_size() / 2;
  int next_top[2] = {top + margin, top + margin};             // left, right: the next box's top
  int next_bottom[2] = {height_ - margin, height_ - margin};  // left, right: the next box's bottom
  // y of a box at x, y (w x h px) moved out of the way of the inset plots: below one (or above
  // it, `up`) that it overlaps.
  auto clear_of_plots = [&](int x, int y, int bw, int bh, bool up) {
    for (int pass = 0; pass < 2; ++pass)
      for (const Plot& p : plots_) {
        const PlotLayout& L = p.plot->layout();
        if (x < L.x + L.width && x + bw > L.x && y < L.y + L.height && y + bh > L.y)
          y = up ? L.y - margin - bh : L.y + L.height + margin;
      }
    return y;
  };
  // A box of w x h px in a corner, stacked under (over) what is there already: its top-left.
  auto place = [&](const std::string& corner, int bw, int bh) {
    const int side = corner.find("right") != std::string::npos ? 1 : 0;
    const int x = side ? width_ - margin - bw : margin;
    const bool bottom = corner.find("bottom") != std::string::npos;
    // Out of the way of the inset plots: below one in a top corner, above it in a bottom one.
    const int y = clear_of_plots(x, bottom ? next_bottom[side] - bh : next_top[side], bw, bh, bottom);
    if (bottom)
      next_bottom[side] = y - margin;
    else
      next_top[side] = y + bh + margin;
    return std::pair<int, int>{x, y};
  };

  if (!plots_.empty() && out.lines.capacity() < max_lines_)
    out.lines.reserve(max_lines_);  // once: curves grow
  for (Plot& p : plots_) {
    for (size_t q = 0; q < p.spec.quantities.size(); ++q)
      p.now[q] = (float)quantity_value(p.spec.quantities[q], w, frame, E0_, L0_, 0, &meters_);
    p.plot->draw(p.t.data(), p.series.data(), (int)p.t.size(), t, out, p.now.data());
  }

  if (!hud_.empty()) {
    Typeface& f = *font_;
    int widest = 0;
    for (size_t k = 0; k < hud_.size(); ++k) {
      format_hud_line(hud_[k], w, frame, E0_, L0_, lines_[k], fps_, &meters_);
      widest = std::max(widest, f.width(lines_[k]));
    }
    const int pad = f.pixel_size() / 2, lh = f.line_height();
    const int box_w = widest + 2 * pad,
              box_h = (int)hud_.size() * lh + 2 * pad - (lh - f.ascent() - f.descent());
    const auto [x0, y0] = place(hud_corner_, box_w, box_h);
    out.rects.push_back({x0, y0, x0 + box_w, y0 + box_h, kPanel});
    for (size_t k = 0; k < hud_.size(); ++k)
      f.draw(lines_[k], x0 + pad, y0 + pad + f.ascent() + (int)k * lh, kInk, &out);
  }

  if (legend_.shown && !legend_.items.empty()) {
    Typeface& f = *small_font_;
    const int pad = f.pixel_size() / 2, lh = f.line_height(), sw = 2 * f.pixel_size();
    int widest = 0;
    for (const LegendEntry& e : legend_.items) widest = std::max(widest, f.width(e.text));
    const int box_w = 3 * pad + sw + widest,
              box_h = (int)legend_.items.size() * lh + 2 * pad - (lh - f.ascent() - f.descent());
    const auto [x0, y0] = place(legend_.corner, box_w, box_h);
    out.rects.push_back({x0, y0, x0 + box_w, y0 + box_h, kPanel});
    for (size_t k = 0; k < legend_.items.size(); ++k) {
      const LegendEntry& e = legend_.items[k];
      const int base = y0 + pad + f.ascent() + (int)k * lh;
      const int sh = std::max(3, f.pixel_size() / 3), ym = base - (int)std::lround(0.33 * f.ascent());
      // The swatch on a light backing, so that black and dark colours show on the dark panel.
      out.rects.push_back(
          {x0 + pad - 1, ym - sh / 2 - 1, x0 + pad + sw + 1, ym - sh / 2 + sh + 1, {200, 200, 200, 255}});
      out.rects.push_back({x0 + pad, ym - sh / 2, x0 + pad + sw, ym - sh / 2 + sh,
                           to_display({e.color[0], e.color[1], e.color[2], 1})});
      f.draw(e.text, x0 + 2 * pad + sw, base, kInk, &out);
    }
  }

  // Labels: each box where its body puts it, then pushed apart where boxes overlap (a few rounds of
  // pairwise separation along the axis of least overlap, half each way, in a fixed order: the same
  // every run), then kept inside the frame below the title.
  label_boxes_.clear();
  for (size_t k = 0; k < labels_.size(); ++k) {
    const BodyLabel& l = labels_[k];
    double depth = 0;
    const Vec3 c = w.centroid(l.body);
    const Eigen::Vector2d p = project_to_pixel(cam, width_, height_, c, &depth);
    if (!(depth > 0)) continue;  // behind the camera
    Typeface& f = *font_;
    const int tw = f.width(l.text), pad = f.pixel_size() / 2;
    const double bw = tw + 2 * pad, bh = f.ascent() + f.descent() + pad;
    double cx, cy;  // the box's centre
    if (l.has_offset) {
      cx = p.x() + l.dx * height_ / 720.0, cy = p.y() - l.dy * height_ / 720.0;
    } else {
      // Just above the body's drawn outline (its radius about the centre of mass, projected).
      const double r = body_radius_[l.body] / pixel_size_at(cam, height_, depth);
      cx = p.x(), cy = p.y() - r - pad - 0.5 * bh;
    }
    label_boxes_.push_back({cx, cy, bw, bh, k});
  }
  // The panels drawn so far (title, HUD, legend, plots) stand still; labels move out of them.
  const size_t panels = out.rects.size();
  const double gap = std::max(2.0, 0.004 * height_);
  auto clamp_box = [&](LabelBox& b) {
    b.x = std::clamp(b.x, margin + 0.5 * b.w, std::max(margin + 0.5 * b.w, width_ - margin - 0.5 * b.w));
    b.y = std::clamp(b.y, top + margin + 0.5 * b.h,
                     std::max(top + margin + 0.5 * b.h, height_ - margin - 0.5 * b.h));
  };
  // Moves a and b apart, half the overlap each, along the axis where they overlap least (a, the
  // earlier label, goes up or left on a tie).
  auto separate = [&](LabelBox& a, LabelBox& b) {
    const double ox = 0.5 * (a.w + b.w) + gap - std::fabs(a.x - b.x);
    const double oy = 0.5 * (a.h + b.h) + gap - std::fabs(a.y - b.y);
    if (ox <= 0 || oy <= 0) return false;
    if (oy <= ox) {  // apart vertically: the upper one up
      const double dir = a.y <= b.y ? -1 : 1;
      a.y += dir * 0.5 * oy, b.y -= dir * 0.5 * oy;
    } else {
      const double dir = a.x <= b.x ? -1 : 1;
      a.x += dir * 0.5 * ox, b.x -= dir * 0.5 * ox;
    }
    return true;
  };
  for (auto& b : label_boxes_) clamp_box(b);
  for (int round = 0; round < 32; ++round) {
    bool moved = false;
    for (size_t i = 0; i < label_boxes_.size(); ++i) {
      for (size_t j = i + 1; j < label_boxes_.size(); ++j)
        moved = separate(label_boxes_[i], label_boxes_[j]) || moved;
      // Out of each panel by the shortest of the four moves (left, right, up, down) that leaves
      // the label inside the frame and clear of it.
      for (size_t r = 0; r < panels; ++r) {
        const ScreenRect& q = out.rects[r];
        auto& l = label_boxes_[i];
        const double hw = 0.5 * l.w + gap, hh = 0.5 * l.h + gap;
        if (!(l.x + hw > q.x0 && l.x - hw < q.x1 && l.y + hh > q.y0 && l.y - hh < q.y1)) continue;
        const double moves[4][2] = {
            {q.x0 - hw - l.x, 0}, {q.x1 + hw - l.x, 0}, {0, q.y0 - hh - l.y}, {0, q.y1 + hh - l.y}};
        double best = 1e300;
        LabelBox pick = l;
        for (const auto& m : moves) {
          LabelBox c = l;
          c.x += m[0], c.y += m[1];
          clamp_box(c);
          const bool clear = !(c.x + hw > q.x0 && c.x - hw < q.x1 && c.y + hh > q.y0 && c.y - hh < q.y1);
          const double d = std::hypot(c.x - l.x, c.y - l.y);
          if (clear && d < best) best = d, pick = c;
        }
        if (best < 1e300) l = pick, moved = true;
      }
      clamp_box(label_boxes_[i]);
    }
    if (!moved) break;
  }
  for (const auto& box : label_boxes_) {
    const BodyLabel& l = labels_[box.label];
    Typeface& f = *font_;
    const int pad = f.pixel_size() / 2, bw = (int)box.w, bh = (int)box.h;
    // Kept inside the frame, whole.
    int x0 = (int)std::lround(box.x - 0.5 * bw), y0 = (int)std::lround(box.y - 0.5 * bh);
    x0 = std::clamp(x0, margin, std::max(margin, width_ - margin - bw));
    y0 = std::clamp(y0, top + margin, std::max(top + margin, height_ - margin - bh));  // below the title
    const Rgba8 ink = l.color ? to_display({(*l.color)[0], (*l.color)[1], (*l.color)[2], 1}) : kInk;
    out.rects.push_back({x0, y0, x0 + bw, y0 + bh, kPanel});
    f.draw(l.text, x0 + pad, y0 + pad / 2 + f.ascent(), ink, &out);
  }

  for (const Caption& c : captions_) {
    if (!(t >= c.from && t < c.to)) continue;
    const double a = c.fade > 0 ? std::min({1.0, (t - c.from) / c.fade, (c.to - t) / c.fade}) : 1.0;
    if (!(a > 0)) continue;
    Typeface& f = *font_;
    const int tw = f.width(c.text), pad = f.pixel_size() / 2;
    const int bh = f.ascent() + f.descent() + pad;
    const int x = (width_ - tw) / 2;
    int y0;
    if (c.position == "top")
      y0 = clear_of_plots(x - pad, top + margin, tw + 2 * pad, bh, false);
    else if (c.position == "center")
      y0 = (height_ - bh) / 2;
    else
      y0 = clear_of_plots(x - pad, height_ - 2 * margin - bh, tw + 2 * pad, bh, true);
    out.rects.push_back({x - pad, y0, x + tw + pad, y0 + bh, faded(kPanel, a)});
    f.draw(c.text, x, y0 + pad / 2 + f.ascent(), faded(kInk, a), &out);
  }
}

}  // namespace simreel
