#include "render/gif_frames.hpp"

extern "C" {
#include <libavcodec/avcodec.h>
#include <libavfilter/avfilter.h>
#include <libavfilter/buffersink.h>
#include <libavfilter/buffersrc.h>
#include <libavutil/opt.h>
}

#include <fcntl.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <stdexcept>
#include <vector>

#include "render/av_error.hpp"

namespace simreel {

namespace {

void check(int e, const char* what) {
  if (e < 0) throw std::runtime_error(std::string("GIF: ") + what + ": " + av_err(e));
}

// A filter graph with one thread (slice threading would not change the output, but one thread
// keeps the work where the writer's thread accounts for it).
struct Graph {
  AVFilterGraph* g = avfilter_graph_alloc();
  Graph() {
    if (!g) throw std::runtime_error("GIF: out of memory for a filter graph");
    g->nb_threads = 1;
  }
  ~Graph() { avfilter_graph_free(&g); }
  AVFilterContext* add(const char* filter, const char* name, const std::string& args) {
    AVFilterContext* c = nullptr;
    check(avfilter_graph_create_filter(&c, avfilter_get_by_name(filter), name, args.c_str(), nullptr, g),
          filter);
    return c;
  }
  static void link(AVFilterContext* a, unsigned pa, AVFilterContext* b, unsigned pb) {
    check(avfilter_link(a, pa, b, pb), "linking filters");
  }
  void configure() { check(avfilter_graph_config(g, nullptr), "configuring the filter graph"); }
};

std::string buffer_args(int w, int h, AVPixelFormat fmt) {
  return "video_size=" + std::to_string(w) + "x" + std::to_string(h) +
         ":pix_fmt=" + std::to_string((int)fmt) + ":time_base=1/1:pixel_aspect=1/1";
}

// An unnamed file in `dir` (or, where the file system cannot, one unlinked at once).
FILE* anonymous_file(const std::string& dir) {
  int fd = open(dir.c_str(), O_TMPFILE | O_RDWR | O_CLOEXEC, 0600);
  if (fd < 0) {
    std::string path = dir + "/.simreel-gif-XXXXXX";
    fd = mkstemp(path.data());
    if (fd >= 0) unlink(path.c_str());
  }
  if (fd < 0) throw std::runtime_error("GIF: cannot create a temporary file in '" + dir + "'");
  FILE* f = fdopen(fd, "w+b");
  if (!f) {
    close(fd);
    throw std::runtime_error("GIF: cannot open a temporary file in '" + dir + "'");
  }
  return f;
}

AVCodecContext* open_codec(bool encoder, int w, int h) {
  const AVCodec* c = encoder ? avcodec_find_encoder(AV_CODEC_ID_QOI) : avcodec_find_decoder(AV_CODEC_ID_QOI);
  if (!c) throw std::runtime_error("GIF: this FFmpeg has no QOI codec (FFmpeg 5.1 or later has)");
  AVCodecContext* x = avcodec_alloc_context3(c);
  x->width = w;
  x->height = h;
  x->pix_fmt = AV_PIX_FMT_RGBA;
  x->time_base = AVRational{1, 1};
  check(avcodec_open2(x, c, nullptr), "opening the QOI codec");
  return x;
}

}  // namespace

struct GifFrames::Impl {
  GifSettings s;
  int ow = 0, oh = 0;
  double ofps = 0;
  long kept = 0, last_slot = -1;
  // Pass 1: source -> [scale] -> split -> sink (frames to keep)
  //                                    \-> palettegen -> sink (the palette, at the end)
  Graph g1;
  AVFilterContext *src1 = nullptr, *keep_sink = nullptr, *palette_sink = nullptr;
  AVCodecContext *qoi_enc = nullptr, *qoi_dec = nullptr;
  AVFrame *in = av_frame_alloc(), *out = av_frame_alloc();
  AVPacket* pkt = av_packet_alloc();
  FILE* store = nullptr;
  bool finished = false;

  ~Impl() {
    avcodec_free_context(&qoi_enc);
    avcodec_free_context(&qoi_dec);
    av_frame_free(&in);
    av_frame_free(&out);
    av_packet_free(&pkt);
    if (store) std::fclose(store);
  }

