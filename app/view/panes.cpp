#include "app/view/panes.hpp"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <stdexcept>

#include <simreel/error.hpp>
#include "app/runner/camera_fit.hpp"
#include "render/fxaa.hpp"

namespace simreel {

namespace {

constexpr uint8_t kGutter[4] = {24, 28, 36, 255};  // the gutters and the title band, display RGB

// The scene's camera with a pane's keys over it. A pane that places its camera itself (position,
// look_at, up, follow or frame) has no part in the scene camera's path, orbit or aim; one that sets
// only fov (or nothing) moves with them (a path's fov keys over the pane's fov). A pane's follow
// keeps the scene's follow damping.
CameraSpec pane_camera(const CameraSpec& base, const PaneCamera& p) {
  CameraSpec c = base;
  c.fit = false;
  if (p.position || p.look_at || p.up || p.follow || p.frame_body) {
    c.path = CameraPath();
    c.orbit.reset();
    c.aim.clear();
  }
  if (p.position) c.position = *p.position;
  if (p.look_at) c.look_at = *p.look_at;
  if (p.up) c.up = *p.up;
  if (p.fov) c.fov = *p.fov;
  if (p.follow) {
    c.follow = *p.follow;
    if (!c.follow.empty()) c.frame_body.clear();
  }
  if (p.frame_body) {
    c.frame_body = *p.frame_body;
    if (!c.frame_body.empty()) c.follow.clear();
  }
  return c;
}

}  // namespace

std::vector<PaneRect> layout_panes(int n, int columns, int width, int height, int top) {
  const int cols = columns > 0 ? std::min(columns, n) : n, rows = (n + cols - 1) / cols;
  const int gutter = std::max(2, height / 360);
  const int pw = (width - (cols - 1) * gutter) / cols, ph = (height - top - (rows - 1) * gutter) / rows;
  if (pw < 16 || ph < 16)
    throw std::invalid_argument("a " + std::to_string(width) + "x" + std::to_string(height) +
                                " frame split into " + std::to_string(cols) + " x " + std::to_string(rows) +
                                " panes leaves panes under 16 px a side: make video.width / height larger");
  // The panes centred: what the whole pixels leave over is split between the two sides.
  const int x_pad = (width - cols * pw - (cols - 1) * gutter) / 2;
  const int y_pad = (height - top - rows * ph - (rows - 1) * gutter) / 2;
  std::vector<PaneRect> out;
  for (int i = 0; i < n; ++i) {
    const int c = i % cols, r = i / cols;
    out.push_back({x_pad + c * (pw + gutter), top + y_pad + r * (ph + gutter), pw, ph});
  }
  return out;
}

struct SceneFrames::Variant {
  Scene scene;
  std::unique_ptr<FrameLoop> loop;
  std::vector<std::function<void(const World&)>> step_hooks;
  FrameLoop::Hooks hooks;
  bool started = false;
};

struct SceneFrames::Pane {
  int world = 0;  // 0 the main world, k + 1 variant k
  Scene scene;
  PaneRect rect;
  std::unique_ptr<SceneView> view;
  std::unique_ptr<Renderer> renderer;
};

SceneFrames::SceneFrames(const Scene& scene, FrameLoop& main, const ViewOptions& o, PostStage post)
    : post_(post), main_(&main), blur_spec_(scene.motion_blur) {
  radii_ = body_radii(main.world());
  if (blur_spec_.on()) {
    blur_ = std::make_unique<BlurAccumulator>(blur_spec_.samples);
    frame_steps_ = std::max(1L, std::lround(1 / (scene.video.fps * main.world().config().dt)));
  }
  for (const VariantSpec& v : scene.views.variants) {
    auto var = std::make_unique<Variant>();
    var->scene = variant_scene(scene, v);
    for (const std::string& n : var->scene.notes) notes_.push_back(n);
    var->loop = std::make_unique<FrameLoop>(var->scene, std::max(1, o.threads));
    variants_.push_back(std::move(var));
  }
  // The overlaid variants' worlds, drawn over every view of the scene as given.
  std::vector<std::pair<const World*, Rgba>> overlaid;
  for (size_t k = 0; k < scene.views.variants.size(); ++k) {
    if (scene.views.variants[k].overlay)
      overlaid.push_back({&variants_[k]->loop->world(), variant_color(scene.views, k)});
  }
  if (!scene.views.split()) {
    view_ = std::make_unique<SceneView>(scene, main.world(), o);
    view_->overlaid = overlaid;
    notes_ = view_->meshes.notes;  // images that could not be decoded
    // With blur the renderer's images are summed first: the post stage runs on their average.
    view_->settings.post = blur_ ? PostStage::caller : post;
    renderer_ = std::make_unique<Renderer>(view_->settings, view_->meshes);
    width_ = view_->settings.width;
    height_ = view_->settings.height;
    if (blur_) frame_.resize((size_t)width_ * height_ * 4);
    return;
  }
  width_ = o.width > 0 ? o.width : scene.video.width;
  height_ = o.height > 0 ? o.height : scene.video.height;
  title_ = scene.overlays.title;
  if (!title_.empty()) {
    const int px = std::max(12, (int)std::lround(height_ * 0.032 * 1.4 * scene.overlays.text_size));
    title_font_ = std::make_unique<Font>(default_font_path(), px);
    band_ = (int)std::lround(px * 1.9);
    const int tw = title_font_->width(title_);
    const int base = (band_ + title_font_->ascent() - title_font_->descent()) / 2;
    title_font_->draw(title_, (width_ - tw) / 2, base, {255, 255, 255, 255}, &title_layer_);
  }
  const std::vector<PaneSpec>& specs = scene.views.panes;
  std::vector<PaneRect> rects;
  try {
    rects = layout_panes((int)specs.size(), scene.views.columns, width_, height_, band_);
  } catch (const std::invalid_argument& e) {
    throw InputError(scene.path + ": panes: " + e.what());
  }
  for (size_t k = 0; k < specs.size(); ++k) {
    auto pane = std::make_unique<Pane>();
    const PaneSpec& ps = specs[k];
    for (size_t v = 0; v < scene.views.variants.size(); ++v)
      if (scene.views.variants[v].name == ps.variant) pane->world = (int)v + 1;
    pane->scene = pane->world ? variants_[pane->world - 1]->scene : scene;
    pane->scene.camera = pane_camera(scene.camera, ps.camera);
    pane->scene.overlays.title = ps.title;
    for (const auto& [body, items] : ps.show) pane->scene.overlays.show[body] = items;
    pane->rect = rects[k];
    ViewOptions po = o;
    po.width = pane->rect.width;
    po.height = pane->rect.height;
    const World& w = pane->world ? variants_[pane->world - 1]->loop->world() : main.world();
    pane->view = std::make_unique<SceneView>(pane->scene, w, po);
    if (pane->world == 0) pane->view->overlaid = overlaid;
    for (const std::string& n : pane->view->meshes.notes)
      if (std::find(notes_.begin(), notes_.end(), n) == notes_.end()) notes_.push_back(n);
    // FXAA and the text run once over the whole frame (on the video writer's thread in render).
    pane->view->settings.post = PostStage::caller;
    fxaa_ = pane->view->settings.fxaa();
    pane->renderer = std::make_unique<Renderer>(pane->view->settings, pane->view->meshes);
    if (pane->world)
      if (auto h = pane->view->step_hook()) variants_[pane->world - 1]->step_hooks.push_back(h);
    panes_.push_back(std::move(pane));
  }
  for (auto& var : variants_) {
    Variant* v = var.get();
    if (!v->step_hooks.empty())
      v->hooks.step = [v](const World& w) {
        for (const auto& h : v->step_hooks) h(w);
      };
  }
  frame_.resize((size_t)width_ * height_ * 4);
  if (blur_) raw_.resize(frame_.size());
}

SceneFrames::~SceneFrames() = default;

std::function<void(const World&)> SceneFrames::step_hook() {
  if (view_) return view_->step_hook();
  std::vector<std::function<void(const World&)>> hooks;
  for (const auto& p : panes_)
    if (p->world == 0)
      if (auto h = p->view->step_hook()) hooks.push_back(h);
  if (hooks.empty()) return {};
  return [hooks](const World& w) {
    for (const auto& h : hooks) h(w);
  };
}

void SceneFrames::save_history(std::ostream& os) const {
  put(os, (uint64_t)variants_.size());
  for (const auto& v : variants_) {
    put(os, (uint8_t)v->started);
    std::ostringstream w;
    v->loop->world().save_state(w);
    put_str(os, w.str());
  }
  put(os, (uint64_t)(view_ ? 1 : panes_.size()));
  if (view_) view_->save_history(os);
  for (const auto& p : panes_) p->view->save_history(os);
}

void SceneFrames::restore_history(std::istream& is) {
  uint64_t n = 0;
  get(is, n);
  if (n != variants_.size()) throw InputError("a checkpoint's variants are not the scene's");
  for (auto& v : variants_) {
    uint8_t started = 0;
    get(is, started);
    v->started = started != 0;
    std::string bytes;
    get_str(is, bytes);
    std::istringstream w(bytes);
    v->loop->world().restore_state(w);
    v->loop->state_restored();
  }
  get(is, n);
  if (n != (view_ ? 1 : panes_.size())) throw InputError("a checkpoint's panes are not the scene's");
  if (view_) view_->restore_history(is);
  for (auto& p : panes_) p->view->restore_history(is);
}

void SceneFrames::advance_variants(const World& main) {
  for (auto& v : variants_) {
    FrameLoop& loop = *v->loop;
    if (!v->started && v->hooks.step) v->hooks.step(loop.world());  // the state it starts from
    v->started = true;
    // The step nearest the main world's simulated time on this variant's grid.
    const long step =
        std::min((long)std::llround(main.time() / loop.world().config().dt), loop.plan().total_steps);
    loop.advance_to(step, v->hooks);
  }
}

void SceneFrames::compose(const World& main, uint8_t* img, long frame) {
  advance_variants(main);
  for (size_t i = 0; i < (size_t)width_ * height_; ++i) std::memcpy(img + 4 * i, kGutter, 4);
  screen_ = title_layer_;  // (keeps its storage once grown)
  for (const auto& p : panes_) {
    const World& w = p->world ? variants_[p->world - 1]->loop->world() : main;
    const uint8_t* px = p->view->draw(*p->renderer, w, nullptr, frame);
    const PaneRect& r = p->rect;
    for (int y = 0; y < r.height; ++y)
      std::memcpy(img + ((size_t)(r.y0 + y) * width_ + r.x0) * 4, px + (size_t)y * r.width * 4,
                  (size_t)r.width * 4);
    // The pane's text, moved to where the pane sits (its panels clipped to the pane).
    for (ScreenRect q : p->view->screen().rects) {
      q.x0 = std::clamp(q.x0, 0, r.width) + r.x0, q.x1 = std::clamp(q.x1, 0, r.width) + r.x0;
      q.y0 = std::clamp(q.y0, 0, r.height) + r.y0, q.y1 = std::clamp(q.y1, 0, r.height) + r.y0;
      screen_.rects.push_back(q);
    }
    // Plots' axes and curves: moved likewise (a plot lies inside its pane).
    for (ScreenLine l : p->view->screen().lines) {
      l.x0 += (float)r.x0, l.x1 += (float)r.x0, l.y0 += (float)r.y0, l.y1 += (float)r.y0;
      screen_.lines.push_back(l);
    }
    for (ScreenGlyph g : p->view->screen().glyphs) {
      g.x += r.x0, g.y += r.y0;
      screen_.glyphs.push_back(g);
    }
  }
}

void SceneFrames::post(uint8_t* img) {
  if (post_ != PostStage::renderer) return;
  if (view_ ? view_->settings.fxaa() : fxaa_) fxaa(img, width_, height_, fxaa_buffers_);
  composite(screen(), img, width_, height_);
}

const uint8_t* SceneFrames::raw(const World& main, long frame) {
  if (view_) {
    advance_variants(main);  // (overlaid ones)
    return view_->draw(*renderer_, main, nullptr, frame);
  }
  compose(main, raw_.data(), frame);
  return raw_.data();
}

const uint8_t* SceneFrames::draw(const World& main, uint8_t* out, long frame) {
  if (!blur_ && view_) {
    advance_variants(main);  // (overlaid ones)
    return view_->draw(*renderer_, main, out, frame);
  }
  uint8_t* img = out ? out : frame_.data();
  if (!blur_) {
    compose(main, img, frame);
  } else {
    // The frame's own state takes the weight its sub-frames left (all of it without them).
    blur_->add(raw(main, frame), (size_t)width_ * height_, blur_->samples() - blur_->weight());
    blur_->finish(img);
  }
  post(img);
  return img;
}

void SceneFrames::blur_hooks(FrameLoop::Hooks& hooks, const FramePlan& plan) {
  if (!blur_) return;
  const FramePlan* pl = &plan;
  hooks.sample_steps = [this, pl](const FrameTarget& t, std::vector<long>& steps) {
    const long previous = t.index > 0 && t.index <= pl->frames ? pl->step(t.index - 1)
                          : t.index == 0                       ? t.step
                                                               : t.step - frame_steps_;
    blur_samples_ = blur_samples(blur_spec_, t.step, previous);
    for (const BlurSample& b : blur_samples_)
      if (b.step < t.step) steps.push_back(b.step);
  };
  hooks.sample = [this](const FrameTarget& t, const World& w) { blur_sample(t, w); };
}

void SceneFrames::blur_sample(const FrameTarget& t, const World& main) {
  for (const BlurSample& b : blur_samples_)
    if (b.step == main.steps()) blur_->add(raw(main, t.index), (size_t)width_ * height_, b.weight);
}

const ScreenLayer& SceneFrames::screen() const {
  return view_ ? view_->screen() : screen_;
}

bool SceneFrames::caller_fxaa() const {
  return post_ == PostStage::caller && (view_ ? view_->settings.fxaa() : fxaa_);
}

std::string SceneFrames::description() const {
  return renderer_ ? renderer_->description() : panes_.front()->renderer->description();
}

bool SceneFrames::shows_nothing(const World& main) const {
  const double aspect_full = (double)width_ / height_;
  // A moving camera (path, orbit) is checked where the last draw put it.
  auto empty_for = [&](const SceneView& v, const World& w, double aspect) {
    const CameraView& c = v.moving() ? v.drawn_camera() : v.camera;
    return !any_body_in_view(w, radii_, c.eye, c.target, c.up, c.fov_deg, aspect) ||
           body_around(w, radii_, c.eye) >= 0;
  };
  if (view_) return view_->follow < 0 && view_->ride < 0 && empty_for(*view_, main, aspect_full);
  bool any_fixed = false;
  for (const auto& p : panes_) {
    if (p->view->follow >= 0 || p->view->ride >= 0) continue;
    any_fixed = true;
    const World& w = p->world ? variants_[p->world - 1]->loop->world() : main;
    if (!empty_for(*p->view, w, (double)p->rect.width / p->rect.height)) return false;
  }
  return any_fixed;
}

std::vector<const World*> SceneFrames::worlds() const {
  std::vector<const World*> out = {&main_->world()};
  for (const auto& v : variants_) out.push_back(&v->loop->world());
  return out;
}

}  // namespace simreel
