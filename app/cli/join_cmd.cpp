// simreel join: the segments `render --chunk` left in a folder, joined into the whole clip without
// re-encoding (render/segment_join.hpp); a GIF's chunks (lossless PNG frames) get one palette here.
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <map>
#include <optional>
#include <regex>

#include <nlohmann/json.hpp>
#include <simreel/error.hpp>
#include "app/cli/chunks.hpp"
#include "app/cli/cli.hpp"
#include "app/cli/commands.hpp"
#include "app/regress/image.hpp"
#include "app/scene/text.hpp"
#include "render/segment_join.hpp"
#include "render/video_writer.hpp"

namespace simreel {

namespace {

namespace fs = std::filesystem;

struct JoinOptions {
  std::vector<std::string> dirs;
  std::optional<std::string> out, name;
  std::optional<int> gif_width;
  std::optional<double> gif_fps;
  bool json = false, quiet = false;
};

void join_table(CLI::App& app, JoinOptions& o) {
  cli::setup(
      app, "join",
      "Joins the chunks `simreel render --chunk I/N -o DIR/` wrote into one clip. Checks first that every "
      "chunk is there and complete, that all were rendered from the same scene, input files, settings "
      "and simreel version (their manifest), that their frames follow one another without a gap or an "
      "overlap, and that their codec parameters match; then copies the packets as they are (no "
      "re-encoding, timestamps untouched, +faststart for .mp4 and .mov): the straight render's packet "
      "timing and keyframe cadence. A .gif is made from chunks rendered with -o DIR/NAME.gif (lossless "
      "frames), with one palette for the clip.",
      "Exit codes: 0 joined, 2 a chunk missing, incomplete or not matching the others (each named).");
  cli::add_positionals(app, o.dirs);
  app.add_option("-o", o.out, "the clip: .mp4, .mov, .mkv, .webm (packets copied) or .gif")->type_name("OUT");
  app.add_option("--name", o.name,
                 "the chunks' name (NAME.chunk-I-of-N.*) when the folder holds chunks of more than one clip")
      ->type_name("NAME");
  app.add_option("--gif-width", o.gif_width, "with a .gif: its width, scaled with a Lanczos filter")
      ->type_name("W")
      ->transform(cli::whole(16, 16384));
  app.add_option("--gif-fps", o.gif_fps, "with a .gif: its frame rate, at most the video's and 50")
      ->type_name("F")
      ->check(cli::positive());
  app.add_flag("--json", o.json, "print the result as one JSON object");
  app.add_flag("--quiet", o.quiet, "print nothing but errors");
}

}  // namespace

int cmd_join(const std::vector<std::string>& args) {
  JoinOptions o;
  CLI::App app;
  join_table(app, o);
  if (!cli::parse(app, args)) return kExitOk;
  if (o.dirs.empty()) throw UsageError("join takes the folder of the chunks (or several folders)");
  if (!o.out) throw UsageError("join needs -o OUT (.mp4, .mov, .mkv, .webm or .gif)");
  // The folders, for messages: "parts" or "parts/0, parts/1, ...".
  std::string dir;
  for (const std::string& d : o.dirs) dir += (dir.empty() ? "" : ", ") + d;
  const std::string out = *o.out, ext = lower_extension(out);
  const std::vector<std::string> exts = {".mp4", ".mov", ".mkv", ".webm", ".gif"};
  if (std::find(exts.begin(), exts.end(), ext) == exts.end())
    throw UsageError("-o '" + out + "' must end in .mp4, .mov, .mkv, .webm or .gif");
  const bool gif = ext == ".gif";
  if ((o.gif_width || o.gif_fps) && !gif)
    throw UsageError("--gif-width and --gif-fps apply to a .gif output");
  std::error_code ec;
  for (const std::string& d : o.dirs)
    if (!fs::is_directory(d, ec)) throw InputError(d + ": no such folder");

  // The records, grouped by clip: NAME.chunk-I-of-N.json.
  const std::regex pat(R"((.+)\.chunk-(\d+)-of-(\d+)\.json)");
  std::map<std::string, std::vector<fs::path>> clips;
  for (const std::string& d : o.dirs)
    for (const auto& e : fs::directory_iterator(d, ec)) {
      std::smatch m;
      const std::string f = e.path().filename().string();
      if (std::regex_match(f, m, pat)) clips[m[1].str()].push_back(e.path());
    }
  if (o.name) {
    const auto it = clips.find(*o.name);
    if (it == clips.end()) throw InputError(dir + ": no chunks named " + *o.name + ".chunk-*");
    clips = {*it};
  }
  if (clips.empty())
    throw InputError(dir + ": no chunks (NAME.chunk-I-of-N.json, written by simreel render --chunk I/N -o " +
                     dir + "/ when a chunk is complete)");
  if (clips.size() > 1) {
    std::string names;
    for (const auto& [n, f] : clips) names += (names.empty() ? "" : ", ") + n;
    throw UsageError(dir + " holds chunks of more than one clip (" + names + "): choose one with --name");
  }
  const std::string name = clips.begin()->first;
  std::vector<ChunkRecord> recs;
  for (const fs::path& p : clips.begin()->second) recs.push_back(read_chunk_record(p.string()));
  std::sort(recs.begin(), recs.end(), [](const ChunkRecord& a, const ChunkRecord& b) {
    return a.chunks != b.chunks ? a.chunks < b.chunks : a.index < b.index;
  });
  const ChunkRecord& r0 = recs.front();
  for (const ChunkRecord& r : recs) {
    if (r.chunks != r0.chunks)
      throw InputError(dir + ": chunks of a split into " + std::to_string(r0.chunks) +
                       " and of a split into " + std::to_string(r.chunks) + " are both here: remove one set");
    if (r.manifest != r0.manifest)
      throw InputError(dir + ": chunk " + std::to_string(r.index) +
                       " was rendered from another scene, input file, "
                       "setting or simreel version than chunk " +
                       std::to_string(r0.index) + " (manifest " + r.manifest + ", not " + r0.manifest +
                       "): render it again");
    if (r.kind != r0.kind || r.total_frames != r0.total_frames || r.keyint != r0.keyint || r.fps != r0.fps)
      throw InputError(dir + ": chunk " + std::to_string(r.index) +
                       " is of another kind or clip than chunk " + std::to_string(r0.index));
  }
  // Every chunk, once: name the missing ones with their frames and the command that makes each.
  std::vector<char> have((size_t)r0.chunks, 0);
  for (const ChunkRecord& r : recs) {
    if (r.index < 0 || r.index >= r0.chunks || have[(size_t)r.index])
      throw InputError(dir + ": chunk " + std::to_string(r.index) + " recorded twice or out of range");
    have[(size_t)r.index] = 1;
  }
  const std::vector<ChunkSpan> table = chunk_table(r0.total_frames, r0.keyint, r0.chunks);
  std::string missing;
  int nmissing = 0;
  for (int i = 0; i < r0.chunks; ++i)
    if (!have[(size_t)i]) {
      ++nmissing;
      std::string cmd = r0.command;
      const std::string id = std::to_string(i) + "/" + std::to_string(r0.chunks);
      if (const size_t at = cmd.find("{}"); at != std::string::npos) cmd.replace(at, 2, id);
      if (cmd.empty()) cmd = "simreel render " + r0.scene + " --chunk " + id + " -o " + o.dirs[0] + "/";
      missing += "\n  chunk " + std::to_string(i) + " (frames " + std::to_string(table[(size_t)i].first) +
                 " to " + std::to_string(table[(size_t)i].last) + "): " + cmd;
    }
  if (nmissing)
    throw InputError(dir + ": " + std::to_string(nmissing) + " of " + std::to_string(r0.chunks) +
                     " chunks missing or incomplete (a chunk's record is written only when its segment is "
                     "complete):" +
                     missing);
  for (size_t i = 0; i < recs.size(); ++i) {
    const long expect = i == 0 ? 0 : recs[i - 1].last + 1;
    if (recs[i].first != expect || recs[i].last < recs[i].first)
      throw InputError(dir + ": chunk " + std::to_string(recs[i].index) + " holds frames " +
                       std::to_string(recs[i].first) + " to " + std::to_string(recs[i].last) + ", not from " +
                       std::to_string(expect) + " on");
  }
  if (recs.back().last != r0.total_frames - 1)
    throw InputError(dir + ": the chunks end at frame " + std::to_string(recs.back().last) + " of " +
                     std::to_string(r0.total_frames));
  if (r0.kind == "none")
    throw UsageError(dir +
                     ": these chunks were rendered with --no-video (PNG frames only, in their --frames-dir): "
                     "there is no video to join");
  if (gif != (r0.kind == "frames"))
    throw UsageError(gif ? dir + ": a GIF is made from lossless chunks: render them with -o " + o.dirs[0] +
                               "/" + name + ".gif (PNG frames), not " + r0.kind + " segments"
                         : dir +
                               ": these chunks are PNG frames for a GIF: join them with -o NAME.gif, or "
                               "render the chunks with -o " +
                               dir + "/ for a video");
  std::string err;
  if (!ensure_parent_dir(out, &err)) throw std::runtime_error(err);
  remove_stale_partials(out);

  const auto t0 = std::chrono::steady_clock::now();
  long packets = 0;
  double duration = 0;
  if (!gif) {
    std::vector<JoinSegment> segs;
    for (const ChunkRecord& r : recs)
      segs.push_back({(fs::path(r.folder) / r.segment).string(), r.first, r.last});
    const JoinResult jr = join_segments(segs, r0.fps, out);
    packets = jr.packets;
    duration = jr.duration;
  } else {
    VideoSettings vs;
    vs.path = out;
    vs.width = r0.width;
    vs.height = r0.height;
    vs.fps = r0.fps;
    if (o.gif_width) {
      if (*o.gif_width > r0.width)
        throw UsageError("--gif-width " + std::to_string(*o.gif_width) + " is wider than the frames (" +
                         std::to_string(r0.width) + " px)");
      vs.gif_width = *o.gif_width;
    }
    if (o.gif_fps) {
      if (*o.gif_fps > 50 || *o.gif_fps > r0.fps * (1 + 1e-12))
        throw UsageError("--gif-fps is at most 50 and at most the video's frame rate");
      vs.gif_fps = *o.gif_fps;
    }
    VideoWriter writer(vs);
    for (const ChunkRecord& r : recs)
      for (long k = r.first; k <= r.last; ++k) {
        char f[32];
        std::snprintf(f, sizeof f, "frame_%05ld.png", k);
        const fs::path p = fs::path(r.folder) / r.segment / f;
        const Image img = read_png(p.string());
        if (img.width != r0.width || img.height != r0.height)
          throw InputError(p.string() + ": " + std::to_string(img.width) + "x" + std::to_string(img.height) +
                           ", not the chunks' " + std::to_string(r0.width) + "x" + std::to_string(r0.height));
        writer.push(img.rgba.data(), k);
      }
    writer.finish();
    packets = writer.frames();
    duration = (double)r0.total_frames / r0.fps;
  }
  const double secs = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  if (o.json) {
    nlohmann::json j;
    j["output"] = out;
    j["chunks"] = r0.chunks;
    j["frames"] = r0.total_frames;
    j["packets"] = packets;
    j["duration"] = duration;
    j["seconds"] = secs;
    j["reencoded"] = gif;
    std::printf("%s\n", j.dump().c_str());
  } else if (!o.quiet) {
    std::printf("joined %d chunks of %s, %ld frames (%.3f s of video), into %s in %.2f s (%s)\n", r0.chunks,
                name.c_str(), r0.total_frames, duration, out.c_str(), secs,
                gif ? "one palette for the clip" : "packets copied, no re-encoding");
  }
  return kExitOk;
}

}  // namespace simreel
