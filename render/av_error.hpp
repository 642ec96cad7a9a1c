// FFmpeg's text for an error code (av_strerror), for the messages of the video writers.
#pragma once
extern "C" {
#include <libavutil/error.h>
}

#include <string>

namespace simreel {

inline std::string av_err(int e) {
  char b[AV_ERROR_MAX_STRING_SIZE] = {};
  av_strerror(e, b, sizeof b);
  return b;
}

}  // namespace simreel
