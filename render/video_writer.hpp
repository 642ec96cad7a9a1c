// Frames to a video file (and/or a PNG sequence) on an encoding thread with a bounded queue, so
// rendering and encoding overlap and memory stays flat however long the clip.
//   .mp4 .mov .mkv  H.264 (libx264, yuv420p, CRF, +faststart), BT.709 tagged
//   .webm           VP9 (libvpx-vp9, realtime, CRF)
//   .gif            GIF: one palette for the clip by FFmpeg's palettegen/paletteuse filters, in two
//                   passes (render/gif_frames.hpp); optionally scaled and at a lower frame rate
// The file is written beside the target as "<name>.partial-<pid>.<ext>" and renamed into place by
// finish(); destroying the writer without finish() removes it. The target never holds a partial file.
#pragma once
#include <cstdint>
#include <memory>
#include <string>

#include "render/render_settings.hpp"
#include "render/screen.hpp"

namespace simreel {

struct VideoSettings {
  std::string path;                                    ///< output video; empty for PNG frames only
  std::string frames_dir;                              ///< if set, also frame_00000.png ... here
  int width = kDefaultWidth, height = kDefaultHeight;  ///< px; even for yuv420p
  double fps = 30;
  int crf = 20;  ///< x264 quality (lower is better; 18-23 typical); NVENC's constant quality `cq`
  /// .mp4 .mov .mkv: an FFmpeg encoder by name (h264_nvenc, hevc_nvenc, libx265, ...) instead of
  /// libx264. One this FFmpeg lacks, or that cannot open here (an NVIDIA card without an NVENC
  /// unit: "OpenEncodeSessionEx failed: unsupported device"; VAAPI, which needs frames uploaded to
  /// the GPU), falls back to libx264 with encoder_note() saying why.
  std::string encoder;
  std::string preset = "veryfast";
  int gif_width = 0;   ///< GIF only: output width, px (the height keeps the aspect); 0: `width`
  double gif_fps = 0;  ///< GIF only: frames/s, at most `fps` and 50; 0: `fps` up to 50
  int queue = 4;       ///< frames in flight between renderer and encoder
  // FXAA (render/fxaa.hpp) on each frame, on the encoding thread, before PNG and video: there it
  // overlaps the rendering of the next frame instead of delaying it. Then each frame's screen
  // layer (commit's `layer`) is composited over it: the renderer's post stage, moved to this
  // thread (RenderSettings::post = PostStage::caller; set fxaa to RenderSettings::fxaa()).
  bool fxaa = false;
};

class VideoWriter {
 public:
  explicit VideoWriter(const VideoSettings& s);  ///< throws std::runtime_error
  ~VideoWriter();
  // Copies one RGBA frame (top row first) into the queue; blocks while the queue is full.
  // `index` is the frame's number in the whole clip: its PNG is frame_<index>.png and its
  // timestamp index / fps, whichever frames came before (a partial render names and times its
  // frames as the full render does). Increasing; -1 takes the number after the previous frame's.
  // `layer`: drawn over the frame after FXAA (copied; its glyph bitmaps must outlive the writer).
  void push(const uint8_t* rgba, long index = -1, const ScreenLayer* layer = nullptr);
  // The same without the copy: acquire() returns the next free frame buffer (width*height*4
  // bytes; blocks while the queue is full), the caller fills it, commit() queues it.
  uint8_t* acquire();
  void commit(long index = -1, const ScreenLayer* layer = nullptr);
  // Drains the queue, flushes the encoder, writes the trailer and renames into place.
  void finish();
  long frames() const;
  double encode_seconds() const;            ///< time the encoding thread spent working
  std::string encoder_name() const;         ///< the encoder in use ("libx264", "h264_nvenc", ...)
  const std::string& encoder_note() const;  ///< why VideoSettings::encoder was not used, or ""

 private:
  struct Impl;
  std::unique_ptr<Impl> p_;
};

}  // namespace simreel
