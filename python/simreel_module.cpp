// simreel from Python: a thin layer over the C++ core (pybind11). The physics, the scene parser,
// the renderer and the encoders stay in C++; this file marshals. The Python package around it
// (python/simreel/__init__.py) adds the scene builder, which writes the scene as YAML text and hands it
// to the same parser as the command line, so a scene built in code is validated, and runs, exactly
// as the same scene written by hand.
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <atomic>
#include <cstring>
#include <memory>
#include <regex>
#include <sstream>

#include <simreel/error.hpp>
#include <simreel/world.hpp>
#include "app/runner/camera_fit.hpp"
#include "app/runner/frame_loop.hpp"
#include "app/scene/frame_plan.hpp"
#include "app/scene/scene.hpp"
#include "app/view/panes.hpp"
#include "render/video_writer.hpp"

namespace py = pybind11;

namespace simreel {
namespace {

// A scene as loaded: what build() makes simulations from.
struct PyScene {
  Scene scene;
  static PyScene from_yaml(const std::string& path) {
    PyScene s;
    s.scene = load_scene(path);
    s.ready();
    return s;
  }
  static PyScene from_string(const std::string& text, const std::string& path) {
    PyScene s;
    s.scene = load_scene_text(text, path);
    s.ready();
    return s;
  }
  // As the command line does before running: frames at k / fps exactly (prepare_run), a fitted
  // camera where the scene asks for camera.auto (one pass of the physics).
  void ready() {
    try {
      prepare_run(scene);
    } catch (const std::invalid_argument& e) {
      throw InputError(scene.path + ": " + e.what());
    }
    fit_camera(scene, 1);
  }
};

class PySim;

// A Renderer drawing a simulation's present state with the scene's camera and overlays.
class PyRenderer {
 public:
  PyRenderer(PySim& sim, int width, int height, const std::string& gl);
  ~PyRenderer() { close(); }
  std::string info() const {
    check();
    return frames_->description();
  }
  int width() const { return width_; }
  int height() const { return height_; }
  py::array_t<uint8_t> render(std::optional<py::array_t<uint8_t>> out);
  void close();
  bool closed() const { return !frames_; }
  void record(const World& w) {  // every physics step (trails, periods, a damped follow)
    if (frames_ && hook_) hook_(w);
  }

 private:
  void check() const {
    if (!frames_) throw std::runtime_error("this Renderer is closed");
  }
  PySim* sim_;
  std::unique_ptr<SceneFrames> frames_;
  std::function<void(const World&)> hook_;
  int width_ = 0, height_ = 0;
};

class PySim {
 public:
  PySim(const PyScene& s, int threads) : scene_(s.scene), loop_(scene_, threads) {
    std::ostringstream os;
    loop_.world().save_state(os);
    initial_ = os.str();
  }
  ~PySim() {
    for (PyRenderer* r : renderers_) r->close();
  }
  World& world() { return loop_.world(); }
  FrameLoop& loop() { return loop_; }
  const Scene& scene() const { return scene_; }
  const std::string& initial_state() const { return initial_; }

  void step(long n) {
    if (n < 0) throw py::value_error("step(n): n must be >= 0");
    {
      py::gil_scoped_release release;
      World& w = loop_.world();
      for (long k = 0; k < n; ++k) {
        w.step();
        for (PyRenderer* r : renderers_) r->record(w);
        steps_.store(w.steps(), std::memory_order_relaxed);
      }
    }
  }
  long steps() const { return steps_.load(std::memory_order_relaxed); }
  double time() const { return steps() * loop_.world().config().dt; }

