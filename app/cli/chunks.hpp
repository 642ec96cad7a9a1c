// A render split into chunks (`simreel plan`, `render --chunk i/N`, `simreel join`): the chunk table,
// the manifest every piece must share, and the record a finished chunk leaves beside its segment.
//
// Chunk boundaries fall on keyframe intervals (render/render_settings.hpp keyframe_interval: the GOP):
// each segment starts with a keyframe where the straight render has one, so the joined clip has the
// straight render's keyframe cadence and a packet copy is legal. Chunks are numbered 0 .. N-1, as a
// Slurm array's SLURM_ARRAY_TASK_ID, a Kubernetes indexed job's JOB_COMPLETION_INDEX or GNU parallel's
// `{#}` - 1 count them.
#pragma once
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "app/scene/scene.hpp"

namespace simreel {

class PrepassStore;

struct ChunkSpan {
  int index = 0;
  long first = 0, last = 0;  ///< video frames, both included
  long count() const { return last - first + 1; }
};

// `frames` video frames in `n` chunks of whole keyframe intervals, as even as the intervals allow
// (the last interval may be short). Throws UsageError when n exceeds the intervals.
std::vector<ChunkSpan> chunk_table(long frames, long keyint, int n);

// "i/N" (0 <= i < N): throws UsageError otherwise.
std::pair<int, int> parse_chunk_arg(const std::string& s);

// What every chunk of one join must share: the scene file's hash, the hashes of the files it reads
// (meshes, images, robot files), the settings that change physics or pixels (after the command's
// overrides; the thread count and the encoder's quality are not among them) and simreel's version.
struct ChunkManifest {
  std::string id;  ///< 16 hex digits over everything below
  std::string scene, scene_hash;
  std::map<std::string, std::string> inputs;  ///< path relative to the scene's folder -> hash
  std::string settings;                       ///< "duration=... timestep=... ..."
  std::string version;
};
// The drawing options of the command line that change pixels, as the manifest records them.
std::string look_settings(const std::optional<std::string>& aa, bool no_shadows);
// `look`: look_settings(...), "" for none.
ChunkManifest chunk_manifest(const std::string& scene_path, const Scene& scene, const std::string& look);

// What `render --chunk` leaves beside its segment when the segment is complete (and only then):
// <stem>.chunk-<i>-of-<N>.json. `join` reads these.
struct ChunkRecord {
  std::string manifest;  ///< ChunkManifest::id
  int index = 0, chunks = 0;
  long first = 0, last = 0;  ///< video frames
  long total_frames = 0;
  long keyint = 0;
  double fps = 0;
  std::string segment;  ///< file name beside the record: a video, or a folder of PNG frames (GIF)
  std::string kind;     ///< "mp4", "mov", "mkv", "webm" (packets), "frames" (PNGs for a GIF join)
  int width = 0, height = 0;
  std::string scene;
  std::string command;  ///< the chunk's render command, "{}" where its I/N stands
  std::string folder;   ///< where the record was read (not stored): the segment is beside it
};
std::string chunk_stem(const std::string& stem, int index, int chunks);  ///< "<stem>.chunk-02-of-04"

// `plan --checkpoints DIR`: DIR/plan.json says what the checkpoints are of; DIR/prepass.bin holds
// the views' pre-pass products; DIR/chunk-I.state the main world and the views' history at the
// frame before chunk I's first (chunk 0 starts from the scene). A chunk checks the plan's manifest
// and chunk count against its own before reading anything else.
struct CheckpointPlan {
  std::string manifest;
  int chunks = 0;
  long total_frames = 0;
  bool fitted = false;  ///< camera.auto was fitted: the camera below replaces the fit
  double position[3] = {}, look_at[3] = {};
};
void write_checkpoint_plan(const std::string& dir, const CheckpointPlan& p);
CheckpointPlan read_checkpoint_plan(const std::string& dir);  ///< throws InputError naming the file
// DIR/chunk-I.state: chunk I's start, taken at the video frame before its first.
struct CheckpointState {
  int index = 0;
  long frame = 0, step = 0;  ///< that frame, and the world's step there
  std::string world;         ///< World::save_state
  std::string history;       ///< SceneFrames::save_history
};
// Each file starts with simreel's mark and the manifest's id; a reader refuses another manifest
// (InputError naming the file). The writers return the bytes written.
size_t write_checkpoint_state(const std::string& dir, const std::string& manifest, const CheckpointState& s);
CheckpointState read_checkpoint_state(const std::string& dir, int index, const std::string& manifest);
size_t write_checkpoint_prepass(const std::string& dir, const std::string& manifest,
                                const PrepassStore& store);
void read_checkpoint_prepass(const std::string& dir, const std::string& manifest, PrepassStore& store);
void write_chunk_record(const std::string& path, const ChunkRecord& r);
ChunkRecord read_chunk_record(const std::string& path);  ///< throws InputError naming the file

}  // namespace simreel
