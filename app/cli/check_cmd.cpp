// simreel check: scenes against committed goldens, physics first, then pixels.
#include <unistd.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <set>
#include <sstream>

#include <simreel/error.hpp>
#include "app/cli/cli.hpp"
#include "app/cli/commands.hpp"
#include "app/cli/fingerprint.hpp"
#include "app/cli/goldens.hpp"
#include "app/cli/junit.hpp"
#include "app/cli/metrics_report.hpp"
#include "app/regress/image.hpp"
#include "app/regress/metrics.hpp"
#include "app/report/report.hpp"
#include "app/runner/camera_fit.hpp"
#include "app/runner/frame_loop.hpp"
#include "app/scene/text.hpp"
#include "app/view/panes.hpp"
#include "sim/base/enum_names.hpp"

namespace simreel {

namespace {

enum class Update { missing, changed, all, none };
constexpr EnumNames<Update, 4> kUpdates{{"missing", "changed", "all", "none"}};
static_assert(kUpdates.complete());

enum class Tolerance { automatic, exact, portable };
constexpr EnumNames<Tolerance, 3> kTolerances{{"auto", "exact", "portable"}};
static_assert(kTolerances.complete());

struct Checked {
  FrameTarget target;
  Image image;
  std::vector<BodyState> bodies;
};

std::vector<uint8_t> slurp(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return std::vector<uint8_t>((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
}

// The command line that reproduces this run with another --update (for the report).
std::string command_line(const std::vector<std::string>& args, const std::string& update) {
  // As the user ran it (build/simreel when not on the PATH), so the printed command can be pasted.
  const bool plain_prog = g_invoked_as.find_first_of(" \t\"'$\\*?;&|<>()") == std::string::npos;
  std::string out = (plain_prog ? g_invoked_as : "'" + g_invoked_as + "'") + " check";
  bool skip = false;
  for (const std::string& a : args) {
    if (skip) {
      skip = false;
      continue;
    }
    if (a == "--update") {
      skip = true;
      continue;
    }
    if (a.rfind("--update=", 0) == 0) continue;
    const bool plain = a.find_first_of(" \t\"'$\\*?;&|<>()") == std::string::npos && !a.empty();
    out += " " + (plain ? a : "'" + a + "'");
  }
  if (!update.empty()) out += " --update " + update;
  return out;
}

// Writes bytes through a temp file beside the target, so a golden is whole or absent.
void write_atomic(const std::string& path, const std::vector<uint8_t>& bytes) {
  AtomicFile f(path);
  if (std::fwrite(bytes.data(), 1, bytes.size(), f.get()) != bytes.size())
    throw std::runtime_error(path + ": could not write");
  f.commit();
}

struct SceneOutcome {
  int passed = 0, failed = 0, missing = 0, written = 0;
};

struct CheckOptions {
  std::vector<std::string> scenes;
  std::optional<std::string> goldens, update, frames, tolerance, report, junit, gl, golden_names;
  bool quiet = false;
};

// Whether the environment says CI: the variable set to anything but "", 0, false, no or off (in
// any case): CI=false on a developer's machine is not CI.
bool ci_env() {
  const char* v = std::getenv("CI");
  if (!v) return false;
  std::string s = v;
  for (char& c : s) c = (char)std::tolower((unsigned char)c);
  return !(s.empty() || s == "0" || s == "false" || s == "no" || s == "off");
}

// check's option table.
void check_table(CLI::App& app, CheckOptions& o) {
  cli::setup(app, "check",
             "Runs each scene and compares chosen frames with goldens in DIR/<scene>/ (PNGs and "
             "manifest.json): first the physics (every body's pose and velocity, relative tolerance 1e-9: "
             "\"physics changed\"), then the pixels (\"rendering changed\"). Only the checked frames are "
             "drawn; the physics runs through the rest.",
             "Frame size: the scene's test.width x test.height (default 480x270, small goldens).\n"
             "Exit codes: 0 all pass (or accepted by --update), 1 a difference, 2 bad input or a golden "
             "missing without --update.");
  cli::add_positionals(app, o.scenes);
  app.add_option("--goldens", o.goldens, "the golden folder (required)")->type_name("DIR");
  app.add_option(
         "--update", o.update,
         "missing: write goldens that do not exist yet (the default on a terminal); changed: rewrite "
         "those that fail; all: rewrite every checked frame; none: write nothing (the default when CI "
         "is set or output is not a terminal)")
      ->check(cli::choice({"missing", "changed", "all", "none"}));
  add_package_path(app);
  app.add_option("--frames", o.frames,
                 "the moments to check, overriding the scene's test.frames (default \"0%, 25%, 50%, 75%, "
                 "100%\": by time, so a new fps keeps the goldens valid): frame numbers N, ranges A:B, times "
                 "Ts, shares P%")
      ->type_name("SPEC");
  app.add_option("--tolerance", o.tolerance,
                 "auto (default): exact pixels when the renderer fingerprint matches the golden's, else "
                 "portable; exact: the decoded pixels must be identical; portable: a perceptual comparison "
                 "that ignores anti-aliasing and noise but fails on many differing pixels or one cluster of "
                 "them")
      ->check(cli::choice({"auto", "exact", "portable"}));
  app.add_option("--report", o.report,
                 "write DIR/index.html: one self-contained page to review the differences")
      ->type_name("DIR");
  app.add_option("--junit", o.junit, "write JUnit XML (one test case per scene and frame) for CI systems")
      ->type_name("FILE");
  app.add_option("--gl", o.gl, "OpenGL context: osmesa or egl")->check(cli::choice({"osmesa", "egl"}));
  app.add_option("--golden-names", o.golden_names,
                 "stem (default): a scene's goldens are in DIR/<file name without extension>; path: in "
                 "DIR/<its path from the current folder without extension>, so that two scenes with one "
                 "file name in different folders can be checked together")
      ->check(cli::choice({"stem", "path"}));
  app.add_flag("--quiet", o.quiet, "print only failures and the summary");
}

}  // namespace

int cmd_check(const std::vector<std::string>& args) {
  CheckOptions o;
  CLI::App app;
  check_table(app, o);
  if (!cli::parse(app, args)) return kExitOk;
  if (o.scenes.empty()) throw UsageError("check takes one or more scene files");
  if (!o.goldens) throw UsageError("check needs --goldens DIR");
  const std::string goldens = *o.goldens;
  // Why nothing is written without --update: said when goldens are missing.
  const char* no_update_reason = ci_env()     ? "CI is set"
                                 : !isatty(1) ? "the output is not a terminal"
                                              : nullptr;
  Update update = no_update_reason ? Update::none : Update::missing;
  if (o.update) update = kUpdates.parse(*o.update).value_or(Update::none);  // names checked by the table
  if (o.update) no_update_reason = nullptr;
  {
    // A wrong --goldens path must not read as every golden missing.
    std::error_code ec;
    if (std::filesystem::exists(goldens, ec) && !std::filesystem::is_directory(goldens, ec))
      throw UsageError("--goldens '" + goldens + "' is not a folder");
    if (!std::filesystem::exists(goldens, ec) && update == Update::none)
      throw InputError(
          "--goldens '" + goldens + "': no such folder (a first run writes it: --update missing" +
          std::string(no_update_reason
                          ? std::string(", which is not the default here since ") + no_update_reason
                          : "") +
          ")");
  }
  Tolerance tolerance = Tolerance::automatic;
  if (o.tolerance) tolerance = kTolerances.parse(*o.tolerance).value_or(Tolerance::automatic);
  ViewOptions vo;
  if (o.gl) {
    vo.gl = *o.gl;
    if (!gl_backend_built(*gl_backend_from_name(vo.gl)))
      throw UsageError("this simreel was built without the " + vo.gl + " backend");
  }
  const bool quiet = o.quiet;
  // Outputs are checked before anything runs.
  std::string err;
  if (o.junit && !ensure_parent_dir(*o.junit, &err)) throw std::runtime_error(err);

  ReportInput report;
  report.title = "simreel check";
  report.command = command_line(args, "");
  report.accept_command = command_line(args, "changed");
  std::vector<JunitCase> junit;
  int bad_input = 0, differ = 0, missing = 0, frames_total = 0, passed_total = 0, written_total = 0;
  std::set<std::string> names;
  // A scene that cannot be checked: said on stderr, and an error in the JUnit file and the report
  // (a CI reporter shows it beside the frames that were checked).
  auto scene_error = [&](const std::string& path, const std::string& message) {
    std::fprintf(stderr, "error: %s\n", message.c_str());
    junit.push_back({path, "scene", 0, "error", message, "bad input"});
    ReportFrame rf;
    rf.scene = path;
    rf.frame = -1;
    rf.status = "error";
    rf.messages.push_back("could not be checked: " + message);
    report.frames.push_back(std::move(rf));
    ++bad_input;
  };

  for (const std::string& path : o.scenes) {
    Scene scene;
    try {
      scene = load_scene(path);
      prepare_run(scene);
    } catch (const std::invalid_argument& e) {
      scene_error(path, path + ": " + e.what());
      continue;
    } catch (const InputError& e) {
      scene_error(path, e.what());
      continue;
    }
    // The golden folder's name: the file's stem, or with --golden-names path its path from here.
    std::string golden_name = scene.name;
    if (o.golden_names && *o.golden_names == "path") {
      std::error_code ec;
      std::filesystem::path rel = std::filesystem::relative(path, std::filesystem::current_path(), ec);
      if (ec || rel.empty() || *rel.begin() == "..") {
        scene_error(path, path +
                              ": --golden-names path names goldens by the scene's path from the current "
                              "folder, and this scene is outside it: run check from a folder above it");
        continue;
      }
      golden_name = rel.replace_extension().generic_string();
    }
    if (!names.insert(golden_name).second) {
      scene_error(
          path, path + ": another scene named '" + golden_name + "' uses the same golden folder " + goldens +
                    "/" + golden_name +
                    (o.golden_names ? "" : " (--golden-names path names them by their paths instead)"));
      continue;
    }
    fit_camera(scene, 1);  // camera: { auto: true }
    const std::string spec = o.frames ? *o.frames : scene.test.frames;
    FrameLoop loop(scene, 1);
    FrameTargets targets;
    try {
      targets = parse_frame_spec(spec, loop.plan(), scene.video.fps, scene.timestep, scene.duration);
    } catch (const std::invalid_argument& e) {
      scene_error(path, path + ": --frames / test.frames: " + e.what());
      continue;
    }
    const std::string dir = (std::filesystem::path(goldens) / golden_name).string();
    const std::string manifest_path = (std::filesystem::path(dir) / "manifest.json").string();
    Manifest manifest;
    bool have_manifest = std::filesystem::exists(manifest_path);
    if (have_manifest) {
      try {
        manifest = read_manifest(manifest_path);
      } catch (const InputError& e) {
        scene_error(path, e.what());
        continue;
      }
    }
    manifest.scene = scene.name;
    // What the bodies weigh: a changed mass or inertia is physics, from frame 0 on (where the
    // bodies have not moved yet and only the pixels would otherwise differ).
    const std::vector<BodyMass> masses = body_masses(loop.world());
    const std::vector<std::string> mass_changes =
        have_manifest ? compare_masses(manifest.masses, masses) : std::vector<std::string>{};

    // Run: the physics through every step, a frame drawn only at the checked moments.
    vo.width = scene.test.width;
    vo.height = scene.test.height;
    // One view or panes (app/view/panes.hpp); FXAA in the renderer: the frame `render` writes.
    SceneFrames view(scene, loop, vo);
    const Fingerprint fp = fingerprint(view.description());
    std::vector<Checked> got;
    double render_s = 0;
    FrameLoop::Hooks hooks;
    hooks.step = view.step_hook();  // trails: every physics step, drawn or not
    // render.motion_blur: the checked moments are frames of the simulation plan
    view.blur_hooks(hooks, loop.plan());
    hooks.frame = [&](const FrameTarget& t, const World& w) {
      const auto t0 = std::chrono::steady_clock::now();
      // Checked moments are simulated times (scenes/README.md, `test`); the HUD's frame is the
      // first video frame that shows the step (with a `time:` block it is not t * fps).
      const long frame = scene.time.identity() ? t.index : loop.video_frame_at_step(t.step);
      const uint8_t* px = view.draw(w, nullptr, frame);
      Checked c{t, Image{}, {}};
      const std::vector<const World*> worlds = view.worlds();
      // The variants' bodies after the scene's, as "VARIANT/BODY".
      for (size_t k = 0; k < worlds.size(); ++k) {
        std::vector<BodyState> b = body_states(*worlds[k]);
        if (k > 0)
          for (BodyState& bs : b) bs.name = scene.views.variants[k - 1].name + "/" + bs.name;
        c.bodies.insert(c.bodies.end(), b.begin(), b.end());
      }
      c.image.width = view.width();
      c.image.height = view.height();
      c.image.rgba.assign(px, px + (size_t)c.image.width * c.image.height * 4);
      got.push_back(std::move(c));
      render_s += std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    };
    loop.run(targets, hooks, false);

    const std::string scene_hash = file_hash(path);
    if (have_manifest && !manifest.scene_hash.empty() && manifest.scene_hash != scene_hash && !quiet)
      std::fprintf(stderr, "note: %s changed since its goldens were written\n", path.c_str());
    // The files it read: a mesh scaled by 2% changes physics and pixels, and the note says which.
    std::map<std::string, std::string> inputs;
    for (const std::string& f : scene.inputs) {
      std::error_code ec;
      std::string rel =
          std::filesystem::relative(f, std::filesystem::path(path).parent_path(), ec).generic_string();
      if (ec || rel.empty()) rel = f;
      inputs[rel] = file_hash(f);
    }
    std::string changed_inputs;  // ", "-joined: what a frame whose physics held but pixels moved blames
    if (have_manifest)
      for (const auto& [f, h] : inputs)
        if (const auto it = manifest.inputs.find(f); it != manifest.inputs.end() && it->second != h)
          changed_inputs += (changed_inputs.empty() ? "" : ", ") + f;
    if (have_manifest && !manifest.inputs.empty() && !quiet) {
      for (const auto& [f, h] : inputs) {
        const auto it = manifest.inputs.find(f);
        if (it == manifest.inputs.end())
          std::fprintf(stderr, "note: %s: %s is read now but was not when its goldens were written\n",
                       path.c_str(), f.c_str());
        else if (it->second != h)
          std::fprintf(stderr, "note: %s: %s changed since its goldens were written\n", path.c_str(),
                       f.c_str());
      }
      for (const auto& [f, h] : manifest.inputs)
        if (!inputs.count(f))
          std::fprintf(stderr, "note: %s: %s was read when its goldens were written and is not now\n",
                       path.c_str(), f.c_str());
    }
    bool manifest_dirty = false;
    SceneOutcome so;
    for (Checked& c : got) {
      ReportFrame rf;
      rf.scene = scene.name;
      rf.frame = (int)c.target.index;
      rf.time = c.target.time;
      // Named as its golden is (a moment of simulated time), not by plan frame: "t=1.25s".
      rf.label = golden_file_name(c.target.time).substr(1);
      rf.label = "t=" + rf.label.substr(0, rf.label.size() - 4);
      rf.width = c.image.width;
      rf.height = c.image.height;
      const std::string file = golden_file_name(c.target.time);
      const std::string png_path = (std::filesystem::path(dir) / file).string();
      const GoldenFrame* g = manifest.find(c.target.time);
      Image golden;
      bool golden_ok = g != nullptr;
      if (g) {
        try {
          golden = read_png((std::filesystem::path(dir) / g->file).string());
        } catch (const InputError& e) {
          rf.messages.push_back(std::string("the golden image cannot be read: ") + e.what());
          golden_ok = false;
        }
      }
      bool pass = false;
      if (golden_ok) {
        // Physics first: a changed trajectory explains any changed picture.
        std::vector<std::string> physics = mass_changes;
        for (const std::string& m : compare_states(g->bodies, c.bodies)) physics.push_back(m);
        for (const std::string& m : physics) rf.messages.push_back("physics changed: " + m);
        if (g->step != c.target.step)
          rf.messages.push_back("physics changed: the frame is taken at step " +
                                std::to_string(c.target.step) + " (golden: step " + std::to_string(g->step) +
                                "; a new timestep?)");
        // Then pixels: exact when the same renderer drew both, else perceptual.
        const bool same_renderer = same_pixels_expected(g->fingerprint, fp);
        const bool exact =
            tolerance == Tolerance::exact || (tolerance == Tolerance::automatic && same_renderer);
        // Portable: the measured defaults when the same rasterizer drew both (llvmpipe's thread
        // count, vector width and the GL backend measured byte-identical); across renderer or
        // Mesa versions the looser cross-renderer tolerance (app/regress/metrics.hpp: softpipe
        // against llvmpipe moved clusters of up to 55 px at 480x270).
        const bool same_gl = same_rasterizer(g->fingerprint, fp);
        const CompareOptions portable = same_gl ? CompareOptions{} : CompareOptions::cross_renderer();
        Image diff;
        const CompareResult r = compare_images(golden, c.image, portable, &diff);
        bool pixels_ok;
        if (!r.same_size) {
          pixels_ok = false;
          rf.kind = "size";
          rf.messages.push_back("size changed: " + r.reason);
        } else if (exact) {
          // The golden PNG is the reference; the manifest's hash records it (a mismatch means
          // the PNG was replaced by hand or by another version of simreel: said, not failed).
          pixels_ok = identical(golden, c.image);
          if (pixel_hash(golden) != g->pixel_hash)
            rf.messages.push_back("note: " + g->file + " does not match the pixel hash in its manifest");
          if (!pixels_ok) {
            const long changed = compare_images(golden, c.image, CompareOptions::exact()).differing;
            rf.messages.push_back("rendering changed (exact): " + std::to_string(changed) +
                                  " pixels changed (" + std::to_string(r.differing + r.antialiased) +
                                  " beyond the portable colour threshold), largest channel change " +
                                  std::to_string((int)r.max_channel_delta) + " levels");
          }
        } else {
          pixels_ok = r.pass;
          if (!pixels_ok)
            rf.messages.push_back(std::string("rendering changed (portable") +
                                  (same_gl ? "" : ", across renderers") + "): " + r.reason);
        }
        if (!physics.empty() || g->step != c.target.step) {
          rf.kind = "physics";
        } else if (!pixels_ok && rf.kind.empty() && !changed_inputs.empty()) {
          // The bodies are where they were, but what they are drawn from is not (frame 0 of a
          // rescaled mesh): the input, not the renderer.
          rf.kind = "input";
          rf.messages.insert(rf.messages.begin(),
                             "input changed: " + changed_inputs +
                                 " (since the goldens were written; the bodies are where "
                                 "they were)");
        } else if (!pixels_ok && rf.kind.empty()) {
          rf.kind = "rendering";
        }
        pass = physics.empty() && g->step == c.target.step && pixels_ok;
        put_metrics(r, rf);
        if (report.golden_fingerprint.empty() || !pass) report.golden_fingerprint = g->fingerprint;
        if (o.report) {
          rf.expected_png = slurp((std::filesystem::path(dir) / g->file).string());
          if (!pass && r.same_size) rf.diff_png = encode_png(diff);
        }
        rf.status = pass ? "pass" : "fail";
      } else {
        rf.status = "missing";
        rf.messages.push_back("no golden for t = " + std::to_string(c.target.time) + " s in " + dir);
      }
      // Write goldens as --update says.
      const bool write =
          (!golden_ok && (update == Update::missing || update == Update::changed || update == Update::all)) ||
          (golden_ok && !pass && (update == Update::changed || update == Update::all)) ||
          (golden_ok && pass && update == Update::all);
      if (write) {
        std::error_code ec;
        std::filesystem::create_directories(dir, ec);
        if (ec) throw std::runtime_error("cannot create the golden folder '" + dir + "': " + ec.message());
        write_atomic(png_path, encode_png(c.image));
        GoldenFrame nf{c.target.time, c.target.step,  file, pixel_hash(c.image),
                       c.image.width, c.image.height, fp,   c.bodies};
        bool replaced = false;
        for (GoldenFrame& old : manifest.frames)
          if (std::fabs(old.time - nf.time) <= 1e-9) old = nf, replaced = true;
        if (!replaced) manifest.frames.push_back(nf);
        manifest_dirty = true;
        rf.status = golden_ok ? "updated" : "new";
        if (!golden_ok)
          rf.messages = {"golden written: " + png_path};
        else
          rf.messages.push_back("golden rewritten (--update): " + png_path);
        ++so.written;
      }
      if (rf.status == "pass" || rf.status == "new" || rf.status == "updated")
        ++so.passed;
      else if (rf.status == "fail")
        ++so.failed;
      else
        ++so.missing;
      if (o.report) rf.actual_png = encode_png(c.image);
      report.actual_fingerprint = fp;

      char t[32];
      std::snprintf(t, sizeof t, "t=%gs", c.target.time);
      const std::string what = rf.status == "pass"      ? "PASS"
                               : rf.status == "new"     ? "NEW "
                               : rf.status == "updated" ? "UPD "
                               : rf.status == "fail"    ? "FAIL"
                                                        : "MISS";
      if (!quiet || rf.status == "fail" || rf.status == "missing") {
        std::string metrics;
        if (!std::isnan(rf.diff_ratio)) {
          char m[160];
          std::snprintf(m, sizeof m, "  [%ld px differ, largest cluster %d, PSNR %s dB, SSIM %.6f]",
                        rf.differing, rf.largest_cluster,
                        std::isinf(rf.psnr) ? "inf" : std::to_string(rf.psnr).c_str(), rf.ssim);
          metrics = m;
        }
        std::printf("%s %s %s%s%s\n", what.c_str(), scene.name.c_str(), t,
                    rf.status == "fail" ? (" (" + rf.kind + " changed)").c_str() : "", metrics.c_str());
        for (const std::string& m : rf.messages) std::printf("     %s\n", m.c_str());
      }
      junit.push_back({scene.name, t, render_s / std::max<size_t>(1, got.size()),
                       rf.status == "fail"      ? "failure"
                       : rf.status == "missing" ? "error"
                                                : "",
                       [&] {
                         std::string m;
                         for (const std::string& s : rf.messages) m += s + "\n";
                         return m;
                       }(),
                       ""});
      report.frames.push_back(std::move(rf));
    }
    // --update changed or all also records what the scene reads now, when that is all that changed.
    if ((update == Update::changed || update == Update::all) && have_manifest &&
        (manifest.inputs != inputs || manifest.masses.empty() || !mass_changes.empty()))
      manifest_dirty = true;
    if (manifest_dirty) {
      if (update == Update::all) {  // exactly the frames checked now: drop those no longer asked for
        std::vector<GoldenFrame> keep;
        for (const GoldenFrame& f : manifest.frames) {
          bool asked = false;
          for (const Checked& c : got) asked |= std::fabs(c.target.time - f.time) <= 1e-9;
          if (asked)
            keep.push_back(f);
          else
            std::filesystem::remove(std::filesystem::path(dir) / f.file);
        }
        manifest.frames = keep;
      }
      std::sort(manifest.frames.begin(), manifest.frames.end(),
                [](const GoldenFrame& x, const GoldenFrame& y) { return x.time < y.time; });
      manifest.simreel_version = kVersion;
      manifest.scene_hash = scene_hash;
      manifest.inputs = inputs;
      manifest.masses = masses;
      write_manifest(manifest_path, manifest);
    }
    if (!quiet)
      std::printf("%s: %zu frames checked, %d written; physics %.3f s, drawing %.3f s\n", scene.name.c_str(),
                  got.size(), so.written, loop.step_seconds(), render_s);
    frames_total += (int)got.size();
    passed_total += so.passed;
    written_total += so.written;
    differ += so.failed;
    missing += so.missing;
  }

  std::ostringstream summary;
  int physics = 0, rendering = 0, input = 0, size = 0;
  for (const ReportFrame& f : report.frames)
    if (f.status == "fail")
      (f.kind == "physics" ? physics : f.kind == "input" ? input : f.kind == "size" ? size : rendering)++;
  summary << differ << " of " << frames_total << " frames differ (" << physics << " physics, ";
  if (input) summary << input << " input, ";
  if (size) summary << size << " of another size, ";
  summary << rendering << " rendering)";
  if (missing)
    summary << ", " << missing << " without a golden (--update missing writes them"
            << (no_update_reason ? std::string("; nothing was written since ") + no_update_reason +
                                       ", where --update defaults to none"
                                 : std::string())
            << ")";
  if (written_total) summary << ", " << written_total << " goldens written";
  if (bad_input)
    summary << ", " << bad_input << (bad_input == 1 ? " scene" : " scenes") << " could not be checked";
  report.summary = summary.str();
  std::printf("%s\n", report.summary.c_str());
  if (differ) std::printf("to accept the changes: %s\n", report.accept_command.c_str());
  if (o.report) {
    const std::string page = write_report(*o.report, report);
    std::printf("report: %s\n", page.c_str());
  }
  if (o.junit) write_junit(*o.junit, "simreel check", junit);
  if (bad_input || missing) return kExitBadInput;
  return differ ? kExitFailure : kExitOk;
}

}  // namespace simreel
