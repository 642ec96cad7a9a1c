// The simreel command line as scripts see it: exit codes, outputs, and no file left by bad input.
#include <fcntl.h>
#include <gtest/gtest.h>
#include <signal.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cctype>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <set>
#include <sstream>
#include <thread>

#include <nlohmann/json.hpp>

#include "tests/cli_run.hpp"
#include "tests/render/decode.hpp"
#include "tests/scratch.hpp"

namespace {

namespace fs = std::filesystem;
using simreel::test::Result;
using simreel::test::run;
using simreel::test::slurp;

// The JSON object a command printed (other lines, such as notes on stderr, around it).
nlohmann::json json_of(const std::string& out) {
  const size_t a = out.find('{'), b = out.rfind('}');
  if (a == std::string::npos || b == std::string::npos) return nullptr;
  return nlohmann::json::parse(out.substr(a, b - a + 1), nullptr, false);
}

fs::path tmp(const std::string& name) {
  return simreel::test::scratch(name);
}

std::string write(const std::string& name, const std::string& text) {
  const fs::path p = tmp(name);
  std::ofstream(p) << text;
  return p.string();
}

const char* kGood =
    "simulation: { duration: 1.0, timestep: 0.01, gravity: [0, 0, -9.81] }\n"
    "video: { width: 64, height: 48, fps: 10 }\n"
    "bodies:\n"
    "  - name: a\n    angular_velocity: [0.1, 3, 0.1]\n"
    "    colliders: [ { shape: box, size: [3, 2, 1], mass: 6 } ]\n"
    "  - name: b\n    position: [5, 0, 0]\n"
    "    colliders: [ { shape: sphere, radius: 0.5 } ]\n";

TEST(Cli, UsageErrorsExitWith2) {
  EXPECT_EQ(run("").code, 2);
  const Result r = run("simulat x.yaml");
  EXPECT_EQ(r.code, 2);
  EXPECT_NE(r.out.find("did you mean 'simulate'?"), std::string::npos) << r.out;
  EXPECT_EQ(run("simulate " + write("g.yaml", kGood) + " --integrator nope").code, 2);
  EXPECT_EQ(run("simulate " + write("g.yaml", kGood) + " --timestep -1").code, 2);
  EXPECT_EQ(run("simulate " + write("g.yaml", kGood) + " --bogus").code, 2);
  const Result gl = run("render " + write("g.yaml", kGood) + " --gl vulkan");
  EXPECT_EQ(gl.code, 2);
  EXPECT_NE(gl.out.find("unknown --gl 'vulkan' (osmesa, egl)"), std::string::npos) << gl.out;
  for (const char* c : {"render", "simulate", "inspect"}) {
    const Result h = run(std::string(c) + " --help");
    EXPECT_EQ(h.code, 0) << c;
    EXPECT_NE(h.out.find("usage: simreel"), std::string::npos) << c;
  }
}

TEST(Cli, BadSceneExitsWith2AndLeavesNoOutput) {
  const fs::path csv = tmp("bad.csv"), mp4 = tmp("bad.mp4");
  fs::remove(csv);
  fs::remove(mp4);
  const std::string bad =
      write("bad.yaml", "simulation: { duration: 1 }\nbodies:\n  - colliders: [ { shape: box } ]\n");
  const Result r = run("simulate " + bad + " --csv " + csv.string());
  EXPECT_EQ(r.code, 2);
  EXPECT_NE(r.out.find("bad.yaml:3:"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("needs 'size'"), std::string::npos) << r.out;
  EXPECT_FALSE(fs::exists(csv));
  EXPECT_EQ(run("render " + bad + " -o " + mp4.string()).code, 2);
  EXPECT_FALSE(fs::exists(mp4));
  EXPECT_EQ(run("simulate " + tmp("missing.yaml").string()).code, 2);
}

TEST(Cli, SimulateWritesTheCsvAtEveryFrameAndAJsonSummary) {
  const fs::path csv = tmp("good.csv");
  const Result r = run("simulate " + write("good.yaml", kGood) + " --csv " + csv.string() + " --json");
  ASSERT_EQ(r.code, 0) << r.out;
  const nlohmann::json j = json_of(r.out);
  EXPECT_EQ(j["steps"], 100) << r.out;
  EXPECT_EQ(j["bodies"], 2);
  for (const char* k : {"step_seconds", "energy_rel_drift", "momentum_rel_drift"})
    EXPECT_TRUE(j[k].is_number()) << k << " in " << r.out;
  std::ifstream in(csv);
  std::string line;
  std::getline(in, line);
  EXPECT_EQ(line, "t,body,px,py,pz,qw,qx,qy,qz,vx,vy,vz,wx,wy,wz");
  int rows = 0;
  std::string first, last;
  while (std::getline(in, line)) {
    if (rows == 0) first = line;
    last = line;
    ++rows;
  }
  EXPECT_EQ(rows, 11 * 2);  // frames at t = 0, 0.1, ..., 1.0, two bodies each
  EXPECT_EQ(first.rfind("0,a,0,0,0,1,0,0,0,", 0), 0u) << first;
  EXPECT_EQ(last.rfind("1,b,5,0,", 0), 0u) << last;
  // Free fall of b: z = -g t^2 / 2 at t = 1 (the default integrator is exact for constant g).
  std::stringstream ss(last);
  std::string f;
  for (int i = 0; i < 5; ++i) std::getline(ss, f, ',');
  EXPECT_NEAR(std::stod(f), -9.81 / 2, 1e-12);
}

// --profile: time per stage and what each stage skipped. kGood plus a static box: the box is
// gyroscopic, the sphere isotropic (auto gives it no gyroscopic work), the static box is never
// integrated; no force field or wrench, so forces and clear are skipped in every step.
// The summary reports drift only for what the scene conserves, and says what breaks the rest: a
// pendulum keeps its energy (the ground it never reaches takes nothing) but not its angular
// momentum (the pivot holds it); a free tumbling body keeps both; a pile keeps neither.
TEST(Cli, SummaryReportsDriftOnlyForWhatIsConserved) {
  Result r = run("simulate scenes/pendulum.yaml --duration 1");
  ASSERT_EQ(r.code, 0) << r.out;
  EXPECT_NE(r.out.find("energy (conserved here): drift"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("angular momentum is not conserved here: a joint holds 'pendulum' to the world"),
            std::string::npos)
      << r.out;
  EXPECT_EQ(r.out.find("angular momentum drift"), std::string::npos) << r.out;
  r = run("simulate scenes/dzhanibekov.yaml --duration 1 --json");
  EXPECT_NE(r.out.find("\"energy_conserved\":true"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("\"angular_momentum_conserved\":true"), std::string::npos) << r.out;
  r = run("simulate scenes/pile.yaml --duration 1");
  EXPECT_NE(r.out.find("energy is not conserved here: contacts take energy"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("angular momentum is not conserved here: contacts with the ground"), std::string::npos)
      << r.out;
  r = run("simulate scenes/spring_pendulum.yaml --duration 1");
  EXPECT_NE(r.out.find("energy is not conserved here: drag takes energy"), std::string::npos) << r.out;
  // A hinge's limits take energy only once reached: a pendulum let go 60 degrees from the vertical
  // swings its coordinate (zero at the start) through 120 degrees either way; with limits at
  // +-150 degrees it keeps its energy, with limits at +-100 it does not.
  auto limited = [&](double deg) {
    const double rad = deg * 3.14159265358979 / 180;
    const std::string scene =
        "simulation: { duration: 3 }\n"
        "bodies:\n"
        "  - { name: bob, position: [0, 0, 1], place: { about: [0, 0, 2], axis: [0, 1, 0], angle: 60 },\n"
        "      colliders: [ { shape: sphere, radius: 0.1 } ] }\n"
        "joints:\n"
        "  - { name: pivot, type: revolute, bodies: [world, bob], anchor: [0, 0, 2], axis: [0, 1, 0],\n"
        "      limits: [" +
        std::to_string(-rad) + ", " + std::to_string(rad) + "] }\n";
    return run("simulate " + write("limited.yaml", scene) + " --json");
  };
  r = limited(150);
  EXPECT_NE(r.out.find("\"energy_conserved\":true"), std::string::npos) << r.out;
  r = limited(100);
  EXPECT_NE(r.out.find("\"energy_conserved\":false"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("a joint reached its limits"), std::string::npos) << r.out;
}

TEST(Cli, ProfileShowsStagesAndWhatWasSkipped) {
  const std::string scene = std::string(kGood) +
                            "  - name: floor\n    static: true\n    position: [0, 0, -50]\n"
                            "    colliders: [ { shape: box, size: [10, 10, 1] } ]\n";
  const Result r = run("simulate " + write("profile.yaml", scene) + " --profile --json");
  ASSERT_EQ(r.code, 0) << r.out;
  const nlohmann::json p = json_of(r.out)["profile"];
  auto stage = [](const nlohmann::json& prof, const char* name) {
    return std::make_tuple(prof[name]["seconds"] == 0, prof[name]["runs"].get<long>(),
                           prof[name]["skipped"].get<long>());
  };
  EXPECT_EQ(stage(p, "forces"), std::make_tuple(true, 0L, 100L)) << r.out;
  EXPECT_EQ(std::get<1>(stage(p, "integrate")), 100);
  EXPECT_EQ(std::get<2>(stage(p, "integrate")), 0);
  EXPECT_EQ(stage(p, "clear"), std::make_tuple(true, 0L, 100L));
  EXPECT_EQ(p["bodies"], nlohmann::json({{"gyroscopic", 1},
                                         {"isotropic_no_gyroscopic_work", 1},
                                         {"static_never_integrated", 1},
                                         {"kinematic", 0}}));
  // The floor is far below: the broad phase runs, the solver never does.
  EXPECT_EQ(stage(p, "solve"), std::make_tuple(true, 0L, 100L));
  EXPECT_EQ(std::get<1>(stage(p, "update_broad_phase")), 100);
  // Nothing that can collide (kGood's two bodies alone never meet... but they could: mask them
  // off): every contact stage is skipped and costs nothing.
  std::string masked = kGood;
  for (size_t q = 0; (q = masked.find("} ]", q)) != std::string::npos; q += 12)
    masked.replace(q, 3, ", mask: 0 } ]");
  const Result m = run("simulate " + write("masked.yaml", masked) + " --profile --json");
  ASSERT_EQ(m.code, 0) << m.out;
  const nlohmann::json mp = json_of(m.out)["profile"];
  for (const char* k : {"update_broad_phase", "collide", "prepare_contacts"})
    EXPECT_EQ(stage(mp, k), std::make_tuple(true, 0L, 100L)) << k << " in " << m.out;
  const Result text = run("simulate " + write("profile.yaml", scene) + " --profile");
  EXPECT_NE(text.out.find("1 static (never integrated)"), std::string::npos) << text.out;
}

// Balls and a box bouncing and rolling on the ground: contacts, restitution and warm starting.
const char* kContactScene =
    "simulation: { duration: 2.0 }\n"
    "video: { width: 64, height: 48, fps: 30 }\n"
    "ground: { friction: 0.5, restitution: 0.6 }\n"
    "bodies:\n"
    "  - name: a\n    position: [0, 0, 1]\n    linear_velocity: [1, 0, 0]\n"
    "    colliders: [ { shape: sphere, radius: 0.2, restitution: 0.7 } ]\n"
    "  - name: b\n    position: [0.1, 0, 2]\n    angular_velocity: [1, 2, 3]\n"
    "    colliders: [ { shape: box, size: [0.4, 0.3, 0.2] } ]\n"
    "  - name: c\n    position: [0.05, 0.02, 3]\n"
    "    colliders: [ { shape: sphere, radius: 0.15 } ]\n";

TEST(Cli, ResumeEqualsStraightRun) {
  const std::string sc = write("contact.yaml", kContactScene);
  ASSERT_EQ(run("simulate " + sc + " --quiet --csv " + tmp("full.csv").string()).code, 0);
  // Saved at 0.7 s, in the middle of the bounces (warm-start impulses and caches in the file).
  ASSERT_EQ(run("simulate " + sc + " --quiet --duration 0.7 --save-state " + tmp("s.bin").string()).code, 0);
  const Result r = run("simulate " + sc + " --quiet --resume " + tmp("s.bin").string() + " --csv " +
                       tmp("part.csv").string());
  ASSERT_EQ(r.code, 0) << r.out;
  const std::string full = slurp(tmp("full.csv")), part = slurp(tmp("part.csv"));
  // The resumed CSV starts at 0.7 s (its header, then the row at t = 0.7) and every row after it is
  // byte-identical to the straight run's tail.
  const size_t at = part.find('\n') + 1;
  ASSERT_EQ(part.compare(at, 6, "0.6999"), 0) << part.substr(0, 200);  // 168 steps of 1/240 s
  const std::string tail = part.substr(at);
  ASSERT_GE(full.size(), tail.size());
  EXPECT_EQ(full.substr(full.size() - tail.size()), tail);
  // A state from another scene, or not a state at all, is refused with exit code 2.
  const Result other = run("simulate " + write("g.yaml", kGood) + " --resume " + tmp("s.bin").string());
  EXPECT_EQ(other.code, 2);
  EXPECT_NE(other.out.find("another scene"), std::string::npos) << other.out;
  EXPECT_EQ(run("simulate " + sc + " --resume " + sc).code, 2);
}

TEST(Cli, JsonReportsContacts) {
  const Result r = run("simulate " + write("contact.yaml", kContactScene) + " --json");
  ASSERT_EQ(r.code, 0) << r.out;
  const nlohmann::json j = json_of(r.out);
  EXPECT_GT(j["contacts_max"].get<int>(), 0) << r.out;
  EXPECT_TRUE(j["max_penetration"].is_number());
  EXPECT_EQ(j["energy_gained"], 0) << r.out;
}

TEST(Cli, SameSceneGivesByteIdenticalTrajectories) {
  const std::string g = write("good.yaml", kGood);
  ASSERT_EQ(run("simulate " + g + " --quiet --csv " + tmp("a.csv").string()).code, 0);
  ASSERT_EQ(run("simulate " + g + " --quiet --threads 2 --csv " + tmp("b.csv").string()).code, 0);
  std::ifstream a(tmp("a.csv")), b(tmp("b.csv"));
  const std::string sa((std::istreambuf_iterator<char>(a)), {}), sb((std::istreambuf_iterator<char>(b)), {});
  EXPECT_EQ(sa, sb);
}

TEST(Cli, NonFiniteStateStopsTheRunNamingBodyAndTime) {
  const std::string s = write("nan.yaml",
                              "simulation: { duration: 1, timestep: 0.01 }\nbodies:\n  - name: wild\n"
                              "    angular_velocity: [1e200, 1e200, 1e150]\n"
                              "    colliders: [ { shape: box, size: [3, 2, 1] } ]\n");
  const Result r = run("simulate " + s);
  EXPECT_EQ(r.code, 1) << r.out;
  EXPECT_NE(r.out.find("'wild'"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("t = "), std::string::npos) << r.out;
}

TEST(Cli, InspectReportsMassPropertiesAsJson) {
  const Result r = run("inspect assets/tetra.off --json --density 1000");
  ASSERT_EQ(r.code, 0) << r.out;
  const nlohmann::json j = json_of(r.out);
  for (const char* k : {"volume", "mass"}) EXPECT_TRUE(j[k].is_number()) << k << " in " << r.out;
  EXPECT_EQ(j["centroid"].size(), 3u);
  EXPECT_EQ(j["inertia"].size(), 3u);
  EXPECT_EQ(j["principal_moments"].size(), 3u);
  EXPECT_EQ(j["closed"], true);
  EXPECT_EQ(j["consistently_oriented"], true);
  EXPECT_EQ(j["warnings"], nlohmann::json::array());
  const Result open = run("inspect assets/open_box.obj");
  EXPECT_EQ(open.code, 2);
  EXPECT_NE(open.out.find("(shell mode)"), std::string::npos) << "the hint names the mode, not a scene key\n"
                                                              << open.out;
  const Result scene = run("inspect scenes/projectile.yaml");
  EXPECT_EQ(scene.code, 2);
  EXPECT_NE(scene.out.find("is a scene file, not a mesh"), std::string::npos) << scene.out;
  const Result hull = run("inspect assets/open_box.obj --mode hull --json");
  EXPECT_EQ(hull.code, 0);
  EXPECT_EQ(json_of(hull.out)["closed"], false) << hull.out;
  EXPECT_EQ(run("inspect " + write("junk.obj", "this is not a mesh\n")).code, 2);
}

// A robot file alone: simulate counts its bodies and joints and lists its notes in --json,
// package:// is found through --package-path, and inspect lists links and joints.
TEST(Cli, RobotFilesDirectly) {
  const std::string urdf = "tests/data/import/elsewhere.urdf";
  const Result missing = run("simulate " + urdf + " --duration 0.1");
  EXPECT_EQ(missing.code, 2);
  EXPECT_NE(missing.out.find("package 'my_robot' not found"), std::string::npos) << missing.out;
  const Result r = run("simulate " + urdf + " --duration 0.1 --json --package-path tests/data/import/pkg");
  ASSERT_EQ(r.code, 0) << r.out;
  const nlohmann::json j = json_of(r.out);
  EXPECT_EQ(j["bodies"], 2);  // the robot and the ground
  const Result dp = run("simulate tests/data/import/double_pendulum.urdf --duration 0.1 --json");
  ASSERT_EQ(dp.code, 0) << dp.out;
  const nlohmann::json k = json_of(dp.out);
  EXPECT_EQ(k["joints"], 2);
  EXPECT_LT(k["joint_error_max"].get<double>(), 1e-12);
  const Result mj = run("simulate tests/data/import/four_bar.xml --duration 0.1 --json");
  ASSERT_EQ(mj.code, 0) << mj.out;
  const nlohmann::json m = json_of(mj.out);
  EXPECT_EQ(m["joints"], 4);
  bool noted = false;
  for (const auto& n : m["notes"])
    noted = noted || n.get<std::string>().find("<flywheel>") != std::string::npos;
  EXPECT_TRUE(noted) << mj.out;
  const Result in = run("inspect tests/data/import/cart_pendulum.urdf --json");
  ASSERT_EQ(in.code, 0) << in.out;
  const nlohmann::json i = json_of(in.out);
  EXPECT_EQ(i["bodies"].size(), 3u);
  EXPECT_EQ(i["joints"].size(), 2u);
  EXPECT_EQ(i["joints"][1]["name"], "hinge");
  EXPECT_EQ(i["bodies"][0]["type"], "static");
}

// inspect says what render will draw of a file's look: its materials, their images (a missing one
// as a warning), texture coordinates.
TEST(Cli, InspectShowsTheFilesLook) {
  write("look.mtl", "newmtl red\nKd 0.8 0.1 0.1\nnewmtl skin\nKd 1 1 1\nmap_Kd gone.png\n");
  const std::string obj =
      write("look.obj",
            "mtllib look.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nvt 0 0\nvt 1 0\nvt 0 1\n"
            "usemtl red\nf 1/1 3/3 2/2\nf 1/1 2/2 4/3\nusemtl skin\nf 1/1 4/3 3/2\nf 2/1 3/2 4/3\n");
  const Result r = run("inspect " + obj + " --json");
  ASSERT_EQ(r.code, 0) << r.out;
  const nlohmann::json look = json_of(r.out)["look"];
  ASSERT_EQ(look["materials"].size(), 2u) << r.out;
  EXPECT_EQ(look["materials"][0]["name"], "red");
  EXPECT_NEAR(look["materials"][0]["color"][0].get<double>(), 0.8, 1e-6);
  EXPECT_TRUE(look["materials"][1]["image"].is_null()) << "gone.png is not there";
  EXPECT_EQ(look["texture_coordinates"], true);
  EXPECT_EQ(look["drawn_with_it"], true);
  EXPECT_NE(r.out.find("gone.png"), std::string::npos) << "a warning names the missing image\n" << r.out;
  const Result plain = run("inspect assets/tetra.off --json");
  EXPECT_EQ(json_of(plain.out)["look"]["materials"].size(), 0u);
}

// Byte-identical PNG frames from separate processes, whatever llvmpipe's rasteriser thread count
// (LP_NUM_THREADS 1, 2, 3), the physics thread count and the GL backend (OSMesa, EGL), with
// shadows and FXAA on.
TEST(Cli, PngFramesAreIdenticalAcrossProcessesAndThreadCounts) {
  const std::string scene =
      write("det.yaml",
            "simulation: { duration: 0.5, timestep: 0.005, gravity: [0, 0, -9.81] }\n"
            "video: { width: 96, height: 64, fps: 10 }\n"
            "camera: { position: [5, -5, 3], look_at: [0, 0, 0] }\n"
            "render: { ground: { height: -2 } }\n"
            "bodies:\n"
            "  - { name: a, angular_velocity: [0.1, 3, 0.1], color: [0.8, 0.3, 0.2],\n"
            "      colliders: [ { shape: box, size: [3, 2, 1] } ] }\n"
            "  - { name: b, position: [1, 1, 1], colliders: [ { shape: sphere, radius: 0.5 } ] }\n");
  const char* runs[][3] = {{"1", "1", ""}, {"2", "2", ""}, {"3", "1", ""}, {"2", "1", "egl"}};
  std::vector<std::vector<std::string>> frames;
  for (const auto& r : runs) {
    const fs::path dir = tmp(std::string("frames_lp") + r[0] + "_" + r[1] + r[2]);
    fs::create_directories(dir);
    const Result res =
        run(std::string("render ") + scene + " --frames-dir " + dir.string() +
                " --no-video --quiet --threads " + r[1] + (*r[2] ? std::string(" --gl ") + r[2] : ""),
            std::string("LP_NUM_THREADS=") + r[0]);
    if (res.code == 2 && res.out.find("built without") != std::string::npos) continue;  // a one-backend build
    ASSERT_EQ(res.code, 0) << res.out;
    std::vector<std::string> f;
    for (int k = 0; k <= 5; ++k) {
      char name[32];
      std::snprintf(name, sizeof name, "frame_%05d.png", k);
      ASSERT_TRUE(fs::exists(dir / name)) << dir / name;
      f.push_back(slurp(dir / name));
    }
    frames.push_back(f);
  }
  for (size_t r = 1; r < frames.size(); ++r)
    for (size_t k = 0; k < frames[0].size(); ++k)
      EXPECT_TRUE(frames[r][k] == frames[0][k])
          << "frame " << k << " differs in run " << r << ": LP_NUM_THREADS=" << runs[r][0] << ", --threads "
          << runs[r][1] << ", --gl " << (*runs[r][2] ? runs[r][2] : "(default)");
  EXPECT_GE(frames.size(), 3u);
  EXPECT_NE(frames[0][0], frames[0][5]) << "the scene should move";
}

TEST(Cli, InterruptedRenderLeavesAPlayableVideoOfTheFramesDone) {
  const std::string scene = write("long.yaml",
                                  "simulation: { duration: 600, timestep: 0.01, gravity: [0, 0, 0] }\n"
                                  "video: { width: 320, height: 240, fps: 30 }\n"
                                  "bodies:\n  - angular_velocity: [0.1, 3, 0.1]\n"
                                  "    colliders: [ { shape: box, size: [3, 2, 1] } ]\n");
  const fs::path out = tmp("long.mp4");
  fs::remove(out);
  const pid_t pid = fork();
  if (pid == 0) {
    const int devnull = open("/dev/null", 1);
    dup2(devnull, 1);
    dup2(devnull, 2);
    execl(SIMREEL_BIN, SIMREEL_BIN, "render", scene.c_str(), "-o", out.string().c_str(), "--quiet",
          (char*)nullptr);
    _exit(99);
  }
  std::this_thread::sleep_for(std::chrono::milliseconds(2500));
  EXPECT_FALSE(fs::exists(out)) << "the video appeared before it was complete";
  kill(pid, SIGINT);
  int st = 0;
  waitpid(pid, &st, 0);
  ASSERT_TRUE(WIFEXITED(st));
  EXPECT_EQ(WEXITSTATUS(st), 128 + SIGINT);
  ASSERT_TRUE(fs::exists(out));
  const simreel::test::Decoded d = simreel::test::decode(out.string());
  EXPECT_EQ(d.codec, "h264");
  EXPECT_GT(d.frames, 0);
  for (const auto& e : fs::directory_iterator(out.parent_path()))
    EXPECT_EQ(e.path().filename().string().find("long.partial"), std::string::npos);
}

// A frame is a pure function of the state, the camera and the settings: frames of a partial
// render (--frames) and a preview (--at) equal the same frames of a full render byte for byte,
// with the same names, for a static camera over a cached ground and for a following camera. The
// sphere flies away so the depth range changes on the way (a depth range kept from earlier frames
// would make frames such as 12 and 25 differ between a full and a partial render).
TEST(Cli, PartialRenderFramesEqualTheFullRendersFrames) {
  for (const char* camera : {"camera: { position: [6, -6, 3], look_at: [0, 0, 0.5] }\n",
                             "camera: { position: [6, -6, 3], look_at: [0, 0, 0.5], follow: b }\n"}) {
    const std::string scene =
        write("pure.yaml", std::string("simulation: { duration: 3, timestep: 0.005 }\n"
                                       "video: { width: 96, height: 64, fps: 10 }\n") +
                               camera +
                               "ground: { restitution: 0.5 }\n"
                               "bodies:\n"
                               "  - { name: a, position: [0, 0, 1], angular_velocity: [0.1, 3, "
                               "0.1], color: [0.8, 0.3, 0.2],\n"
                               "      colliders: [ { shape: box, size: [1, 0.6, 0.3] } ] }\n"
                               "  - { name: b, position: [1, 1, 0.5], linear_velocity: [-3, 8, 9],\n"
                               "      colliders: [ { shape: sphere, radius: 0.3 } ] }\n");
    const fs::path full = tmp("full"), part = tmp("part"), at = tmp("at.png");
    fs::remove_all(full), fs::remove_all(part);
    ASSERT_EQ(run("render " + scene + " --no-video --quiet --frames-dir " + full.string()).code, 0);
    const Result r =
        run("render " + scene + " --no-video --quiet --frames 9:12,25 --frames-dir " + part.string());
    ASSERT_EQ(r.code, 0) << r.out;
    std::vector<std::string> names;
    for (const auto& e : fs::directory_iterator(part)) names.push_back(e.path().filename().string());
    std::sort(names.begin(), names.end());
    EXPECT_EQ(names, (std::vector<std::string>{"frame_00009.png", "frame_00010.png", "frame_00011.png",
                                               "frame_00012.png", "frame_00025.png"}));
    for (const std::string& n : names)
      EXPECT_TRUE(slurp(part / n) == slurp(full / n)) << n << " with " << camera;
    ASSERT_EQ(run("render " + scene + " --quiet --at 1.1 -o " + at.string()).code, 0);
    EXPECT_TRUE(slurp(at) == slurp(full / "frame_00011.png")) << "--at 1.1 is frame 11, with " << camera;
    EXPECT_FALSE(slurp(full / "frame_00009.png") == slurp(full / "frame_00011.png"))
        << "the scene should move";
  }
}

// A moving camera and motion blur keep frames pure: a partial render's frames, and --at's, are the
// full render's byte for byte with a camera path, an orbit around a moving body, a damped follow
// (advanced at every step, drawn or not) and motion blur (sub-frames at the steps before each
// frame). Frame 9's shutter opens before frame 9, where the partial render draws nothing else.
TEST(Cli, PartialRenderFramesEqualTheFullRendersWithAMovingCameraAndBlur) {
  const std::string blur = "render: { motion_blur: { samples: 4, shutter: 0.5 } }\n";
  const std::vector<std::string> cameras = {
      "camera:\n  look_at: [0, 0, 0.5]\n  path:\n    - { t: 0.2, position: [6, -6, 3], fov: 35 }\n"
      "    - { t: 1.4, position: [7, 2, 2] }\n    - { t: 2.5, position: [2, 7, 4], look_at: [0, 1, 1], fov: "
      "50 }\n",
      "camera: { orbit: { body: b, radius: 6, height: 2, period: 4 } }\n",
      "camera: { position: [6, -6, 3], look_at: [0, 0, 0.5], follow: { body: b, damping: 0.3 } }\n",
      "camera: { position: [6, -6, 3], look_at: [0, 0, 0.5] }\n" + blur,
      "camera: { orbit: { period: 6 }, position: [6, -6, 3], look_at: [0, 0, 0.5] }\n" + blur};
  for (const std::string& camera : cameras) {
    const std::string scene = write("moving.yaml",
                                    "simulation: { duration: 3, timestep: 0.005 }\n"
                                    "video: { width: 96, height: 64, fps: 10 }\n" +
                                        camera +
                                        "ground: { restitution: 0.5 }\n"
                                        "bodies:\n"
                                        "  - { name: a, position: [0, 0, 1], angular_velocity: "
                                        "[0.1, 3, 0.1], color: [0.8, 0.3, 0.2],\n"
                                        "      colliders: [ { shape: box, size: [1, 0.6, 0.3] } ] }\n"
                                        "  - { name: b, position: [1, 1, 0.5], linear_velocity: "
                                        "[-3, 2, 9],\n"
                                        "      colliders: [ { shape: sphere, radius: 0.3 } ] }\n");
    const fs::path full = tmp("mfull"), part = tmp("mpart"), at = tmp("mat.png");
    fs::remove_all(full), fs::remove_all(part);
    const Result f = run("render " + scene + " --no-video --quiet --frames-dir " + full.string());
    ASSERT_EQ(f.code, 0) << f.out;
    const Result r =
        run("render " + scene + " --no-video --quiet --frames 9:12,25 --frames-dir " + part.string());
    ASSERT_EQ(r.code, 0) << r.out;
    for (const char* n :
         {"frame_00009.png", "frame_00010.png", "frame_00011.png", "frame_00012.png", "frame_00025.png"})
      EXPECT_TRUE(slurp(part / n) == slurp(full / n)) << n << " with " << camera;
    ASSERT_EQ(run("render " + scene + " --quiet --at 1.1 -o " + at.string()).code, 0);
    EXPECT_TRUE(slurp(at) == slurp(full / "frame_00011.png")) << "--at 1.1 is frame 11, with " << camera;
    EXPECT_FALSE(slurp(full / "frame_00010.png") == slurp(full / "frame_00011.png")) << camera;
  }
}

// The plain `follow: NAME` and `follow: { body: NAME, damping: 0 }` draw the same frames; a
// damping draws others (the camera lags the body). Motion blur of a scene where nothing moves is
// the sharp frame byte for byte through the whole pipeline (FXAA and the HUD on the writer's
// thread); of a moving ball it is not.
TEST(Cli, ZeroDampingIsTheRigidFollowAndAStillSceneBlursToItself) {
  const std::string box =
      "  - { name: a, position: [0, 0, 0.15], colliders: [ { shape: box, size: [1, 0.6, 0.3] } ] }\n";
  const std::string ball =
      "  - { name: b, position: [1, 1, 2], linear_velocity: [-1, 1, 3], colliders: [ { shape: sphere, "
      "radius: 0.3 } ] }\n";
  auto frames = [&](const std::string& text, const std::string& name) {
    const std::string scene = write(name + ".yaml", "video: { width: 96, height: 64, fps: 10 }\n" + text);
    const fs::path dir = tmp(name);
    fs::remove_all(dir);
    const Result r = run("render " + scene + " --no-video --quiet --frames-dir " + dir.string());
    EXPECT_EQ(r.code, 0) << r.out;
    std::vector<std::string> out;
    for (int k = 0; k <= 10; ++k) {
      char n[32];
      std::snprintf(n, sizeof n, "frame_%05d.png", k);
      out.push_back(slurp(dir / n));
      EXPECT_FALSE(out.back().empty()) << name << " " << n;
    }
    return out;
  };
  const std::string run1 = "simulation: { duration: 1, timestep: 0.005 }\nground: true\n";
  const std::string cam = "camera: { position: [5, -5, 3], look_at: [0, 0, 0.5], ";
  const auto rigid = frames(run1 + cam + "follow: b }\nbodies:\n" + box + ball, "rigid");
  EXPECT_TRUE(rigid ==
              frames(run1 + cam + "follow: { body: b, damping: 0 } }\nbodies:\n" + box + ball, "damp0"));
  const auto damped =
      frames(run1 + cam + "follow: { body: b, damping: 0.5 } }\nbodies:\n" + box + ball, "damp5");
  EXPECT_TRUE(rigid[0] == damped[0]) << "both start on the body";
  EXPECT_FALSE(rigid[5] == damped[5]) << "a damped camera lags";

  const std::string hud = "overlays: { hud: [\"t = {t:.2f} s\"] }\n";
  const std::string still =
      "simulation: { duration: 1, timestep: 0.005, gravity: [0, 0, 0] }\nground: true\n" + cam + "}\n" + hud +
      "bodies:\n" + box;
  const std::string blur = "render: { motion_blur: { samples: 6, shutter: 1 } }\n";
  EXPECT_TRUE(frames(still, "still") == frames(still + blur, "still_blur"));
  const auto moving = frames(run1 + cam + "}\nbodies:\n" + box + ball, "moving");
  const auto moving_blur = frames(run1 + cam + "}\n" + blur + "bodies:\n" + box + ball, "moving_blur");
  EXPECT_TRUE(moving[0] == moving_blur[0]) << "frame 0 has no shutter interval before it";
  EXPECT_FALSE(moving[5] == moving_blur[5]) << "the ball moves: blurred";
}

// --frames-dir never mixes old frames with new ones: a folder holding frames is refused (exit 2,
// nothing touched) unless --overwrite, which deletes the old frames (and only them) first.
TEST(Cli, FramesDirRefusesOldFramesUnlessOverwrite) {
  const std::string scene = write("g.yaml", kGood);
  const fs::path dir = tmp("frames");
  ASSERT_EQ(run("render " + scene + " --no-video --quiet --frames-dir " + dir.string()).code, 0);
  EXPECT_TRUE(fs::exists(dir / "frame_00010.png"));
  std::ofstream(dir / "notes.txt") << "mine";
  const Result again =
      run("render " + scene + " --no-video --quiet --duration 0.5 --frames-dir " + dir.string());
  EXPECT_EQ(again.code, 2);
  EXPECT_NE(again.out.find("--overwrite"), std::string::npos) << again.out;
  EXPECT_TRUE(fs::exists(dir / "frame_00010.png")) << "a refused run must not touch the folder";
  const Result ow =
      run("render " + scene + " --no-video --quiet --duration 0.5 --overwrite --frames-dir " + dir.string());
  ASSERT_EQ(ow.code, 0) << ow.out;
  EXPECT_TRUE(fs::exists(dir / "frame_00005.png"));
  EXPECT_FALSE(fs::exists(dir / "frame_00006.png")) << "a stale frame of the longer run survived";
  EXPECT_TRUE(fs::exists(dir / "notes.txt")) << "--overwrite deletes frames only";
}

// Outputs simreel cannot write are refused before anything runs: exit 2, no file.
TEST(Cli, UnwritableOutputsAreRefusedUpFront) {
  const std::string scene = write("g.yaml", kGood);
  for (const char* o : {"x.png", "dz", "x.avi"}) {
    const fs::path out = tmp(o);
    const Result r = run("render " + scene + " --quiet -o " + out.string());
    EXPECT_EQ(r.code, 2) << o << ": " << r.out;
    EXPECT_NE(r.out.find("must end in"), std::string::npos) << r.out;
    EXPECT_FALSE(fs::exists(out)) << o;
  }
  const fs::path folder = tmp("folder.mp4");
  fs::create_directories(folder);
  const Result r = run("render " + scene + " --quiet -o " + folder.string());
  EXPECT_EQ(r.code, 2) << r.out;
  EXPECT_NE(r.out.find("folder"), std::string::npos) << r.out;
  EXPECT_EQ(run("render " + scene + " --quiet --at 0.5 -o " + tmp("x.mp4").string()).code, 2);
  EXPECT_EQ(run("render " + scene + " --quiet --at 7 -o " + tmp("x.png").string()).code, 2);
  EXPECT_EQ(run("render " + scene + " --quiet --frames 99 -o " + tmp("y.mp4").string()).code, 2);
  EXPECT_FALSE(fs::exists(tmp("y.mp4").string()));
}

// simulate and render run the same steps and report the same figures.
TEST(Cli, SimulateAndRenderReportTheSameRun) {
  const std::string scene = write("g.yaml",
                                  "simulation: { duration: 1.03, timestep: 0.01 }\n"
                                  "video: { width: 64, height: 48, fps: 10 }\n"
                                  "bodies:\n  - angular_velocity: [0.1, 3, 0.1]\n"
                                  "    colliders: [ { shape: box, size: [3, 2, 1] } ]\n");
  const Result s = run("simulate " + scene + " --json");
  const Result r = run("render " + scene + " --json -o " + tmp("g.mp4").string());
  ASSERT_EQ(s.code, 0);
  ASSERT_EQ(r.code, 0) << r.out;
  const nlohmann::json js = json_of(s.out), jr = json_of(r.out);
  for (const char* k : {"steps", "frames", "energy_rel_drift", "momentum_rel_drift"})
    EXPECT_EQ(js[k], jr[k]) << k;
  EXPECT_EQ(js["steps"], 103);
}

// Options that need a value never take the next option as it (simulate --csv --quiet wrote a file
// called --quiet); an unknown command points at the top-level help and the nearest command.
TEST(Cli, OptionsAreNeverValuesAndTyposGetTheNearestCommand) {
  const std::string scene = write("g.yaml", kGood);
  const Result r = run("simulate " + scene + " --csv --quiet");
  EXPECT_EQ(r.code, 2);
  EXPECT_NE(r.out.find("--csv needs a value, got the option --quiet"), std::string::npos) << r.out;
  EXPECT_FALSE(fs::exists("--quiet"));
  const Result t = run("rendr " + scene);
  EXPECT_EQ(t.code, 2);
  EXPECT_NE(t.out.find("did you mean 'render'"), std::string::npos) << t.out;
  EXPECT_NE(t.out.find("see simreel --help"), std::string::npos) << t.out;
}

// The options a help text lists: its lines "  -o OUT  ..." and "  -h, --help  ..."; -h and --help,
// which every command has, are left out.
std::set<std::string> help_options(const std::string& help) {
  std::set<std::string> names;
  std::istringstream in(help);
  for (std::string line; std::getline(in, line);) {
    if (line.rfind("  -", 0) != 0) continue;
    std::istringstream words(line);
    for (std::string w; words >> w;) {
      const bool more = w.back() == ',';
      if (more) w.pop_back();
      if (w != "-h" && w != "--help") names.insert(w);
      if (!more) break;
    }
  }
  return names;
}

// The options the README's usage block gives `command`: every -x / --word in its lines (a command's
// line starts "simreel COMMAND", its continuation lines with spaces).
std::set<std::string> readme_options(const std::string& readme, const std::string& command) {
  const size_t a = readme.find("## Using it\n```\n");
  const size_t b = readme.find("```", a + 16);
  std::istringstream in(readme.substr(a + 16, b - a - 16));
  std::set<std::string> names;
  bool mine = false;
  for (std::string line; std::getline(in, line);) {
    if (line.rfind("simreel ", 0) == 0) {
      std::istringstream w(line.substr(8));
      std::string c;
      w >> c;
      mine = c == command;
    }
    if (!mine) continue;
    for (size_t i = 0; i < line.size(); ++i) {
      if (line[i] != '-' || (i > 0 && line[i - 1] != '[' && line[i - 1] != ' ')) continue;
      size_t j = i;
      while (j < line.size() && (line[j] == '-' || std::isalnum((unsigned char)line[j]))) ++j;
      names.insert(line.substr(i, j - i));
      i = j;
    }
  }
  return names;
}

// The README's usage block lists every option of every command and no other: the same
// set as each command's --help (which the option tables generate).
TEST(Cli, ReadmeUsageBlockAndHelpListTheSameOptions) {
  const std::string readme = slurp("README.md");
  ASSERT_NE(readme.find("## Using it\n```\n"), std::string::npos);
  const Result top = run("--help");
  ASSERT_EQ(top.code, 0);
  std::istringstream in(top.out);
  int commands = 0;
  for (std::string line; std::getline(in, line);) {
    if (line.rfind("  simreel ", 0) != 0) continue;
    const std::string command = line.substr(10, line.find(' ', 10) - 10);
    ++commands;
    const Result h = run(command + " --help");
    ASSERT_EQ(h.code, 0) << command;
    const std::set<std::string> help = help_options(h.out), doc = readme_options(readme, command);
    EXPECT_GT(help.size(), 2u) << command << ": " << h.out;
    for (const std::string& o : help)
      EXPECT_TRUE(doc.count(o)) << "simreel " << command << " " << o
                                << " is missing from the README's usage block";
    for (const std::string& o : doc)
      EXPECT_TRUE(help.count(o)) << "the README gives simreel " << command << " " << o
                                 << ", which --help does not list";
  }
  EXPECT_EQ(commands, 7) << top.out;
}

// Help comes from the option tables, in one layout; --help wins over any other error.
TEST(Cli, HelpIsGeneratedFromTheTables) {
  for (const char* c : {"render", "simulate", "inspect", "check", "diff", "plan", "join"}) {
    const Result h = run(std::string(c) + " --bogus --width 1 --help");
    EXPECT_EQ(h.code, 0) << c << ": " << h.out;
    EXPECT_EQ(h.out.rfind(std::string("usage: simreel ") + c + " ", 0), 0u) << h.out;
    EXPECT_NE(h.out.find("\noptions:\n"), std::string::npos) << h.out;
    EXPECT_NE(h.out.find("  -h, --help          print this help\n"), std::string::npos) << h.out;
    std::istringstream in(h.out);
    for (std::string line; std::getline(in, line);) EXPECT_LE(line.size(), 100u) << c << ": " << line;
    EXPECT_EQ(run(std::string(c) + " -h").out, h.out);
  }
  const Result top = run("help");
  EXPECT_EQ(top.code, 0);
  EXPECT_NE(top.out.find("  simreel check SCENE... --goldens DIR [options]\n"), std::string::npos) << top.out;
}

// Parsing rules on top of CLI11: nearest option named, flags take no value, the last of a repeated
// option wins, values are checked with messages that name the option, an option's value may be a
// negative number, and every usage error exits 2 naming the command's help.
TEST(Cli, OptionErrorsNameTheOptionAndExitWith2) {
  const std::string scene = write("g.yaml", kGood);
  const struct {
    std::string args, message;
  } bad[] = {
      {"simulate " + scene + " --integratr rk4", "unknown option --integratr; did you mean --integrator?"},
      {"simulate " + scene + " --quiet=yes", "--quiet takes no value"},
      {"simulate " + scene + " --csv", "--csv needs a value (see simreel simulate --help)"},
      {"simulate " + scene + " --duration abc", "--duration expects a number, got 'abc'"},
      {"simulate " + scene + " --duration inf", "--duration expects a number, got 'inf'"},
      {"simulate " + scene + " --timestep -1", "--timestep must be positive, got '-1'"},
      {"simulate " + scene + " --threads 2.5", "--threads expects a whole number from 1 to 256, got '2.5'"},
      {"simulate " + scene + " --integrator rk5",
       "unknown --integrator 'rk5' (auto, seed, euler_gyro, rk4, splitting); did you mean 'rk4'?"},
      {"render " + scene + " --crf 52", "--crf expects a whole number from 0 to 51, got '52'"},
      {"render " + scene + " --aa msaa3", "unknown --aa 'msaa3' (fxaa, msaa2, msaa4, none)"},
      {"render " + scene + " -o " + tmp("x.mp4").string() + " --gif-fps 10",
       "--gif-fps applies to a .gif output"},
      {"render " + scene + " " + scene, "render takes one scene file"},
      {"inspect x.obj --mode solid --mode wire", "unknown --mode 'wire' (solid, shell, hull)"},
      {"check " + scene + " --update sometimes --goldens g",
       "unknown --update 'sometimes' (missing, changed, all, none)"},
      {"diff a.png b.png --tolerance loose", "unknown --tolerance 'loose' (portable, exact)"},
      {"diff a.png", "diff takes two inputs, A and B"},
  };
  for (const auto& b : bad) {
    const Result r = run(b.args);
    EXPECT_EQ(r.code, 2) << b.args << ": " << r.out;
    EXPECT_NE(r.out.find(b.message), std::string::npos) << b.args << ": " << r.out;
  }
  // The last of a repeated option wins; "2.0" is a whole number; a negative value is a value.
  const Result r = run("simulate " + scene + " --json --duration 5 --duration 0.5 --threads 2.0");
  ASSERT_EQ(r.code, 0) << r.out;
  EXPECT_EQ(json_of(r.out)["steps"], 50) << r.out;
  const Result neg = run("render " + scene + " --at -0.5 -o " + tmp("n.png").string());
  EXPECT_EQ(neg.code, 2) << neg.out;
  EXPECT_NE(neg.out.find("--at -0.5 is outside the run"), std::string::npos) << neg.out;
}

// GIF options end to end: --gif-width scales (the height by the aspect ratio), --gif-fps picks the
// frame nearest each GIF frame's time; both refused beyond what the frames have. The same scene
// gives the same GIF, byte for byte.
TEST(Cli, GifWidthAndFrameRate) {
  const std::string scene = write("g.yaml", kGood);  // 64x48, 10 frames/s, 1 s: 11 frames
  const fs::path gif = tmp("g.gif"), again = tmp("again.gif");
  ASSERT_EQ(run("render " + scene + " --quiet -o " + gif.string() + " --gif-width 32 --gif-fps 5").code, 0);
  const simreel::test::Decoded d = simreel::test::decode(gif.string());
  EXPECT_EQ(d.codec, "gif");
  EXPECT_EQ(d.width, 32);
  EXPECT_EQ(d.height, 24);
  EXPECT_EQ(d.frames, 6);  // t = 0, 0.2, ..., 1.0
  EXPECT_NEAR(d.duration, 1.2, 0.011);
  ASSERT_EQ(run("render " + scene + " --quiet -o " + again.string() + " --gif-width 32 --gif-fps 5").code, 0);
  EXPECT_TRUE(slurp(gif) == slurp(again)) << "two renders of one scene gave different GIFs";
  const Result wide = run("render " + scene + " --quiet -o " + tmp("w.gif").string() + " --gif-width 128");
  EXPECT_EQ(wide.code, 2);
  EXPECT_NE(wide.out.find("--gif-width 128 is wider than the frames (64 px)"), std::string::npos) << wide.out;
  const Result fast = run("render " + scene + " --quiet -o " + tmp("f.gif").string() + " --gif-fps 12");
  EXPECT_EQ(fast.code, 2);
  EXPECT_NE(fast.out.find("--gif-fps 12 is above the video's frame rate (fps 10)"), std::string::npos)
      << fast.out;
  EXPECT_FALSE(fs::exists(tmp("w.gif")));
  EXPECT_FALSE(fs::exists(tmp("f.gif")));
}

// --quiet prints nothing but errors; without it a run that is not on a terminal logs plain
// progress lines (every 10%) on stderr and the summary on stdout.
TEST(Cli, QuietIsQuietAndLogsGetPlainProgress) {
  const std::string scene = write("g.yaml", kGood);
  EXPECT_EQ(run("simulate " + scene + " --quiet").out, "");
  // Notes too (here: the timestep shortened to divide 1/fps) are silent under --quiet.
  const std::string noted = write("noted.yaml",
                                  "simulation: { duration: 0.2, timestep: 0.003 }\n"
                                  "video: { width: 64, height: 48, fps: 25 }\n"
                                  "bodies:\n  - { colliders: [ { shape: box, size: [1, 1, 1] } ] }\n");
  EXPECT_NE(run("simulate " + noted).out.find("note:"), std::string::npos);
  EXPECT_EQ(run("simulate " + noted + " --quiet").out, "");
  EXPECT_EQ(run("render " + noted + " --quiet -o " + tmp("noted.mp4").string()).out, "");
  const std::string err = tmp("err.txt");
  const Result r = run("simulate " + scene + " 2>" + err + " >/dev/null; cat " + err);
  EXPECT_NE(r.out.find("11/11 frames (100%)"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("6/11 frames (55%)"), std::string::npos) << r.out;
  EXPECT_EQ(r.out.find('\r'), std::string::npos) << "no terminal redraws in a log";
}

// Frames fall exactly at k / fps: a timestep that does not divide the frame interval is shortened
// (with a note), never longer than asked; a step longer than the interval no longer repeats frames.
TEST(Cli, FramesFallExactlyAtMultiplesOfTheFrameInterval) {
  for (const char* sim :
       {"{ duration: 1.0, timestep: 0.0041666666666666667 }", "{ duration: 1.0, timestep: 0.5 }"}) {
    const std::string scene = write("fps.yaml", std::string("simulation: ") + sim +
                                                    "\nvideo: { width: 64, height: 48, fps: 25 }\n"
                                                    "bodies:\n  - { angular_velocity: [0.1, 3, 0.1], "
                                                    "colliders: [ { shape: box, size: [3, 2, 1] } ] }\n");
    const std::string csv = tmp("fps.csv");
    const Result r = run("simulate " + scene + " --csv " + csv);
    ASSERT_EQ(r.code, 0) << r.out;
    EXPECT_NE(r.out.find("does not divide the frame interval"), std::string::npos) << r.out;
    std::ifstream in(csv);
    std::string line;
    std::getline(in, line);
    int k = 0;
    std::vector<std::string> states;
    while (std::getline(in, line)) {
      EXPECT_NEAR(std::stod(line), k / 25.0, 1e-12) << line;
      states.push_back(line.substr(line.find(',')));
      ++k;
    }
    EXPECT_EQ(k, 26);
    for (size_t i = 1; i < states.size(); ++i)
      EXPECT_NE(states[i], states[i - 1]) << "frame " << i << " repeats";
  }
}

// Run lengths over the documented limits, and a denormal timestep, are refused up front naming the keys.
TEST(Cli, RunLimitsAreCheckedUpFront) {
  for (const char* sim : {"{ duration: 1e9 }", "{ duration: 1, timestep: 4.9e-324 }"}) {
    const std::string scene =
        write("limits.yaml", std::string("simulation: ") + sim +
                                 "\nbodies:\n  - { colliders: [ { shape: sphere, radius: 1 } ] }\n");
    const Result r = run("simulate " + scene);
    EXPECT_EQ(r.code, 2) << sim << ": " << r.out;
    EXPECT_NE(r.out.find("simulation."), std::string::npos) << r.out;  // the key named
    EXPECT_TRUE(r.out.find("over the limit") != std::string::npos ||
                r.out.find("more than any run") != std::string::npos)
        << r.out;
  }
  const std::string scene = write("frames.yaml",
                                  "simulation: { duration: 100 }\nvideo: { fps: 1e6 }\n"
                                  "bodies:\n  - { colliders: [ { shape: sphere, radius: 1 } ] }\n");
  const Result r = run("render " + scene + " -o " + tmp("f.mp4").string());
  EXPECT_EQ(r.code, 2) << r.out;
  EXPECT_NE(r.out.find("video.fps"), std::string::npos) << r.out;
}

// A CSV goes through symlinks (the link stays a link) and devices (/dev/null stays a device), and
// temp files of killed runs beside the target are cleaned up.
TEST(Cli, CsvTargetsSymlinksDevicesAndStaleTempFiles) {
  const std::string scene = write("g.yaml", kGood);
  const fs::path real = tmp("real.csv"), link = tmp("link.csv");
  fs::create_symlink(real, link);
  const fs::path stale = tmp("link.csv.partial-999999999");
  std::ofstream(stale) << "left by a killed run";
  ASSERT_EQ(run("simulate " + scene + " --quiet --csv " + link.string()).code, 0);
  EXPECT_TRUE(fs::is_symlink(link));
  EXPECT_GT(fs::file_size(real), 100u);
  ASSERT_EQ(run("simulate " + scene + " --quiet --csv /dev/null").code, 0);
  EXPECT_TRUE(fs::is_character_file("/dev/null")) << "/dev/null was replaced";
  const fs::path stale2 = tmp("x.csv.partial-999999999");
  std::ofstream(stale2) << "left by a killed run";
  ASSERT_EQ(run("simulate " + scene + " --quiet --csv " + tmp("x.csv").string()).code, 0);
  EXPECT_FALSE(fs::exists(stale2)) << "a dead process's temp file stays";
}

// Interrupts: the run stops between steps and finishes its outputs, whatever signals follow.
TEST(Cli, SignalsStopBetweenStepsAndFinishTheOutputs) {
  const std::string scene = write("long.yaml",
                                  "simulation: { duration: 600, timestep: 0.0001, gravity: [0, 0, 0] }\n"
                                  "video: { width: 160, height: 120, fps: 10 }\n"
                                  "bodies:\n  - angular_velocity: [0.1, 3, 0.1]\n"
                                  "    colliders: [ { shape: box, size: [3, 2, 1] } ]\n");
  auto start = [&](std::vector<std::string> argv) {
    const pid_t pid = fork();
    if (pid == 0) {
      const int devnull = open("/dev/null", O_WRONLY);
      dup2(devnull, 1);
      dup2(devnull, 2);
      std::vector<char*> c;
      c.push_back((char*)SIMREEL_BIN);
      for (std::string& s : argv) c.push_back(s.data());
      c.push_back(nullptr);
      execv(SIMREEL_BIN, c.data());
      _exit(99);
    }
    return pid;
  };
  auto wait_code = [](pid_t pid) {
    int st = 0;
    waitpid(pid, &st, 0);
    return WIFEXITED(st) ? WEXITSTATUS(st) : -WTERMSIG(st);
  };
  // simulate with a CSV: 130, the rows done kept, no temp file.
  const fs::path csv = tmp("int.csv");
  // Waits (up to 20 s: the machine may be loaded) until the run's temp file beside `target` exists,
  // then a little more: the run is stepping.
  auto wait_started = [](const fs::path& target, int then_ms) {
    for (int i = 0; i < 400; ++i) {
      for (const auto& e : fs::directory_iterator(target.parent_path()))
        if (e.path().filename().string().rfind(target.stem().string() + ".", 0) == 0 &&
            e.path().filename().string().find(".partial-") != std::string::npos) {
          std::this_thread::sleep_for(std::chrono::milliseconds(then_ms));
          return;
        }
      std::this_thread::sleep_for(std::chrono::milliseconds(50));
    }
  };
  pid_t pid = start({"simulate", scene, "--csv", csv.string(), "--quiet"});
  wait_started(csv, 300);
  kill(pid, SIGINT);
  kill(pid, SIGINT);
  EXPECT_EQ(wait_code(pid), 130);
  ASSERT_TRUE(fs::exists(csv));
  EXPECT_GT(fs::file_size(csv), 50u);
  // render, SIGINT then SIGTERM a few ms later while the video is being finished, then SIGHUP:
  // the first signal's code, a playable video, nothing temporary.
  for (int second_ms : {0, 5, 30}) {
    const fs::path out = tmp("int" + std::to_string(second_ms) + ".mp4");
    pid = start({"render", scene, "-o", out.string(), "--quiet"});
    wait_started(out, 500);
    kill(pid, SIGINT);
    std::this_thread::sleep_for(std::chrono::milliseconds(second_ms));
    kill(pid, SIGTERM);
    kill(pid, SIGHUP);
    const int code = wait_code(pid);
    if (second_ms == 0)  // sent together, either may be handled first: but one of them, not a kill
      EXPECT_TRUE(code == 130 || code == 143 || code == 129) << code;
    else
      EXPECT_EQ(code, 130) << second_ms;
    ASSERT_TRUE(fs::exists(out)) << second_ms;
    EXPECT_GT(simreel::test::decode(out.string()).frames, 0);
  }
  // A GIF is encoded after the last frame (its palette needs them all): interrupted, and again
  // while it is being encoded, it is still finished.
  const fs::path gif = tmp("int.gif");
  pid = start({"render", scene, "-o", gif.string(), "--quiet"});
  wait_started(gif, 500);
  kill(pid, SIGINT);
  std::this_thread::sleep_for(std::chrono::milliseconds(20));
  kill(pid, SIGTERM);
  // (On a loaded machine the process may not run between the two kills: both are then pending and
  // either can be the first it sees.)
  const int gif_code = wait_code(pid);
  EXPECT_TRUE(gif_code == 130 || gif_code == 143) << gif_code;
  ASSERT_TRUE(fs::exists(gif));
  EXPECT_GT(simreel::test::decode(gif.string()).frames, 0);
  pid = start({"render", scene, "-o", tmp("hup.mp4").string(), "--quiet"});
  wait_started(tmp("hup.mp4"), 500);
  kill(pid, SIGHUP);
  EXPECT_EQ(wait_code(pid), 129);
  EXPECT_TRUE(fs::exists(tmp("hup.mp4")));
  for (const auto& e : fs::directory_iterator(simreel::test::scratch_dir()))
    EXPECT_EQ(e.path().filename().string().find(".partial"), std::string::npos) << e.path();
}

// Hostile meshes give exit 2 and a message naming the file, from `inspect` and through a
// scene; never a crash (the PLY headers below used to kill every command inside assimp).
TEST(Cli, HostileMeshesExitWith2AndSayWhy) {
  const std::string dup = "tests/data/hostile/ply_duplicate_property.ply";
  const fs::path glb = tmp("dup.glb");
  fs::copy_file(dup, glb);
  for (const std::string& f :
       {dup, glb.string(), std::string("tests/data/hostile/ply_nameless_property.ply")}) {
    const Result r = run("inspect " + f);
    EXPECT_EQ(r.code, 2) << r.out;
    EXPECT_NE(r.out.find("error: " + f + ":"), std::string::npos) << r.out;
  }
  const std::string scene = write(
      "ply.yaml", "bodies:\n  - colliders: [{ shape: mesh, file: " + fs::absolute(dup).string() + " }]\n");
  const Result s = run("simulate " + scene + " --quiet");
  EXPECT_EQ(s.code, 2) << s.out;
  EXPECT_NE(s.out.find("second property named 'x'"), std::string::npos) << s.out;
  // Shell mode at 1e80 used to exit 0 with "mass": null.
  const Result shell = run("inspect tests/data/hostile/tetra_1e80.off --mode shell --json");
  EXPECT_EQ(shell.code, 2) << shell.out;
  EXPECT_NE(shell.out.find("would overflow double precision"), std::string::npos) << shell.out;
  // A directory or a FIFO is not a missing file (and a FIFO is never opened: that would block).
  const fs::path fifo = tmp("f.off");
  ASSERT_EQ(mkfifo(fifo.c_str(), 0600), 0);
  const Result ff = run("inspect " + fifo.string());
  EXPECT_EQ(ff.code, 2);
  EXPECT_NE(ff.out.find("is not a regular file"), std::string::npos) << ff.out;
  const Result dd = run("inspect " + tmp("").string());
  EXPECT_EQ(dd.code, 2);
  EXPECT_NE(dd.out.find("is a directory"), std::string::npos) << dd.out;
}

// A mesh's note is printed once (it was printed as a note, then again as a warning in the
// summary); the JSON summary carries it under "notes".
TEST(Cli, MeshNotesArePrintedOnce) {
  const Result r = run("simulate scenes/composite.yaml --duration 0.05");
  ASSERT_EQ(r.code, 0) << r.out;
  const std::string note = "(assets/torus.obj): the mesh is not convex";
  const size_t first = r.out.find(note);
  ASSERT_NE(first, std::string::npos) << r.out;
  EXPECT_EQ(r.out.find(note, first + 1), std::string::npos) << "printed twice:\n" << r.out;
  const Result j = run("simulate scenes/composite.yaml --duration 0.05 --json 2>/dev/null");
  const nlohmann::json o = json_of(j.out);
  ASSERT_TRUE(o.is_object()) << j.out;
  EXPECT_EQ(o["notes"].size(), 2u) << j.out;
  EXPECT_EQ(o["warnings"].size(), 0u) << j.out;
}

// camera: { auto: true } frames bodies the default camera never sees; a render whose frames show
// no body (a 100 m box, metres by mistake, with the camera inside it) says so.
TEST(Cli, AutoCameraFramesTheSceneAndEmptyFramesAreWarned) {
  const std::string far =
      "simulation: { duration: 1, timestep: 0.01 }\nvideo: { width: 64, height: 48, fps: 10 }\n"
      "bodies:\n  - { name: ball, position: [60, 40, 10], linear_velocity: [3, 0, 5],\n"
      "      colliders: [ { shape: sphere, radius: 0.2 } ] }\n";
  Result r = run("render " + write("far.yaml", far) + " -o " + tmp("far.mp4").string());
  EXPECT_EQ(r.code, 0) << r.out;
  EXPECT_NE(r.out.find("11 of 11 frames show no body"), std::string::npos) << r.out;
  r = run("render " + write("auto.yaml", far + "camera: { auto: true }\n") + " -o " +
          tmp("auto.mp4").string());
  EXPECT_EQ(r.code, 0) << r.out;
  EXPECT_NE(r.out.find("camera.auto: looking at"), std::string::npos) << r.out;
  EXPECT_EQ(r.out.find("show no body"), std::string::npos) << r.out;
  // The fitted frame shows the ball: many pixels differ from the empty sky of the first render.
  ASSERT_EQ(run("render " + write("auto.yaml", far + "camera: { auto: true }\n") + " --at 0.5 -o " +
                tmp("a.png").string())
                .code,
            0);
  ASSERT_EQ(run("render " + write("far.yaml", far) + " --at 0.5 -o " + tmp("f.png").string()).code, 0);
  EXPECT_NE(slurp(tmp("a.png")), slurp(tmp("f.png")));
  r = run("render " +
          write("big.yaml",
                "simulation: { duration: 1, timestep: 0.01, gravity: [0, 0, 0] }\n"
                "video: { width: 64, height: 48, fps: 10 }\n"
                "bodies:\n  - { name: crate, colliders: [ { shape: box, size: [100, 100, 100] } ] }\n") +
          " -o " + tmp("big.mp4").string());
  EXPECT_NE(r.out.find("the camera is inside body 'crate'"), std::string::npos) << r.out;
}

// A missing mesh lists the absolute paths tried, each once.
TEST(Cli, MissingMeshListsAbsolutePathsOnce) {
  const Result r =
      run("simulate " +
          write("miss.yaml", "bodies:\n  - colliders: [ { shape: mesh, file: missing_part.stl } ]\n"));
  EXPECT_EQ(r.code, 2);
  const size_t a = r.out.find("looked in "), b = r.out.find(')', a);
  ASSERT_NE(a, std::string::npos) << r.out;
  std::vector<std::string> paths;
  std::stringstream list(r.out.substr(a + 10, b - a - 10));
  for (std::string p; std::getline(list, p, ',');) paths.push_back(p.substr(p.find_first_not_of(' ')));
  EXPECT_GE(paths.size(), 2u) << r.out;
  for (size_t i = 0; i < paths.size(); ++i) {
    EXPECT_TRUE(fs::path(paths[i]).is_absolute()) << paths[i];
    for (size_t j = 0; j < i; ++j) EXPECT_NE(paths[i], paths[j]);
  }
}

// Frame sizes the encoder cannot take are refused before rendering: exit 2, nothing written.
TEST(Cli, CodecLimitsAreCheckedUpFront) {
  const std::string scene = write("g.yaml", kGood);
  const auto t0 = std::chrono::steady_clock::now();
  const Result r = run("render " + scene + " --width 16384 --height 16384 -o " + tmp("huge.mp4").string());
  EXPECT_EQ(r.code, 2) << r.out;
  EXPECT_NE(r.out.find("H.264 cannot encode 16384x16384"), std::string::npos) << r.out;
  EXPECT_LT(std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count(), 2.0);
  EXPECT_FALSE(fs::exists(tmp("huge.mp4")));
}

}  // namespace
