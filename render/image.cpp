#include "render/image.hpp"

extern "C" {
#include <libavcodec/avcodec.h>
#include <libavutil/imgutils.h>
#include <libavutil/log.h>
#include <libswscale/swscale.h>
}

#include <algorithm>
#include <array>
#include <climits>
#include <cmath>
#include <cstring>
#include <fstream>
#include <memory>
#include <sstream>
#include <stdexcept>

#include "render/material.hpp"

namespace simreel {

namespace {

[[noreturn]] void fail(const std::string& name, const std::string& what) {
  throw std::runtime_error("image '" + name + "': " + what);
}

// The decoder a file's first bytes announce (TGA, which has no signature, by its name).
AVCodecID codec_of(std::string_view b, const std::string& name, const char** format) {
  auto starts = [&](const char* sig, size_t n, size_t at = 0) {
    return b.size() >= at + n && std::memcmp(b.data() + at, sig, n) == 0;
  };
  struct Sig {
    const char* bytes;
    size_t n, at;
    AVCodecID id;
    const char* format;
  };
  static const Sig sigs[] = {
      {"\x89PNG\r\n\x1a\n", 8, 0, AV_CODEC_ID_PNG, "PNG"},
      {"\xff\xd8\xff", 3, 0, AV_CODEC_ID_MJPEG, "JPEG"},
      {"GIF87a", 6, 0, AV_CODEC_ID_GIF, "GIF"},
      {"GIF89a", 6, 0, AV_CODEC_ID_GIF, "GIF"},
      {"BM", 2, 0, AV_CODEC_ID_BMP, "BMP"},
      {"WEBP", 4, 8, AV_CODEC_ID_WEBP, "WebP"},

  };
  for (const Sig& s : sigs)
    if (starts(s.bytes, s.n, s.at) && (s.id != AV_CODEC_ID_WEBP || starts("RIFF", 4))) {
      *format = s.format;
      return s.id;
    }
  std::string ext = name.size() >= 4 ? name.substr(name.size() - 4) : "";
  for (char& c : ext) c = (char)std::tolower((unsigned char)c);
  if (ext == ".tga") {
    *format = "TGA";
    return AV_CODEC_ID_TARGA;
  }
  return AV_CODEC_ID_NONE;
}

TextureImage decode_raw(std::string_view b, const std::string& name) {
  uint32_t wh[2] = {0, 0};
  for (int i = 0; i < 2; ++i)
    for (int k = 0; k < 4; ++k) wh[i] |= (uint32_t)(uint8_t)b[8 + 4 * i + k] << (8 * k);
  if (wh[0] == 0 || wh[1] == 0 || wh[0] > (uint32_t)kMaxImageSide || wh[1] > (uint32_t)kMaxImageSide ||
      (b.size() - 16) / 4 / wh[0] < wh[1] || b.size() - 16 != (size_t)wh[0] * wh[1] * 4)
    fail(name, "broken raw RGBA data");
  TextureImage im;
  im.width = (int)wh[0];
  im.height = (int)wh[1];
  im.rgba.assign(b.begin() + 16, b.end());
  return im;
}

}  // namespace

TextureImage decode_image(std::string_view bytes, const std::string& name) {
  if (bytes.size() >= 16 && std::memcmp(bytes.data(), kRawRgbaMagic, 8) == 0) return decode_raw(bytes, name);
  const char* format = "";
  const AVCodecID id = codec_of(bytes, name, &format);
  if (id == AV_CODEC_ID_NONE) {
    std::string head;
    for (size_t i = 0; i < std::min<size_t>(bytes.size(), 4); ++i) {
      char h[4];
      std::snprintf(h, sizeof h, "%02x", (unsigned)(uint8_t)bytes[i]);
      head += h;
    }
    fail(name, "not an image simreel reads (PNG, JPEG, GIF, BMP, WebP, TGA); it starts with bytes " +
                   (head.empty() ? std::string("(none: the file is empty)") : head));
  }
  const AVCodec* codec = avcodec_find_decoder(id);
  if (!codec) fail(name, std::string("this FFmpeg has no ") + format + " decoder");
  struct Ctx {
    AVCodecContext* c = nullptr;
    AVPacket* p = nullptr;
    AVFrame* f = nullptr;
    SwsContext* s = nullptr;
    ~Ctx() {
      sws_freeContext(s);
      av_frame_free(&f);
      av_packet_free(&p);
      avcodec_free_context(&c);
    }
  } x;
  // FFmpeg's own log lines ("LZW decode failed") would reach the user's terminal: the error thrown
  // says what is wrong. Scenes load before any thread starts, so the global level is safe to flip.
  struct Quiet {
    int level = av_log_get_level();
    Quiet() { av_log_set_level(AV_LOG_QUIET); }
    ~Quiet() { av_log_set_level(level); }
  } quiet;
  x.c = avcodec_alloc_context3(codec);
  x.p = av_packet_alloc();
  x.f = av_frame_alloc();
  if (!x.c || !x.p || !x.f) throw std::bad_alloc();
  // One thread and bit-exact decoding (its IDCT among them): the same texels on every machine.
  x.c->thread_count = 1;
  x.c->flags |= AV_CODEC_FLAG_BITEXACT;
  x.c->err_recognition = AV_EF_EXPLODE;  // a broken stream is an error, not a concealed picture
  if (avcodec_open2(x.c, codec, nullptr) < 0)
    fail(name, std::string("cannot open the ") + format + " decoder");
  // The packet: the whole file, with the zero padding FFmpeg's bit readers may read into.
  if (bytes.size() > (size_t)INT32_MAX - AV_INPUT_BUFFER_PADDING_SIZE) fail(name, "too large");
  if (av_new_packet(x.p, (int)bytes.size()) < 0) throw std::bad_alloc();
  std::memcpy(x.p->data, bytes.data(), bytes.size());
  const std::string broken = std::string("broken ") + format + " data";
  if (avcodec_send_packet(x.c, x.p) < 0) fail(name, broken);
  avcodec_send_packet(x.c, nullptr);  // end of stream: decoders that hold a frame give it now
  if (avcodec_receive_frame(x.c, x.f) < 0) fail(name, broken + " (no picture decoded)");
  const int w = x.f->width, h = x.f->height;
  if (w <= 0 || h <= 0 || w > kMaxImageSide || h > kMaxImageSide)
    fail(name, std::to_string(w) + "x" + std::to_string(h) + " px: sides of 1 to " +
                   std::to_string(kMaxImageSide) + " px are drawn");
  // To RGBA8 with swscale's bit-exact arithmetic (no CPU-specific rounding).
  x.s = sws_getContext(w, h, (AVPixelFormat)x.f->format, w, h, AV_PIX_FMT_RGBA,
                       SWS_POINT | SWS_BITEXACT | SWS_ACCURATE_RND | SWS_FULL_CHR_H_INT, nullptr, nullptr,
                       nullptr);
  if (!x.s) {
    const char* pf = av_get_pix_fmt_name((AVPixelFormat)x.f->format);
    fail(name, std::string("cannot convert its pixel format (") + (pf ? pf : "unknown") + ")");
  }
  TextureImage im;
  im.width = w;
  im.height = h;
  im.rgba.resize((size_t)w * h * 4);
  uint8_t* dst[4] = {im.rgba.data(), nullptr, nullptr, nullptr};
  const int stride[4] = {4 * w, 0, 0, 0};
  if (sws_scale(x.s, x.f->data, x.f->linesize, 0, h, dst, stride) != h) fail(name, "pixel conversion failed");
  // Formats without alpha come out of swscale opaque; palette images keep their transparency.
  return im;
}

TextureImage read_image(const std::string& file) {
  std::ifstream f(file, std::ios::binary);
  if (!f) throw std::runtime_error("image '" + file + "': cannot open it");
  std::ostringstream ss;
  ss << f.rdbuf();
  if (f.bad()) throw std::runtime_error("image '" + file + "': cannot read it");
  return decode_image(ss.str(), file);
}

void shrink_image(TextureImage& im, int max_side) {
  // Averages in linear light so that a checker does not darken when it shrinks.
  static const auto table = [] {
    std::array<float, 256> t{};
    for (int i = 0; i < 256; ++i) t[i] = srgb_to_linear(i / 255.0f);
    return t;
  }();
  auto encode = [](float l) {
    const float c = l <= 0.0031308f ? 12.92f * l : 1.055f * std::pow(l, 1 / 2.4f) - 0.055f;
    return (uint8_t)std::lround(std::clamp(c, 0.0f, 1.0f) * 255.0f);
  };
  while (im.width > max_side || im.height > max_side) {
    const int w = std::max(1, im.width / 2), h = std::max(1, im.height / 2);
    std::vector<uint8_t> out((size_t)w * h * 4);
    for (int y = 0; y < h; ++y)
      for (int x = 0; x < w; ++x)
        for (int c = 0; c < 4; ++c) {
          float sum = 0;
          for (int dy = 0; dy < 2; ++dy)
            for (int dx = 0; dx < 2; ++dx) {
              const int sx = std::min(2 * x + dx, im.width - 1), sy = std::min(2 * y + dy, im.height - 1);
              const uint8_t v = im.rgba[((size_t)sy * im.width + sx) * 4 + c];
              sum += c == 3 ? v / 255.0f : table[v];
            }
          out[((size_t)y * w + x) * 4 + c] =
              c == 3 ? (uint8_t)std::lround(sum / 4 * 255.0f) : encode(sum / 4);
        }
    im.width = w;
    im.height = h;
    im.rgba = std::move(out);
  }
}

}  // namespace simreel
