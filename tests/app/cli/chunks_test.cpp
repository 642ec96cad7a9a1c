// A render split into chunks, run by GNU parallel, joined, and held to the straight render: every
// packet's timestamps equal, at --crf 0 every decoded frame equal, at the default quality within the
// straight render's own error to the PNG frames; scenes with what a chunk cannot make alone (a trail,
// a plot, a measured period, auto-scaled arrows, an automatic camera) give the same frames chunked,
// with and without checkpoints. (app/cli/chunks.hpp, render/segment_join.hpp)
#include <gtest/gtest.h>

extern "C" {
#include <libavformat/avformat.h>
}

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <regex>
#include <thread>

#include "app/cli/chunks.hpp"
#include "app/cli/commands.hpp"
#include "app/cli/video_frames.hpp"
#include "app/regress/image.hpp"
#include "tests/cli_run.hpp"
#include "tests/scratch.hpp"

namespace simreel {
namespace {

namespace fs = std::filesystem;
using test::run;
using test::scratch;
using test::slurp;

const std::string kBoxes = "tests/data/chunks/boxes.yaml";             // 51 frames, 3 keyframe intervals
const std::string kPendulum = "tests/data/chunks/pendulum_plot.yaml";  // the same, with overlays

// A shell command's exit code and output (stdout and stderr).
test::Result sh(const std::string& cmd) {
  return test::shell(cmd);
}

bool have(const std::string& tool) {
  return std::system(("command -v " + tool + " >/dev/null 2>&1").c_str()) == 0;
}

struct Packet {
  int64_t pts, dts;
  bool key;
  int size;
  bool operator==(const Packet& o) const { return pts == o.pts && dts == o.dts && key == o.key; }
};

// Every video packet of a file, in file order.
std::vector<Packet> packets(const std::string& path) {
  AVFormatContext* f = nullptr;
  std::vector<Packet> out;
  if (avformat_open_input(&f, path.c_str(), nullptr, nullptr) < 0) return out;
  avformat_find_stream_info(f, nullptr);
  const int s = av_find_best_stream(f, AVMEDIA_TYPE_VIDEO, -1, -1, nullptr, 0);
  AVPacket* p = av_packet_alloc();
  while (s >= 0 && av_read_frame(f, p) >= 0) {
    if (p->stream_index == s) out.push_back({p->pts, p->dts, (p->flags & AV_PKT_FLAG_KEY) != 0, p->size});
    av_packet_unref(p);
  }
  av_packet_free(&p);
  avformat_close_input(&f);
  return out;
}

// Mean squared error (per RGB sample, 0-255) of a video's decoded frames to the PNG frames it was
// encoded from; frames matched in order.
double mse_to_frames(const std::string& video, const std::string& dir, long frames) {
  VideoFrames v(video);
  Image img;
  double t = 0, sum = 0;
  long k = 0, n = 0;
  while (v.next(img, t)) {
    char name[32];
    std::snprintf(name, sizeof name, "frame_%05ld.png", k++);
    const Image ref = read_png((fs::path(dir) / name).string());
    for (size_t i = 0; i < ref.rgba.size(); ++i) {
      if (i % 4 == 3) continue;
      const double d = (double)img.rgba[i] - ref.rgba[i];
      sum += d * d, ++n;
    }
  }
  EXPECT_EQ(k, frames) << video;
  return n ? sum / n : 1e9;
}

// The PNG frames of two folders: the same names, byte for byte.
void expect_same_frames(const std::string& a, const std::string& b, long frames) {
  for (long k = 0; k < frames; ++k) {
    char name[32];
    std::snprintf(name, sizeof name, "frame_%05ld.png", k);
    const std::string x = slurp(fs::path(a) / name), y = slurp(fs::path(b) / name);
    ASSERT_FALSE(x.empty()) << a << "/" << name;
    EXPECT_TRUE(x == y) << name << " differs between " << a << " and " << b;
  }
}

// GNU parallel running the chunks, two at a time, failing fast; `extra` goes to every render.
test::Result parallel_chunks(const std::string& scene, int n, const std::string& extra) {
  std::string ids;
  for (int i = 0; i < n; ++i) ids += " " + std::to_string(i);
  return sh("parallel -j2 --halt now,fail=1 " + std::string(SIMREEL_BIN) + " render " + scene +
            " --chunk {}/" + std::to_string(n) + " --quiet " + extra + " :::" + ids);
}

TEST(ChunkTable, ChunksStartOnKeyframes) {
  const auto t = chunk_table(51, 20, 3);
  ASSERT_EQ(t.size(), 3u);
  EXPECT_EQ(t[0].first, 0);
  EXPECT_EQ(t[0].last, 19);
  EXPECT_EQ(t[1].first, 20);
  EXPECT_EQ(t[1].last, 39);
  EXPECT_EQ(t[2].first, 40);
  EXPECT_EQ(t[2].last, 50);
  // pile.yaml: 181 frames at 30 fps, a keyframe every 60: 4 intervals, the last of one frame.
  const auto p = chunk_table(181, 60, 2);
  EXPECT_EQ(p[0].last, 119);
  EXPECT_EQ(p[1].first, 120);
  EXPECT_EQ(p[1].last, 180);
  for (const auto& c : chunk_table(1000, 60, 7)) EXPECT_EQ(c.first % 60, 0);
  try {
    chunk_table(51, 20, 4);
    FAIL() << "4 chunks of 3 intervals";
  } catch (const UsageError& e) {
    EXPECT_NE(std::string(e.what()).find("at most 3 chunks"), std::string::npos) << e.what();
  }
  EXPECT_EQ(keyframe_interval(30), 60);
  EXPECT_EQ(keyframe_interval(10), 20);
  EXPECT_EQ(parse_chunk_arg("2/3"), std::make_pair(2, 3));
  EXPECT_THROW(parse_chunk_arg("3/3"), UsageError);
  EXPECT_THROW(parse_chunk_arg("1-3"), UsageError);
  EXPECT_THROW(parse_chunk_arg("-1/3"), UsageError);
}

TEST(Chunks, PlanPrintsTheTableAndCommands) {
  const auto r = run("plan " + kBoxes + " --chunks 3 --json");
  ASSERT_EQ(r.code, 0) << r.out;
  EXPECT_NE(r.out.find("\"frames\":51"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("\"keyframe_interval\":20"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("--chunk 2/3"), std::string::npos) << r.out;
  const auto t = run("plan " + kBoxes + " --chunks 3 --width 320 --height 240");
  ASSERT_EQ(t.code, 0) << t.out;
  EXPECT_NE(t.out.find("40-50"), std::string::npos) << t.out;
  EXPECT_NE(t.out.find("--width 320 --height 240"), std::string::npos) << t.out;
  const auto bad = run("plan " + kBoxes + " --chunks 4");
  EXPECT_EQ(bad.code, 2);
  EXPECT_NE(bad.out.find("at most 3 chunks"), std::string::npos) << bad.out;
}

// GNU parallel, 3 chunks, lossless: the join is the straight render, packet for packet and pixel
// for pixel.
TEST(Chunks, ParallelJoinEqualsStraightAtCrf0) {
  ASSERT_TRUE(have("parallel")) << "GNU parallel is missing: .ci/setup installs it";
  const std::string d = scratch("");
  ASSERT_EQ(run("render " + kBoxes + " --crf 0 --quiet -o " + d + "straight.mp4").code, 0);
  const auto p = parallel_chunks(kBoxes, 3, "--crf 0 -o " + d + "parts/");
  ASSERT_EQ(p.code, 0) << p.out;
  const auto j = run("join " + d + "parts -o " + d + "joined.mp4");
  ASSERT_EQ(j.code, 0) << j.out;
  EXPECT_NE(j.out.find("joined 3 chunks of boxes, 51 frames (5.100 s of video)"), std::string::npos) << j.out;
  const auto a = packets(d + "straight.mp4"), b = packets(d + "joined.mp4");
  ASSERT_EQ(a.size(), 51u);
  ASSERT_EQ(b.size(), a.size());
  long keys = 0;
  for (size_t i = 0; i < a.size(); ++i) {
    EXPECT_EQ(a[i], b[i]) << "packet " << i << ": pts " << b[i].pts << " dts " << b[i].dts << " (straight "
                          << a[i].pts << ", " << a[i].dts << ")";
    keys += a[i].key;
  }
  EXPECT_GE(keys, 3);  // at 0, 20 and 40: where the chunks start
  const auto diff = run("diff " + d + "joined.mp4 " + d + "straight.mp4 --tolerance exact --quiet");
  EXPECT_EQ(diff.code, 0) << diff.out;
}

// At the default quality separate encodes differ a little; the join must be as close to the PNG
// frames as the straight render is. The chunks share one --frames-dir, each writing its own frames.
TEST(Chunks, DefaultQualityWithinTheStraightRendersError) {
  ASSERT_TRUE(have("parallel")) << "GNU parallel is missing: .ci/setup installs it";
  const std::string d = scratch("");
  ASSERT_EQ(run("render " + kBoxes + " --quiet -o " + d + "straight.mp4 --frames-dir " + d + "png").code, 0);
  const auto p = parallel_chunks(kBoxes, 3, "-o " + d + "parts/ --frames-dir " + d + "shared");
  ASSERT_EQ(p.code, 0) << p.out;
  expect_same_frames(d + "png", d + "shared", 51);
  ASSERT_EQ(run("join " + d + "parts -o " + d + "joined.mp4 --quiet").code, 0);
  const auto a = packets(d + "straight.mp4"), b = packets(d + "joined.mp4");
  ASSERT_EQ(a.size(), b.size());
  for (size_t i = 0; i < a.size(); ++i) EXPECT_EQ(a[i].pts, b[i].pts) << i;
  const double straight = mse_to_frames(d + "straight.mp4", d + "png", 51);
  const double joined = mse_to_frames(d + "joined.mp4", d + "png", 51);
  std::printf("MSE to the PNG frames: straight %.4f, joined %.4f\n", straight, joined);
  // Boundaries on keyframes add no keyframe; the encodes differ by x264's rate control and lookahead,
  // which cannot see across a boundary (measured here: MSE 6.76 against 6.45, 0.2 dB). 0.5 dB of
  // PSNR (MSE x 1.12) is what a viewer cannot see and what an extra keyframe a chunk would cost.
  EXPECT_LE(joined, straight * 1.12);
  // A second chunk run into the same folder refuses its own frames, not the others'.
  const auto again = run("render " + kBoxes + " --chunk 1/3 -o " + d + "parts/ --frames-dir " + d + "shared");
  EXPECT_EQ(again.code, 2);
  EXPECT_NE(again.out.find("already holds 20 of this chunk's frames"), std::string::npos) << again.out;
}

// A trail, a plot, a measured period, an auto-scaled arrow and camera.auto: the same frames in
// chunks as straight, from t = 0 in each chunk and from checkpoints.
TEST(Chunks, PlotTrailAndAutoCameraSameChunkedAsStraight) {
  ASSERT_TRUE(have("parallel")) << "GNU parallel is missing: .ci/setup installs it";
  const std::string d = scratch("");
  ASSERT_EQ(run("render " + kPendulum + " --no-video --quiet --frames-dir " + d + "straight").code, 0);
  auto p = parallel_chunks(kPendulum, 3, "-o " + d + "parts/ --no-video --frames-dir " + d + "replayed");
  ASSERT_EQ(p.code, 0) << p.out;
  expect_same_frames(d + "straight", d + "replayed", 51);
  const auto plan = run("plan " + kPendulum + " --chunks 3 --checkpoints " + d + "ck");
  ASSERT_EQ(plan.code, 0) << plan.out;
  EXPECT_NE(plan.out.find("checkpoints: "), std::string::npos) << plan.out;
  for (const char* f : {"plan.json", "prepass.bin", "chunk-1.state", "chunk-2.state"})
    EXPECT_TRUE(fs::exists(d + "ck/" + f)) << f;
  p = parallel_chunks(kPendulum, 3,
                      "-o " + d + "parts2/ --crf 0 --checkpoints " + d + "ck --frames-dir " + d + "resumed");
  ASSERT_EQ(p.code, 0) << p.out;
  expect_same_frames(d + "straight", d + "resumed", 51);
  // ... and the joined video is the straight one's.
  ASSERT_EQ(run("render " + kPendulum + " --crf 0 --quiet -o " + d + "straight.mp4").code, 0);
  ASSERT_EQ(run("join " + d + "parts2 -o " + d + "joined.mp4 --quiet").code, 0);
  EXPECT_EQ(run("diff " + d + "joined.mp4 " + d + "straight.mp4 --tolerance exact --quiet").code, 0);
}

// A scene rendered straight, then in 3 chunks from `plan --checkpoints` (each chunk resumed from its
// checkpoint, one after another): the same 51 frames.
void expect_checkpointed_chunks_equal_straight(const std::string& scene) {
  const std::string d = scratch("");
  ASSERT_EQ(run("render " + scene + " --no-video --quiet --frames-dir " + d + "straight").code, 0);
  ASSERT_EQ(run("plan " + scene + " --chunks 3 --quiet --checkpoints " + d + "ck").code, 0);
  for (int i = 0; i < 3; ++i) {
    const auto r = run("render " + scene + " --quiet --no-video --chunk " + std::to_string(i) +
                       "/3 --checkpoints " + d + "ck -o " + d + "parts/ --frames-dir " + d + "resumed");
    ASSERT_EQ(r.code, 0) << r.out;
  }
  expect_same_frames(d + "straight", d + "resumed", 51);
}

// A variant's world, a damped following camera, motion blur and trails in two panes: the same
// frames from checkpoints as straight.
TEST(Chunks, VariantsDampedFollowAndBlurSameFromCheckpoints) {
  expect_checkpointed_chunks_equal_straight("tests/data/chunks/variants_blur.yaml");
}

// Measured HUD values, snapshots, a system's arrows and an overlaid variant: the same frames from
// checkpoints as straight.
TEST(Chunks, MeasuredValuesSnapshotsAndOverlaidVariantsSameFromCheckpoints) {
  expect_checkpointed_chunks_equal_straight("tests/data/chunks/meters_snapshots.yaml");
}

// A GIF has one palette for the clip: chunks render lossless frames and join makes the palette.
TEST(Chunks, GifJoinedEqualsStraightGif) {
  const std::string d = scratch("");
  ASSERT_EQ(run("render " + kBoxes + " --quiet -o " + d + "straight.gif").code, 0);
  for (int i = 0; i < 3; ++i)
    ASSERT_EQ(
        run("render " + kBoxes + " --quiet --chunk " + std::to_string(i) + "/3 -o " + d + "g/clip.gif").code,
        0);
  const auto mp4 = run("join " + d + "g -o " + d + "joined.mp4");
  EXPECT_EQ(mp4.code, 2);
  EXPECT_NE(mp4.out.find("PNG frames for a GIF"), std::string::npos) << mp4.out;
  const auto j = run("join " + d + "g -o " + d + "joined.gif");
  ASSERT_EQ(j.code, 0) << j.out;
  EXPECT_TRUE(slurp(d + "straight.gif") == slurp(d + "joined.gif"))
      << "the joined GIF differs from the straight one";
}

// What join and a chunk refuse, each with the chunk named and what to do.
TEST(Chunks, MissingForeignAndStaleChunksAreRefused) {
  const std::string d = scratch("");
  ASSERT_EQ(run("render " + kBoxes + " --quiet --chunk 0/3 -o " + d + "parts/").code, 0);
  ASSERT_EQ(run("render " + kBoxes + " --quiet --chunk 2/3 -o " + d + "parts/").code, 0);
  auto j = run("join " + d + "parts -o " + d + "x.mp4");
  EXPECT_EQ(j.code, 2);
  EXPECT_NE(j.out.find("1 of 3 chunks missing"), std::string::npos) << j.out;
  // ... with the command that makes it: the others' options, its own I/N.
  EXPECT_NE(j.out.find("chunk 1 (frames 20 to 39): " + std::string(SIMREEL_BIN) + " render " + kBoxes +
                       " --quiet --chunk 1/3 -o " + d + "parts/"),
            std::string::npos)
      << j.out;
  EXPECT_FALSE(fs::exists(d + "x.mp4"));
  // Chunk 1 rendered at another timestep: another manifest.
  ASSERT_EQ(run("render " + kBoxes + " --quiet --chunk 1/3 --timestep 0.0025 -o " + d + "parts/").code, 0);
  j = run("join " + d + "parts -o " + d + "x.mp4");
  EXPECT_EQ(j.code, 2);
  EXPECT_NE(j.out.find("another scene, input file, setting or simreel version"), std::string::npos) << j.out;
  // Another encoder setting is not the manifest's business, but the packets cannot be copied.
  ASSERT_EQ(run("render " + kBoxes + " --quiet --chunk 1/3 --crf 30 -o " + d + "parts/").code, 0);
  j = run("join " + d + "parts -o " + d + "x.mp4");
  EXPECT_EQ(j.code, 2);
  EXPECT_NE(j.out.find("without re-encoding"), std::string::npos) << j.out;
  // A checkpoint of another setting is refused before anything runs.
  ASSERT_EQ(run("plan " + kBoxes + " --chunks 3 --quiet --checkpoints " + d + "ck").code, 0);
  auto r =
      run("render " + kBoxes + " --chunk 1/3 --timestep 0.0025 --checkpoints " + d + "ck -o " + d + "p2/");
  EXPECT_EQ(r.code, 2);
  EXPECT_NE(r.out.find("these checkpoints are of another scene"), std::string::npos) << r.out;
  r = run("render " + kBoxes + " --chunk 1/2 --checkpoints " + d + "ck -o " + d + "p2/");
  EXPECT_EQ(r.code, 2);
  EXPECT_NE(r.out.find("a split into 3 chunks"), std::string::npos) << r.out;
  // A failed chunk names itself and its frames.
  fs::remove(d + "ck/chunk-2.state");
  r = run("render " + kBoxes + " --chunk 2/3 --checkpoints " + d + "ck -o " + d + "p2/");
  EXPECT_EQ(r.code, 2);
  EXPECT_NE(r.out.find("chunk 2 of 3 (frames 40 to 50) failed"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("chunk-2.state: missing"), std::string::npos) << r.out;
}

// GNU parallel over --sshlogin, against an sshd started here on a loopback port (Debian's
// openssh-server); the chunks write to a folder both sides see.
TEST(Chunks, ParallelOverSshLoopback) {
  const std::string d = scratch("");
  const std::string sshd = fs::exists("/usr/sbin/sshd") ? "/usr/sbin/sshd" : "";
  if (sshd.empty() || !have("ssh") || !have("ssh-keygen") || !have("parallel"))
    GTEST_SKIP() << "no sshd, ssh or parallel here (Debian: openssh-server, openssh-client, parallel)";
  if (geteuid() != 0) GTEST_SKIP() << "sshd needs root to run here (privilege separation)";
  if (sh("ssh-keygen -q -t ed25519 -N '' -f " + d + "host && ssh-keygen -q -t ed25519 -N '' -f " + d +
         "user && cp " + d + "user.pub " + d + "authorized_keys && chmod 600 " + d + "authorized_keys")
          .code != 0)
    GTEST_SKIP() << "ssh-keygen failed";
  const int port = 20000 + getpid() % 20000;
  std::ofstream(d + "sshd_config")
      << "Port " << port << "\nListenAddress 127.0.0.1\nHostKey " << d << "host\nAuthorizedKeysFile " << d
      << "authorized_keys\nPidFile " << d
      << "sshd.pid\nPermitRootLogin prohibit-password\nPasswordAuthentication no\n"
         "UsePAM no\nStrictModes no\n";
  sh("mkdir -p /run/sshd");
  const auto start = sh(sshd + " -f " + d + "sshd_config -E " + d + "sshd.log");
  if (start.code != 0) GTEST_SKIP() << "sshd did not start: " << start.out;
  const std::string ssh =
      "ssh -i " + d + "user -p " + std::to_string(port) +
      " -o StrictHostKeyChecking=no -o UserKnownHostsFile=/dev/null -o LogLevel=ERROR -o BatchMode=yes";
  bool up = false;
  for (int i = 0; i < 50 && !up; ++i) {
    up = sh(ssh + " 127.0.0.1 true").code == 0;
    if (!up) std::this_thread::sleep_for(std::chrono::milliseconds(100));
  }
  const std::string pid = slurp(d + "sshd.pid");
  if (!up) {
    if (!pid.empty()) sh("kill " + pid);
    GTEST_SKIP() << "sshd started but takes no login: " << slurp(d + "sshd.log");
  }
  // A shared file system: the remote side works in this folder, the chunks land where join reads.
  const std::string cwd = fs::current_path().string();
  const auto p = sh("parallel --ssh '" + ssh + "' -S 2/127.0.0.1 --workdir " + cwd + " --halt now,fail=1 " +
                    std::string(SIMREEL_BIN) + " render " + kBoxes + " --chunk {}/3 --crf 0 --quiet -o " + d +
                    "parts/ ::: 0 1 2");
  // None: the scene goes out (--basefile) and is removed after (--cleanup), each chunk's folder comes
  // back (--return); the remote side works in a folder of its own.
  fs::create_directories(d + "local");
  fs::copy_file(kBoxes, d + "local/boxes.yaml");
  const auto q =
      sh("cd " + d + "local && parallel --ssh '" + ssh + "' -S 2/127.0.0.1 --workdir " + d +
         "remote --basefile boxes.yaml --return parts/{}/ --cleanup --halt now,fail=1 " +
         std::string(SIMREEL_BIN) + " render boxes.yaml --chunk {}/3 --crf 0 --quiet -o parts/{}/ ::: 0 1 2");
  sh("kill " + pid);
  ASSERT_EQ(p.code, 0) << p.out;
  ASSERT_EQ(run("join " + d + "parts -o " + d + "joined.mp4 --quiet").code, 0);
  ASSERT_EQ(run("render " + kBoxes + " --crf 0 --quiet -o " + d + "straight.mp4").code, 0);
  EXPECT_EQ(run("diff " + d + "joined.mp4 " + d + "straight.mp4 --tolerance exact --quiet").code, 0);
  ASSERT_EQ(q.code, 0) << q.out;
  EXPECT_FALSE(fs::exists(d + "remote/boxes.yaml")) << "--cleanup left the scene sent";
  const auto j = run("join " + d + "local/parts/0 " + d + "local/parts/1 " + d + "local/parts/2 -o " + d +
                     "joined2.mp4 --quiet");
  ASSERT_EQ(j.code, 0) << j.out;
  EXPECT_EQ(run("diff " + d + "joined2.mp4 " + d + "straight.mp4 --tolerance exact --quiet").code, 0);
}

}  // namespace
}  // namespace simreel