  void build_pass1() {
    // RGB0: the frames' fourth byte is not looked at (a GIF frame is opaque; paletteuse would make
    // pixels of alpha < 128 transparent).
    src1 = g1.add("buffer", "in", buffer_args(s.width, s.height, AV_PIX_FMT_RGB0));
    AVFilterContext* last = src1;
    if (ow != s.width || oh != s.height) {
      AVFilterContext* scale =
          g1.add("scale", "scale", "w=" + std::to_string(ow) + ":h=" + std::to_string(oh) + ":flags=lanczos");
      Graph::link(last, 0, scale, 0);
      last = scale;
    }
    AVFilterContext* split = g1.add("split", "split", "2");
    Graph::link(last, 0, split, 0);
    AVFilterContext* keep_fmt = g1.add("format", "keep_fmt", "pix_fmts=rgba");
    keep_sink = g1.add("buffersink", "keep", "");
    Graph::link(split, 0, keep_fmt, 0);
    Graph::link(keep_fmt, 0, keep_sink, 0);
    // palettegen's defaults, as `ffmpeg -vf palettegen` runs it: 255 colours fitted to the histogram
    // of every pixel of every frame, and one entry kept transparent for the GIF encoder to mark
    // pixels that did not change since the previous frame.
    AVFilterContext* gen = g1.add("palettegen", "palettegen", "");
    palette_sink = g1.add("buffersink", "palette", "");
    Graph::link(split, 1, gen, 0);
    Graph::link(gen, 0, palette_sink, 0);
    g1.configure();
  }

  // Compresses a frame (nullptr: the end) and appends what the encoder gives: records of
  // [int64 GIF frame number][uint32 size][QOI bytes].
  void store_frame(const AVFrame* f) {
    check(avcodec_send_frame(qoi_enc, f), "compressing a frame");
    while (avcodec_receive_packet(qoi_enc, pkt) == 0) {
      const uint32_t n = (uint32_t)pkt->size;
      const int64_t slot = pkt->pts;
      const bool ok = std::fwrite(&slot, sizeof slot, 1, store) == 1 &&
                      std::fwrite(&n, sizeof n, 1, store) == 1 && std::fwrite(pkt->data, 1, n, store) == n;
      av_packet_unref(pkt);
      if (!ok) throw std::runtime_error("GIF: cannot write the temporary frames (disk full?)");
    }
  }

