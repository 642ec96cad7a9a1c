#include "app/cli/chunks.hpp"

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>

#include <nlohmann/json.hpp>
#include <simreel/error.hpp>

#include "app/cli/commands.hpp"
#include "app/cli/goldens.hpp"
#include "app/scene/text.hpp"
#include "app/view/view_state.hpp"
#include "sim/base/hash.hpp"

namespace simreel {

using nlohmann::json;

std::vector<ChunkSpan> chunk_table(long frames, long keyint, int n) {
  if (frames < 1) throw UsageError("the clip has no frames to split");
  const long intervals = (frames + keyint - 1) / keyint;
  if (n < 1 || n > intervals)
    throw UsageError("cannot split " + std::to_string(frames) + " frames into " + std::to_string(n) +
                     " chunks: chunks start on keyframes, one every " + std::to_string(keyint) +
                     " frames, so at most " + std::to_string(intervals) + " chunks");
  std::vector<ChunkSpan> out;
  for (int i = 0; i < n; ++i) {
    // Interval i*intervals/n onwards: the chunks differ by at most one interval.
    const long a = (long)i * intervals / n, b = (long)(i + 1) * intervals / n;
    out.push_back({i, a * keyint, std::min(frames, b * keyint) - 1});
  }
  return out;
}

std::pair<int, int> parse_chunk_arg(const std::string& s) {
  const size_t slash = s.find('/');
  int i = -1, n = -1;
  try {
    size_t pi = 0, pn = 0;
    if (slash != std::string::npos) {
      i = std::stoi(s.substr(0, slash), &pi);
      n = std::stoi(s.substr(slash + 1), &pn);
    }
    if (slash == std::string::npos || pi != slash || pn != s.size() - slash - 1) i = -1;
  } catch (const std::exception&) {
    i = -1;
  }
  if (i < 0 || n < 1)
    throw UsageError("--chunk '" + s + "': give I/N, chunk I of N, I from 0 to N-1 (as SLURM_ARRAY_TASK_ID)");
  if (i >= n)
    throw UsageError("--chunk " + s + ": chunks are numbered 0 to " + std::to_string(n - 1) +
                     " (as SLURM_ARRAY_TASK_ID counts them)");
  return {i, n};
}

ChunkManifest chunk_manifest(const std::string& scene_path, const Scene& scene, const std::string& look) {
  ChunkManifest m;
  m.scene = scene_path;
  m.scene_hash = file_hash(scene_path);
  for (const std::string& f : scene.inputs) {
    std::error_code ec;
    std::string rel =
        std::filesystem::relative(f, std::filesystem::path(scene_path).parent_path(), ec).generic_string();
    if (ec || rel.empty()) rel = f;
    m.inputs[rel] = file_hash(f);
  }
  // The values in effect, so that `--duration 5` on a scene of 5 s is the same run.
  char buf[512];
  std::snprintf(buf, sizeof buf, "duration=%.17g timestep=%.17g integrator=%s fps=%.17g width=%d height=%d",
                scene.duration, scene.timestep, to_string(scene.integrator), scene.video.fps,
                scene.video.width + scene.video.width % 2, scene.video.height + scene.video.height % 2);
  m.settings = buf;
  if (!look.empty()) m.settings += " " + look;
  m.version = kVersion;
  std::string all = m.scene_hash + "\n" + m.settings + "\n" + m.version + "\n";
  for (const auto& [f, h] : m.inputs) all += f + "=" + h + "\n";
  uint64_t h = fnv1a(1469598103934665603ull, all.data(), all.size());
  std::snprintf(buf, sizeof buf, "%016llx", (unsigned long long)h);
  m.id = buf;
  return m;
}

std::string look_settings(const std::optional<std::string>& aa, bool no_shadows) {
  std::string s;
  if (aa) s += "aa=" + *aa;
  if (no_shadows) s += std::string(s.empty() ? "" : " ") + "shadows=off";
  return s;
}

void write_checkpoint_plan(const std::string& dir, const CheckpointPlan& p) {
  json j;
  j["manifest"] = p.manifest;
  j["chunks"] = p.chunks;
  j["total_frames"] = p.total_frames;
  if (p.fitted) {
    j["camera"]["position"] = {p.position[0], p.position[1], p.position[2]};
    j["camera"]["look_at"] = {p.look_at[0], p.look_at[1], p.look_at[2]};
  }
  const std::string path = (std::filesystem::path(dir) / "plan.json").string();
  AtomicFile f(path);
  const std::string text = j.dump(2) + "\n";
  if (std::fwrite(text.data(), 1, text.size(), f.get()) != text.size())
    throw std::runtime_error(path + ": could not write");
  f.commit();
}

CheckpointPlan read_checkpoint_plan(const std::string& dir) {
  const std::string path = (std::filesystem::path(dir) / "plan.json").string();
  std::ifstream in(path);
  if (!in)
    throw InputError(
        path + ": no checkpoint plan here (made by simreel plan SCENE --chunks N --checkpoints " + dir + ")");
  CheckpointPlan p;
  try {
    const json j = json::parse(in);
    p.manifest = j.at("manifest").get<std::string>();
    p.chunks = j.at("chunks").get<int>();
    p.total_frames = j.at("total_frames").get<long>();
    if (j.contains("camera")) {
      p.fitted = true;
      for (int k = 0; k < 3; ++k) {
        p.position[k] = j.at("camera").at("position").at(k).get<double>();
        p.look_at[k] = j.at("camera").at("look_at").at(k).get<double>();
      }
    }
  } catch (const json::exception& e) {
    throw InputError(path + ": not a checkpoint plan written by simreel plan (" + e.what() + ")");
  }
  return p;
}

namespace {

constexpr char kCheckpointMagic[] = "simreel checkpoint 1\n";

size_t write_checkpoint_file(const std::string& path, const std::string& manifest, const std::string& body) {
  std::ostringstream os;
  os.write(kCheckpointMagic, sizeof kCheckpointMagic - 1);
  put_str(os, manifest);
  const std::string bytes = os.str() + body;
  AtomicFile f(path);
  if (std::fwrite(bytes.data(), 1, bytes.size(), f.get()) != bytes.size())
    throw std::runtime_error(path + ": could not write the checkpoint");
  f.commit();
  return bytes.size();
}

// Opens a checkpoint file and reads past its mark and manifest, which must be `manifest`.
std::ifstream open_checkpoint_file(const std::string& path, const std::string& manifest,
                                   const char* missing) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError(path + ": " + missing);
  std::string magic(sizeof kCheckpointMagic - 1, '\0');
  in.read(magic.data(), (std::streamsize)magic.size());
  if (!in || magic != kCheckpointMagic) throw InputError(path + ": not a checkpoint written by simreel plan");
  std::string id;
  get_str(in, id);
  if (id != manifest)
    throw InputError(path + ": a checkpoint of another scene, input, setting or version (manifest " + id +
                     ", this chunk's " + manifest + ")");
  return in;
}

std::string state_path(const std::string& dir, int index) {
  return (std::filesystem::path(dir) / ("chunk-" + std::to_string(index) + ".state")).string();
}

}  // namespace

