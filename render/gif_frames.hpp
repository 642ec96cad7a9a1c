// GIF frames for the video writer (render/video_writer.hpp): one 256-colour palette for the whole
// clip and every frame mapped onto it, by FFmpeg's palettegen and paletteuse filters (libavfilter),
// the filters `ffmpeg -vf palettegen/paletteuse` runs.
//
// palettegen needs every frame before it gives the palette, so the clip goes through twice:
//   pass 1 (add(), per frame, on the writer's thread): scale to the GIF's size (Lanczos), count the
//     frame's colours into palettegen's histogram, and keep the frame losslessly compressed (QOI,
//     through libavcodec) in an unnamed temporary file beside the output;
//   pass 2 (finish()): the palette, then each kept frame decoded and mapped onto it by paletteuse
//     (Sierra-2-4A error diffusion, default; only the rectangle that changed since the previous
//     frame is re-mapped), handed to the GIF encoder.
// Memory stays flat however long the clip: one frame in each filter graph and palettegen's colour
// histogram (one count per distinct colour). Measured on the default demo at 1280x720
// and 30 frames/s (this 2-core machine, peak RSS of the whole render): 235 MB for 3 s and for 12 s
// (H.264: 270 MB), where `ffmpeg -vf split,palettegen,paletteuse` in one filter graph buffers every
// frame: 440 MB for 3 s. Kept frames: QOI, 6.4 MB for 91 frames (70 kB a frame); FFV1 gave 4.8 MB
// for about 2.6x QOI's CPU time, LCL's deflate 4.0 MB for 1.7x. A palette without a second pass
// (fitted to the first frames, or a new one each frame) misses colours that come later or flickers.
// The temporary file has no name (O_TMPFILE, else unlinked at once): nothing of it outlives the
// process, however it ends. The same frames give byte-identical GIFs (one filter thread).
//
// Results, 3 s of three demos at 1280x720 (tests/render/gif_frames_test.cpp checks flat colours):
//   dzhanibekov  1.13 MB (byte-identical to the ffmpeg command with the same filters on our PNG
//                frames; `ffmpeg -i clip.mp4 -vf palettegen/paletteuse` on our H.264 clip: 2.40 MB;
//                the median-cut palette of the first frame with Floyd-Steinberg used before: 13.0 MB,
//                its flat sky a dither of 3 palette entries)
//   pile         2.03 MB (ffmpeg from the H.264 clip 4.29 MB, before 11.0 MB)
//   dominoes     0.51 MB (1.47 MB, before 9.8 MB)
// Dithering: paletteuse's default (Sierra-2-4A) keeps shading smooth; dither=none was 10% smaller
// with steps in the shading seen when zoomed, bayer 25% larger. diff_mode=rectangle: the same size
// (within 0.03%), about half paletteuse's time.
#pragma once
#include <cstdint>
#include <functional>
#include <memory>
#include <string>

struct AVFrame;

namespace simreel {

struct GifSettings {
  int width = 0, height = 0;  ///< rendered frames, px
  double fps = 30;            ///< rendered frames: frame k is at time k / fps
  int out_width = 0;          ///< GIF width, px; 0: `width`. The height keeps the aspect ratio
  double out_fps = 0;         ///< GIF frames/s (<= fps); 0: fps
  std::string dir = ".";      ///< where the temporary frames go (the output's folder)
};

class GifFrames {
 public:
  explicit GifFrames(const GifSettings& s);  ///< throws std::runtime_error
  ~GifFrames();
  int out_width() const;
  int out_height() const;
  double out_fps() const;
  // Pass 1: frame number `index` (RGBA, top row first). Frames between two GIF frame times are
  // dropped: GIF frame j shows the rendered frame nearest to time j / out_fps.
  void add(const uint8_t* rgba, long index);
  // Pass 2: each kept frame as a PAL8 AVFrame (pts: GIF frame number j, in 1 / out_fps units),
  // in order. Call once.
  void finish(const std::function<void(AVFrame*)>& encode);
  long frames() const;  ///< frames kept so far

 private:
  struct Impl;
  std::unique_ptr<Impl> p_;
};

}  // namespace simreel