  void drain_keep() {
    for (;;) {
      const int e = av_buffersink_get_frame(keep_sink, out);
      if (e == AVERROR(EAGAIN) || e == AVERROR_EOF) return;
      check(e, "scaling a frame");
      store_frame(out);
      av_frame_unref(out);
    }
  }
};

GifFrames::GifFrames(const GifSettings& s) : p_(std::make_unique<Impl>()) {
  Impl& P = *p_;
  P.s = s;
  P.ow = s.out_width > 0 ? s.out_width : s.width;
  P.oh = std::max(1, (int)std::lround((double)s.height * P.ow / s.width));
  P.ofps = s.out_fps > 0 ? std::min(s.out_fps, s.fps) : s.fps;
  if (!P.in || !P.out || !P.pkt) throw std::runtime_error("GIF: out of memory");
  P.build_pass1();
  P.qoi_enc = open_codec(true, P.ow, P.oh);
  P.store = anonymous_file(s.dir);
}

GifFrames::~GifFrames() = default;

int GifFrames::out_width() const {
  return p_->ow;
}
int GifFrames::out_height() const {
  return p_->oh;
}
double GifFrames::out_fps() const {
  return p_->ofps;
}
long GifFrames::frames() const {
  return p_->kept;
}

void GifFrames::add(const uint8_t* rgba, long index) {
  Impl& P = *p_;
  // GIF frame j is at time j / out_fps: it shows the rendered frame nearest to that time, k =
  // round(j fps / out_fps). (Every j has one, as out_fps <= fps.)
  const long slot = std::lround(index * P.ofps / P.s.fps);
  if (slot <= P.last_slot || std::lround(slot * P.s.fps / P.ofps) != index) return;
  P.last_slot = slot;
  AVFrame* f = P.in;
  f->format = AV_PIX_FMT_RGB0;
  f->width = P.s.width;
  f->height = P.s.height;
  f->data[0] = const_cast<uint8_t*>(rgba);  // read only: the buffer source copies it
  f->linesize[0] = P.s.width * 4;
  f->pts = slot;
  check(av_buffersrc_write_frame(P.src1, f), "adding a frame");
  std::memset(f->data, 0, sizeof f->data);
  ++P.kept;
  P.drain_keep();
}

void GifFrames::finish(const std::function<void(AVFrame*)>& encode) {
  Impl& P = *p_;
  if (P.finished) throw std::logic_error("GifFrames::finish called twice");
  P.finished = true;
  // End of pass 1: the last frames kept, then the palette.
  check(av_buffersrc_add_frame(P.src1, nullptr), "ending pass 1");
  P.drain_keep();
  P.store_frame(nullptr);
  if (std::fflush(P.store) != 0)
    throw std::runtime_error("GIF: cannot write the temporary frames (disk full?)");
  AVFrame* palette = av_frame_alloc();
  const int e = av_buffersink_get_frame(P.palette_sink, palette);
  if (e < 0) {
    av_frame_free(&palette);
    check(e, "getting the palette");
  }

  // Pass 2: frames -> paletteuse <- palette.
  Graph g2;
  AVFilterContext* src = g2.add("buffer", "in", buffer_args(P.ow, P.oh, AV_PIX_FMT_RGBA));
  AVFilterContext* pal = g2.add("buffer", "palette",
                                buffer_args(palette->width, palette->height, (AVPixelFormat)palette->format));
  // Sierra-2-4A error diffusion (paletteuse's default); diff_mode=rectangle re-maps only the
  // rectangle that changed since the previous frame, so still parts keep the same pixels (the GIF
  // encoder then stores them as transparent, unchanged) and dither patterns do not crawl.
  AVFilterContext* use = g2.add("paletteuse", "paletteuse", "diff_mode=rectangle");
  AVFilterContext* sink = g2.add("buffersink", "out", "");
  Graph::link(src, 0, use, 0);
  Graph::link(pal, 0, use, 1);
  Graph::link(use, 0, sink, 0);
  g2.configure();
  palette->pts = 0;
  int pe = av_buffersrc_add_frame(pal, palette);  // takes the reference
  av_frame_free(&palette);
  check(pe, "setting the palette");
  check(av_buffersrc_add_frame(pal, nullptr), "setting the palette");

  P.qoi_dec = open_codec(false, P.ow, P.oh);
  auto drain = [&] {
    for (;;) {
      const int r = av_buffersink_get_frame(sink, P.out);
      if (r == AVERROR(EAGAIN) || r == AVERROR_EOF) return;
      check(r, "mapping a frame onto the palette");
      encode(P.out);
      av_frame_unref(P.out);
    }
  };
  std::rewind(P.store);
  std::vector<uint8_t> bytes;
  int64_t slot = 0;
  uint32_t n = 0;
  while (std::fread(&slot, sizeof slot, 1, P.store) == 1) {
    if (std::fread(&n, sizeof n, 1, P.store) != 1)
      throw std::runtime_error("GIF: temporary frames cut short");
    bytes.resize(n + AV_INPUT_BUFFER_PADDING_SIZE);
    if (std::fread(bytes.data(), 1, n, P.store) != n)
      throw std::runtime_error("GIF: temporary frames cut short");
    std::memset(bytes.data() + n, 0, AV_INPUT_BUFFER_PADDING_SIZE);
    P.pkt->data = bytes.data();
    P.pkt->size = (int)n;
    check(avcodec_send_packet(P.qoi_dec, P.pkt), "reading a frame back");
    P.pkt->data = nullptr;
    P.pkt->size = 0;
    while (avcodec_receive_frame(P.qoi_dec, P.in) == 0) {
      P.in->pts = slot;
      check(av_buffersrc_add_frame(src, P.in), "mapping a frame");
      drain();
    }
  }
  check(av_buffersrc_add_frame(src, nullptr), "ending pass 2");
  drain();
}

}  // namespace simreel