  std::vector<std::string> body_names() const {
    std::vector<std::string> out;
    const World& w = loop_.world();
    for (int i = 0; i < w.body_count(); ++i) out.push_back(w.def(i).name);
    return out;
  }
  template <class F>
  py::array_t<double> per_body(int cols, F f) const {
    const World& w = loop_.world();
    py::array_t<double> a({(py::ssize_t)w.body_count(), (py::ssize_t)cols});
    auto m = a.mutable_unchecked<2>();
    for (int i = 0; i < w.body_count(); ++i) f(w, i, &m(i, 0));
    return a;
  }
  py::array_t<double> positions() const {
    return per_body(3, [](const World& w, int i, double* o) {
      const Vec3 p = w.origin_position(i);
      o[0] = p.x(), o[1] = p.y(), o[2] = p.z();
    });
  }
  py::array_t<double> orientations() const {
    return per_body(4, [](const World& w, int i, double* o) {
      const Quat q = w.orientation(i);
      o[0] = q.w(), o[1] = q.x(), o[2] = q.y(), o[3] = q.z();
    });
  }
  py::array_t<double> velocities() const {
    return per_body(3, [](const World& w, int i, double* o) {
      const Vec3 v = w.linear_velocity(i);
      o[0] = v.x(), o[1] = v.y(), o[2] = v.z();
    });
  }
  py::array_t<double> angular_velocities() const {
    return per_body(3, [](const World& w, int i, double* o) {
      const Vec3 v = w.angular_velocity(i);
      o[0] = v.x(), o[1] = v.y(), o[2] = v.z();
    });
  }
  py::array_t<double> centers_of_mass() const {
    return per_body(3, [](const World& w, int i, double* o) {
      const Vec3 c = w.centroid(i);
      o[0] = c.x(), o[1] = c.y(), o[2] = c.z();
    });
  }
  py::dict mass_properties(int i) const {
    const World& w = loop_.world();
    if (i < 0 || i >= w.body_count())
      throw py::index_error("body " + std::to_string(i) + " of " + std::to_string(w.body_count()));
    py::dict d;
    d["mass"] = w.mass(i);
    const Vec3& c = w.local_centroid(i);
    d["center_of_mass"] = std::vector<double>{c.x(), c.y(), c.z()};
    const Mat3 I = w.inertia_world(i);
    py::array_t<double> a({3, 3});
    auto m = a.mutable_unchecked<2>();
    for (int r = 0; r < 3; ++r)
      for (int k = 0; k < 3; ++k) m(r, k) = I(r, k);
    d["inertia_world"] = a;
    return d;
  }
  py::list contacts() const {
    std::vector<ContactData> cs;
    loop_.world().contacts(cs);
    py::list out;
    for (const ContactData& c : cs) {
      py::dict d;
      d["body_a"] = c.body_a;
      d["body_b"] = c.body_b;
      d["normal"] = std::vector<double>{c.normal_W.x(), c.normal_W.y(), c.normal_W.z()};
      py::list pts;
      for (int j = 0; j < c.count; ++j) {
        const ContactData::Point& p = c.points[j];
        py::dict q;
        q["position"] = std::vector<double>{p.p_W.x(), p.p_W.y(), p.p_W.z()};
        q["separation"] = p.separation;
        q["normal_force"] = p.normal_force;
        q["force"] = std::vector<double>{p.force_W.x(), p.force_W.y(), p.force_W.z()};
        pts.append(q);
      }
      d["points"] = pts;
      const Vec3 f = c.force_W();
      d["force"] = std::vector<double>{f.x(), f.y(), f.z()};
      out.append(d);
    }
    return out;
  }
  py::bytes state() const {
    std::ostringstream os;
    loop_.world().save_state(os);
    return py::bytes(os.str());
  }
  void set_state(const py::bytes& b) {
    std::istringstream is{std::string(b)};
    loop_.world().restore_state(is);
    loop_.state_restored();
    steps_.store(loop_.world().steps());
  }
  double energy() const { return loop_.world().kinetic_energy() + loop_.world().potential_energy(); }

  void attach(PyRenderer* r) { renderers_.push_back(r); }
  void detach(PyRenderer* r) {
    renderers_.erase(std::remove(renderers_.begin(), renderers_.end(), r), renderers_.end());
  }

