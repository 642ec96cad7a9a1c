// Frames of a video file (MP4, WebM, GIF, anything libavformat opens) as RGBA images with their
// timestamps, decoded one at a time so a long clip never sits in memory whole.
#pragma once
#include <memory>
#include <string>

#include "app/regress/image.hpp"

namespace simreel {

class VideoFrames {
 public:
  // Throws InputError naming the file if it cannot be opened or holds no video stream.
  explicit VideoFrames(const std::string& path);
  ~VideoFrames();
  // The next frame and its presentation time in seconds (the stream's own timestamps: a clip of
  // frames 40-49 at 30 fps starts at 1.333 s; MPEG-TS, whose clock starts anywhere, counts from its
  // first frame); false at the end.
  // Throws InputError if the data is corrupt beyond the decoder's recovery.
  bool next(Image& out, double& time);
  double fps() const;  ///< the stream's base frame rate (else its average), 0 if unknown
  int width() const;
  int height() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> p_;
};

}  // namespace simreel