size_t write_checkpoint_state(const std::string& dir, const std::string& manifest, const CheckpointState& s) {
  std::ostringstream os;
  put(os, (int32_t)s.index);
  put(os, (int64_t)s.frame);
  put(os, (int64_t)s.step);
  put_str(os, s.world);
  put_str(os, s.history);
  return write_checkpoint_file(state_path(dir, s.index), manifest, os.str());
}

CheckpointState read_checkpoint_state(const std::string& dir, int index, const std::string& manifest) {
  const std::string path = state_path(dir, index);
  std::ifstream in = open_checkpoint_file(
      path, manifest, "missing (simreel plan --checkpoints writes one for each chunk after the first)");
  CheckpointState s;
  int32_t i = 0;
  int64_t frame = 0, step = 0;
  get(in, i);
  get(in, frame);
  get(in, step);
  if (i != index)
    throw InputError(path + ": the state of chunk " + std::to_string(i) + ", not of chunk " +
                     std::to_string(index));
  s.index = i, s.frame = (long)frame, s.step = (long)step;
  get_str(in, s.world);
  get_str(in, s.history);
  return s;
}

size_t write_checkpoint_prepass(const std::string& dir, const std::string& manifest,
                                const PrepassStore& store) {
  std::ostringstream os;
  store.save(os);
  return write_checkpoint_file((std::filesystem::path(dir) / "prepass.bin").string(), manifest, os.str());
}

void read_checkpoint_prepass(const std::string& dir, const std::string& manifest, PrepassStore& store) {
  std::ifstream in = open_checkpoint_file((std::filesystem::path(dir) / "prepass.bin").string(), manifest,
                                          "missing (written by simreel plan --checkpoints)");
  store.load(in);
}

std::string chunk_stem(const std::string& stem, int index, int chunks) {
  // Zero-padded to the width of N, so that a listing sorts in chunk order.
  const int w = (int)std::to_string(chunks).size();
  char buf[64];
  std::snprintf(buf, sizeof buf, ".chunk-%0*d-of-%d", w, index, chunks);
  return stem + buf;
}

void write_chunk_record(const std::string& path, const ChunkRecord& r) {
  json j;
  j["manifest"] = r.manifest;
  j["chunk"] = r.index;
  j["chunks"] = r.chunks;
  j["frames"] = {r.first, r.last};
  j["total_frames"] = r.total_frames;
  j["keyframe_interval"] = r.keyint;
  j["fps"] = r.fps;
  j["segment"] = r.segment;
  j["kind"] = r.kind;
  j["width"] = r.width;
  j["height"] = r.height;
  j["scene"] = r.scene;
  j["command"] = r.command;
  AtomicFile f(path);
  const std::string text = j.dump(2) + "\n";
  if (std::fwrite(text.data(), 1, text.size(), f.get()) != text.size())
    throw std::runtime_error(path + ": could not write the chunk's record");
  f.commit();
}

ChunkRecord read_chunk_record(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw InputError(path + ": cannot open");
  ChunkRecord r;
  try {
    const json j = json::parse(in);
    r.manifest = j.at("manifest").get<std::string>();
    r.index = j.at("chunk").get<int>();
    r.chunks = j.at("chunks").get<int>();
    r.first = j.at("frames").at(0).get<long>();
    r.last = j.at("frames").at(1).get<long>();
    r.total_frames = j.at("total_frames").get<long>();
    r.keyint = j.at("keyframe_interval").get<long>();
    r.fps = j.at("fps").get<double>();
    r.segment = j.at("segment").get<std::string>();
    r.kind = j.at("kind").get<std::string>();
    r.width = j.at("width").get<int>();
    r.height = j.at("height").get<int>();
    r.scene = j.value("scene", "");
    r.command = j.value("command", "");
    r.folder = std::filesystem::path(path).parent_path().string();
  } catch (const json::exception& e) {
    throw InputError(path + ": not a chunk record written by simreel render --chunk (" + e.what() + ")");
  }
  return r;
}

}  // namespace simreel