 private:
  Scene scene_;
  FrameLoop loop_;
  std::string initial_;
  std::atomic<long> steps_{0};
  std::vector<PyRenderer*> renderers_;
};

PyRenderer::PyRenderer(PySim& sim, int width, int height, const std::string& gl) : sim_(&sim) {
  ViewOptions o;
  o.width = width;
  o.height = height;
  o.gl = gl;
  // The views start from the scene's initial state (the HUD's E0 and L0, trails' starts): a
  // renderer made after steps is set up on the initial state, then the present one is put back.
  World& w = sim.world();
  std::string now;
  const bool stepped = w.steps() > 0;
  if (stepped) {
    std::ostringstream os;
    w.save_state(os);
    now = os.str();
    std::istringstream is(sim.initial_state());
    w.restore_state(is);
  }
  try {
    frames_ = std::make_unique<SceneFrames>(sim.scene(), sim.loop(), o);
  } catch (const std::invalid_argument& e) {
    throw py::value_error(e.what());
  }
  if (stepped) {
    std::istringstream is(now);
    w.restore_state(is);
  }
  hook_ = frames_->step_hook();
  if (hook_) hook_(w);
  width_ = frames_->width();
  height_ = frames_->height();
  sim.attach(this);
}

void PyRenderer::close() {
  if (sim_) sim_->detach(this);
  sim_ = nullptr;
  frames_.reset();
}

py::array_t<uint8_t> PyRenderer::render(std::optional<py::array_t<uint8_t>> out) {
  check();
  py::array_t<uint8_t> img;
  if (out) {
    const py::array_t<uint8_t>& o = *out;
    if (o.ndim() != 3 || o.shape(0) != height_ || o.shape(1) != width_ || o.shape(2) != 3)
      throw py::value_error("out must be a (" + std::to_string(height_) + ", " + std::to_string(width_) +
                            ", 3) uint8 array");
    if (!(o.flags() & py::array::c_style) || !o.writeable())
      throw py::value_error("out must be a writeable C-contiguous uint8 array");
    img = o;
  } else {
    img = py::array_t<uint8_t>({(py::ssize_t)height_, (py::ssize_t)width_, (py::ssize_t)3});
  }
  const World& w = sim_->world();
  // The HUD's frame number as `render --at` gives it: the first video frame showing this step.
  const long frame = sim_->loop().video_frame_at_step(w.steps());
  const uint8_t* rgba = frames_->draw(w, nullptr, frame);
  uint8_t* dst = img.mutable_data();
  const size_t n = (size_t)width_ * height_;
  for (size_t i = 0; i < n; ++i) std::memcpy(dst + 3 * i, rgba + 4 * i, 3);
  return img;
}

// Frames from numpy to a video file, with the command line's encoders.
class PyVideoWriter {
 public:
  PyVideoWriter(const std::string& path, double fps, int crf, const std::string& encoder)
      : path_(path), fps_(fps), crf_(crf), encoder_(encoder) {
    if (!(fps > 0)) throw py::value_error("fps must be > 0");
    if (crf < 0 || crf > 51) throw py::value_error("crf must be 0 to 51");
  }
  void write(const py::array_t<uint8_t, py::array::c_style | py::array::forcecast>& img) {
    if (closed_) throw std::runtime_error("this VideoWriter is closed");
    if (img.ndim() != 3 || (img.shape(2) != 3 && img.shape(2) != 4))
      throw py::value_error("write() takes an (H, W, 3) or (H, W, 4) uint8 array");
    const int h = (int)img.shape(0), w = (int)img.shape(1), c = (int)img.shape(2);
    if (!writer_) {
      if (w % 2 || h % 2)
        throw py::value_error("video frames need even sizes (yuv420p): got " + std::to_string(w) + "x" +
                              std::to_string(h));
      VideoSettings s;
      s.path = path_;
      s.width = w;
      s.height = h;
      s.fps = fps_;
      s.crf = crf_;
      s.encoder = encoder_;
      writer_ = std::make_unique<VideoWriter>(s);
      width_ = w, height_ = h;
    } else if (w != width_ || h != height_) {
      throw py::value_error("frame of " + std::to_string(w) + "x" + std::to_string(h) + " in a video of " +
                            std::to_string(width_) + "x" + std::to_string(height_));
    }
    const uint8_t* src = img.data();  // `img` holds the array for the call
    const size_t n = (size_t)w * h;
    py::gil_scoped_release release;  // the queue may be full: wait for the encoder without the GIL
    uint8_t* dst = writer_->acquire();
    if (c == 4) {
      std::memcpy(dst, src, n * 4);
    } else {
      for (size_t i = 0; i < n; ++i) {
        std::memcpy(dst + 4 * i, src + 3 * i, 3);
        dst[4 * i + 3] = 255;
      }
    }
    writer_->commit();
  }
  long frames() const { return writer_ ? writer_->frames() : 0; }
  // A playable video of the frames written, however the `with` block ended; nothing without frames.
  void close() {
    if (closed_) return;
    closed_ = true;
    if (writer_ && writer_->frames() > 0) {
      py::gil_scoped_release release;
      writer_->finish();
    }
    writer_.reset();
  }

 private:
  std::string path_;
  double fps_;
  int crf_;
  std::string encoder_;
  std::unique_ptr<VideoWriter> writer_;
  int width_ = 0, height_ = 0;
  bool closed_ = false;
};

}  // namespace
}  // namespace simreel

