// Video segments joined into one file without re-encoding: every packet copied with the timestamps
// it has. A chunk of a render (`render --chunk`) carries absolute timestamps (frame k at k / fps)
// and starts on a keyframe with the same codec parameters as every other chunk, so the copy is the
// straight render's packet sequence. FFmpeg's concat demuxer, the usual join, places each file at
// the previous one's start plus its duration and leaves a gap as long as each segment's start time
// (a 6.03 s clip in 4 chunks came out 10.60 s long); this join does not re-time anything.
#pragma once
#include <string>
#include <vector>

namespace simreel {

struct JoinSegment {
  std::string path;
  long first = 0, last = 0;  ///< the video frames it must hold, both included
};

struct JoinResult {
  long packets = 0;
  double duration = 0;  ///< s, of the joined stream
};

// Writes `out` (.mp4 .mov .mkv .webm; beside it as a partial file first, renamed when complete;
// +faststart for .mp4 and .mov) from the segments in order. Throws InputError naming the segment
// when one cannot be read, holds no video, has codec parameters (codec, size, pixel format, the
// stream's header bytes) or a time base other than the first segment's, or does not hold exactly
// its frames (a gap, an overlap, a missing or extra frame); std::runtime_error when `out` cannot be
// written.
JoinResult join_segments(const std::vector<JoinSegment>& segments, double fps, const std::string& out);

}  // namespace simreel