PYBIND11_MODULE(_simreel, m) {
  using namespace simreel;
  m.doc() = "simreel's C++ core (the package simreel wraps it)";
  static py::exception<InputError> input_error(m, "InputError", PyExc_ValueError);
  static py::exception<StateError> state_error(m, "StateError", PyExc_RuntimeError);
  py::register_exception_translator([](std::exception_ptr p) {
    try {
      if (p) std::rethrow_exception(p);
    } catch (const InputError& e) {
      // "FILE:LINE:COL: KEY: what" (scenes), "FILE: what" (files): the parts as attributes.
      const std::string msg = e.what();
      py::object err = py::reinterpret_borrow<py::object>(input_error.ptr())(msg);  // an instance
      py::object none = py::none();
      err.attr("file") = none, err.attr("line") = none, err.attr("column") = none, err.attr("key") = none;
      std::smatch mm;
      static const std::regex full(R"(^(.*?):(\d+):(\d+): ([^:]+): )");
      static const std::regex file_only(R"(^([^:]+): )");
      if (std::regex_search(msg, mm, full)) {
        err.attr("file") = mm[1].str();
        err.attr("line") = std::stoi(mm[2].str());
        err.attr("column") = std::stoi(mm[3].str());
        err.attr("key") = mm[4].str();
      } else if (std::regex_search(msg, mm, file_only)) {
        err.attr("file") = mm[1].str();
      }
      PyErr_SetObject(input_error.ptr(), err.ptr());
    } catch (const StateError& e) {
      PyErr_SetString(state_error.ptr(), e.what());
    }
  });

  py::class_<PyScene>(m, "_Scene")
      .def_static("from_yaml", &PyScene::from_yaml, py::arg("path"))
      .def_static("from_string", &PyScene::from_string, py::arg("text"), py::arg("path"))
      .def_property_readonly("name", [](const PyScene& s) { return s.scene.name; })
      .def_property_readonly("duration", [](const PyScene& s) { return s.scene.duration; })
      .def_property_readonly("timestep", [](const PyScene& s) { return s.scene.timestep; })
      .def_property_readonly("fps", [](const PyScene& s) { return s.scene.video.fps; })
      .def_property_readonly("notes", [](const PyScene& s) { return s.scene.notes; })
      .def_property_readonly("warnings", [](const PyScene& s) { return s.scene.warnings; });

  py::class_<PySim>(m, "Simulation")
      .def(py::init<const PyScene&, int>(), py::arg("scene"), py::arg("threads") = 1)
      .def("step", &PySim::step, py::arg("n") = 1, "n physics steps (the GIL released meanwhile)")
      .def_property_readonly("time", &PySim::time, "s, simulated")
      .def_property_readonly("steps", &PySim::steps)
      .def_property_readonly(
          "timestep", [](PySim& s) { return s.world().config().dt; }, "s")
      .def_property_readonly("body_names", &PySim::body_names)
      .def_property_readonly("positions", &PySim::positions, "(N, 3) m, body origins, world")
      .def_property_readonly("orientations", &PySim::orientations, "(N, 4) body-to-world quaternions w x y z")
      .def_property_readonly("velocities", &PySim::velocities, "(N, 3) m/s, of the centres of mass, world")
      .def_property_readonly("angular_velocities", &PySim::angular_velocities, "(N, 3) rad/s, world")
      .def_property_readonly("centers_of_mass", &PySim::centers_of_mass, "(N, 3) m, world")
      .def_property_readonly("energy", &PySim::energy, "J, kinetic + potential")
      .def("mass_properties", &PySim::mass_properties, py::arg("body"))
      .def("contacts", &PySim::contacts)
      .def("state", &PySim::state, "the whole state, in --save-state's format")
      .def("set_state", &PySim::set_state, py::arg("state"));

  py::class_<PyRenderer>(m, "Renderer")
      .def(py::init<PySim&, int, int, const std::string&>(), py::arg("sim"), py::arg("width") = 0,
           py::arg("height") = 0, py::arg("gl") = "", py::keep_alive<1, 2>())
      .def_property_readonly("info", &PyRenderer::info)
      .def_property_readonly("width", &PyRenderer::width)
      .def_property_readonly("height", &PyRenderer::height)
      .def_property_readonly("closed", &PyRenderer::closed)
      .def("render", &PyRenderer::render, py::arg("out") = py::none())
      .def("close", &PyRenderer::close)
      .def(
          "__enter__", [](PyRenderer& r) -> PyRenderer& { return r; }, py::return_value_policy::reference)
      .def("__exit__", [](PyRenderer& r, py::args) { r.close(); });

  py::class_<PyVideoWriter>(m, "VideoWriter")
      .def(py::init<const std::string&, double, int, const std::string&>(), py::arg("path"),
           py::arg("fps") = 30, py::arg("crf") = 20, py::arg("encoder") = "")
      .def("write", &PyVideoWriter::write, py::arg("image"))
      .def_property_readonly("frames", &PyVideoWriter::frames)
      .def("close", &PyVideoWriter::close)
      .def(
          "__enter__", [](PyVideoWriter& v) -> PyVideoWriter& { return v; },
          py::return_value_policy::reference)
      .def("__exit__", [](PyVideoWriter& v, py::args) { v.close(); });
}
