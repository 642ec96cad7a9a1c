#include "render/video_writer.hpp"

#include "render/fxaa.hpp"
#include "render/gif_frames.hpp"
#include "render/yuv.hpp"

extern "C" {
#include <libavcodec/avcodec.h>
#include <libavformat/avformat.h>
#include <libavutil/imgutils.h>
#include <libavutil/opt.h>
}

#include <unistd.h>

#include <chrono>
#include <condition_variable>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <mutex>
#include <stdexcept>
#include <thread>
#include <vector>

#include "render/av_error.hpp"
#include "render/png_writer.hpp"

namespace simreel {

struct VideoWriter::Impl {
  VideoSettings s;
  std::string tmp;
  AVFormatContext* fmt = nullptr;
  AVCodecContext* enc = nullptr;
  AVStream* st = nullptr;
  AVFrame* frame = nullptr;
  AVPacket* pkt = nullptr;
  std::unique_ptr<GifFrames> gif;  // GIF only: palettes by libavfilter, in two passes
  FxaaBuffers fxaa_buffers;
  bool header_written = false, finished = false;

  // Bounded queue: slots cycle free -> filled (by push) -> free (by the encoder thread).
  std::vector<std::vector<uint8_t>> slots;
  std::vector<long> slot_index;           // the frame number each slot carries: its PNG name and timestamp
  std::vector<ScreenLayer> slot_layer;    // the screen layer each slot carries (storage reused)
  size_t head = 0, tail = 0, filled = 0;  // ring indices, guarded by mu
  bool closing = false;
  std::string error;  // first error on the encoder thread
  std::mutex mu;
  std::condition_variable cv_push, cv_pop;
  std::thread worker;
  long nframes = 0;
  long next_index = 0;  // the smallest frame number the next commit may carry
  double busy = 0;

  void open_video() {
    const std::filesystem::path target(s.path);
    tmp = (target.parent_path() /
           (target.stem().string() + ".partial-" + std::to_string(getpid()) + target.extension().string()))
              .string();
    if (avformat_alloc_output_context2(&fmt, nullptr, nullptr, s.path.c_str()) < 0 || !fmt)
      throw std::runtime_error("no video format for '" + s.path + "' (use .mp4, .webm or .gif)");
    const std::string ext = target.extension().string();
    const bool is_gif = ext == ".gif", webm = ext == ".webm";
    const bool h264 = !is_gif && !webm;
    const AVCodec* codec = nullptr;
    AVRational rate{};
    if (!h264 && !s.encoder.empty())
      note = "--encoder applies to .mp4, .mov and .mkv outputs: '" + s.encoder + "' not used for " + ext;
    if (h264 && !s.encoder.empty() && s.encoder != "libx264") {
      codec = avcodec_find_encoder_by_name(s.encoder.c_str());
      if (!codec)
        note = "this FFmpeg has no encoder '" + s.encoder + "': encoding with libx264";
      else if (codec->type != AVMEDIA_TYPE_VIDEO)
        note = "'" + s.encoder + "' is not a video encoder: encoding with libx264", codec = nullptr;
    }
    if (!codec) codec = avcodec_find_encoder_by_name(is_gif ? "gif" : webm ? "libvpx-vp9" : "libx264");
    if (!codec) throw std::runtime_error("this FFmpeg has no encoder for '" + ext + "'");
    st = avformat_new_stream(fmt, nullptr);
    if (!open_encoder(codec, is_gif, webm, &rate)) {  // the named encoder cannot run here
      codec = avcodec_find_encoder_by_name("libx264");
      if (!codec || !open_encoder(codec, is_gif, webm, &rate))
        throw std::runtime_error("cannot open the libx264 encoder: " + open_error);
    }
    avcodec_parameters_from_context(st->codecpar, enc);
    st->time_base = enc->time_base;
    st->avg_frame_rate = rate;
    finish_open(ext, is_gif);
  }

  std::string note, open_error;

  // Sets up `enc` for `codec` and opens it; false (with note and open_error said) if a named
  // encoder other than libx264 cannot open here, so the caller falls back.
  bool open_encoder(const AVCodec* codec, bool is_gif, bool webm, AVRational* rate_out) {
    const std::filesystem::path target(s.path);
    if (enc) avcodec_free_context(&enc);
    enc = avcodec_alloc_context3(codec);
    enc->width = s.width;
    enc->height = s.height;
    AVRational rate = av_d2q(s.fps, 100000);
    if (is_gif) {
      GifSettings g;
      g.width = s.width;
      g.height = s.height;
      g.fps = s.fps;
      g.out_width = s.gif_width;
      g.out_fps = s.gif_fps > 0 ? s.gif_fps : std::min(s.fps, 50.0);
      g.dir = target.has_parent_path() ? target.parent_path().string() : ".";
      gif = std::make_unique<GifFrames>(g);
      enc->width = gif->out_width();
      enc->height = gif->out_height();
      rate = av_d2q(gif->out_fps(), 100000);
    }
    *rate_out = rate;
    enc->time_base = av_inv_q(rate);
    enc->framerate = rate;
    enc->pix_fmt = is_gif ? AV_PIX_FMT_PAL8 : AV_PIX_FMT_YUV420P;
    enc->gop_size = (int)keyframe_interval(s.fps);
    if (!is_gif) {
      enc->color_range = AVCOL_RANGE_MPEG;
      enc->colorspace = AVCOL_SPC_BT709;
      enc->color_primaries = AVCOL_PRI_BT709;
      enc->color_trc = AVCOL_TRC_BT709;
      enc->chroma_sample_location = AVCHROMA_LOC_CENTER;  // render/yuv.hpp averages 2x2 blocks
    }
    if (fmt->oformat->flags & AVFMT_GLOBALHEADER) enc->flags |= AV_CODEC_FLAG_GLOBAL_HEADER;
    AVDictionary* opts = nullptr;
    const bool x264 = std::string(codec->name) == "libx264";
    if (!is_gif && !webm && x264) {
      av_dict_set(&opts, "preset", s.preset.c_str(), 0);
      av_dict_set(&opts, "crf", std::to_string(s.crf).c_str(), 0);
    } else if (!is_gif && !webm) {  // another encoder: its own quality option at the same level
      const std::string name = codec->name;
      if (name.find("nvenc") != std::string::npos) {
        av_dict_set(&opts, "rc", "vbr", 0);
        av_dict_set(&opts, "cq", std::to_string(s.crf).c_str(), 0);
        av_dict_set(&opts, "preset", "p4", 0);
      } else if (name == "libx265") {
        av_dict_set(&opts, "preset", s.preset.c_str(), 0);
        av_dict_set(&opts, "crf", std::to_string(s.crf).c_str(), 0);
      }
    } else if (webm) {
      av_dict_set(&opts, "deadline", "realtime", 0);
      av_dict_set(&opts, "cpu-used", "8", 0);
      av_dict_set(&opts, "crf", "32", 0);
      enc->bit_rate = 0;
    }
    // FFmpeg prints its own reason at error level ("OpenEncodeSessionEx failed: unsupported
    // device"); the note says what simreel did about it.
    int e = avcodec_open2(enc, codec, &opts);
    av_dict_free(&opts);
    if (e < 0) {
      open_error = av_err(e);
      if (!x264 && !is_gif && !webm) {
        const std::string name = codec->name;
        const std::string why =
            name.find("vaapi") != std::string::npos
                ? "; VAAPI encoders take frames uploaded to the GPU, which simreel does not do"
            : name.find("nvenc") != std::string::npos
                ? "; no NVIDIA driver here, or a card without an NVENC unit, such as an H100"
                : "";
        note = "the " + name + " encoder cannot run here (" + open_error + why + "): encoding with libx264";
        return false;
      }
      throw std::runtime_error("cannot open the " + std::string(codec->name) + " encoder: " + open_error);
    }
    return true;
  }

  void finish_open(const std::string& ext, bool is_gif) {
    int e = 0;
    // The muxer reopens its url for +faststart: point it at the temporary file we write.
    av_freep(&fmt->url);
    fmt->url = av_strdup(tmp.c_str());
    if ((e = avio_open(&fmt->pb, tmp.c_str(), AVIO_FLAG_WRITE)) < 0)
      throw std::runtime_error("cannot write '" + tmp + "': " + av_err(e));
    AVDictionary* mopts = nullptr;
    if (ext == ".mp4" || ext == ".mov") av_dict_set(&mopts, "movflags", "+faststart", 0);
    e = avformat_write_header(fmt, &mopts);
    av_dict_free(&mopts);
    if (e < 0) throw std::runtime_error("cannot start '" + s.path + "': " + av_err(e));
    header_written = true;
    pkt = av_packet_alloc();
    if (is_gif) return;  // GIF frames come from GifFrames, in finish()
    frame = av_frame_alloc();
    frame->format = enc->pix_fmt;
    frame->width = s.width;
    frame->height = s.height;
    frame->color_range = enc->color_range;
    frame->colorspace = enc->colorspace;
    frame->color_primaries = enc->color_primaries;
    frame->color_trc = enc->color_trc;
    if (av_frame_get_buffer(frame, 0) < 0) throw std::runtime_error("out of memory for a video frame");
    // Pixel conversion in encode(): render/yuv.hpp for YUV 4:2:0.
  }

  void drain_packets() {
    for (;;) {
      const int e = avcodec_receive_packet(enc, pkt);
      if (e == AVERROR(EAGAIN) || e == AVERROR_EOF) return;
      if (e < 0) throw std::runtime_error("encoding failed: " + av_err(e));
      av_packet_rescale_ts(pkt, enc->time_base, st->time_base);
      pkt->stream_index = st->index;
      const int w = av_interleaved_write_frame(fmt, pkt);
      if (w < 0) throw std::runtime_error("writing the video failed: " + av_err(w));
    }
  }

  void encode(uint8_t* rgba, long index, const ScreenLayer& layer) {
    if (s.fxaa) fxaa(rgba, s.width, s.height, fxaa_buffers);
    if (!layer.empty()) composite(layer, rgba, s.width, s.height);
    if (!s.frames_dir.empty()) {
      char name[32];
      std::snprintf(name, sizeof name, "frame_%05ld.png", index);
      write_png((std::filesystem::path(s.frames_dir) / name).string(), rgba, s.width, s.height);
    }
    if (!enc) return;
    if (gif) {
      gif->add(rgba, index);  // pass 1; the GIF is encoded in finish()
      return;
    }
    if (av_frame_make_writable(frame) < 0) throw std::runtime_error("video frame not writable");
    rgba_to_yuv420_bt709(rgba, s.width, s.height, frame->data[0], frame->linesize[0], frame->data[1],
                         frame->linesize[1], frame->data[2], frame->linesize[2]);
    frame->pts = index;
    send(frame);
  }

  void send(AVFrame* f) {
    const int e = avcodec_send_frame(enc, f);
    if (e < 0) throw std::runtime_error("encoding failed: " + av_err(e));
    drain_packets();
  }

  void run() {
    for (;;) {
      std::unique_lock<std::mutex> lk(mu);
      cv_pop.wait(lk, [&] { return filled > 0 || closing; });
      if (filled == 0 && closing) return;
      std::vector<uint8_t>& slot = slots[tail];
      const long index = slot_index[tail];
      const ScreenLayer& layer = slot_layer[tail];
      lk.unlock();
      const auto t0 = std::chrono::steady_clock::now();
      try {
        if (error.empty()) encode(slot.data(), index, layer);
      } catch (const std::exception& ex) {
        std::lock_guard<std::mutex> g(mu);
        error = ex.what();
      }
      busy += std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
      lk.lock();
      tail = (tail + 1) % slots.size();
      --filled;
      cv_push.notify_one();
    }
  }

  void stop_worker() {
    {
      std::lock_guard<std::mutex> g(mu);
      closing = true;
    }
    cv_pop.notify_all();
    if (worker.joinable()) worker.join();
  }

  void release() {
    av_packet_free(&pkt);
    av_frame_free(&frame);
    avcodec_free_context(&enc);
    gif.reset();
    if (fmt) {
      if (fmt->pb) avio_closep(&fmt->pb);
      avformat_free_context(fmt);
      fmt = nullptr;
    }
  }
};

VideoWriter::VideoWriter(const VideoSettings& s) : p_(std::make_unique<Impl>()) {
  Impl& P = *p_;
  P.s = s;
  av_log_set_level(AV_LOG_ERROR);  // encoder statistics are not for the user's terminal
  if (!s.path.empty()) {
    if (s.width % 2 || s.height % 2)
      throw std::runtime_error("video width and height must be even for yuv420p (got " +
                               std::to_string(s.width) + "x" + std::to_string(s.height) + ")");
    try {
      P.open_video();
    } catch (...) {
      P.release();
      if (!P.tmp.empty()) std::remove(P.tmp.c_str());
      throw;
    }
  }
  P.slots.assign(std::max(1, s.queue), std::vector<uint8_t>((size_t)s.width * s.height * 4));
  P.slot_index.assign(P.slots.size(), 0);
  P.slot_layer.assign(P.slots.size(), ScreenLayer{});
  P.worker = std::thread([this] { p_->run(); });
}

VideoWriter::~VideoWriter() {
  Impl& P = *p_;
  P.stop_worker();
  P.release();
  if (!P.finished && !P.tmp.empty()) std::remove(P.tmp.c_str());
}

uint8_t* VideoWriter::acquire() {
  Impl& P = *p_;
  std::unique_lock<std::mutex> lk(P.mu);
  P.cv_push.wait(lk, [&] { return P.filled < P.slots.size(); });
  if (!P.error.empty()) throw std::runtime_error(P.error);
  return P.slots[P.head].data();  // the caller is the only writer of this slot until commit()
}

void VideoWriter::commit(long index, const ScreenLayer* layer) {
  Impl& P = *p_;
  std::lock_guard<std::mutex> lk(P.mu);
  if (index < 0) index = P.next_index;
  if (index < P.next_index)
    throw std::logic_error("video frames must come in increasing order (frame " + std::to_string(index) +
                           " after " + std::to_string(P.next_index - 1) + ")");
  P.next_index = index + 1;
  P.slot_index[P.head] = index;
  // Vector assignment reuses the slot's storage: no allocation once the slots have grown.
  if (layer) {
    P.slot_layer[P.head] = *layer;
  } else {
    P.slot_layer[P.head].clear();
  }
  P.head = (P.head + 1) % P.slots.size();
  ++P.filled;
  ++P.nframes;
  P.cv_pop.notify_one();
}

void VideoWriter::push(const uint8_t* rgba, long index, const ScreenLayer* layer) {
  std::memcpy(acquire(), rgba, p_->slots[0].size());
  commit(index, layer);
}

void VideoWriter::finish() {
  Impl& P = *p_;
  P.stop_worker();
  if (!P.error.empty()) throw std::runtime_error(P.error);
  if (P.enc) {
    if (P.gif) P.gif->finish([&](AVFrame* f) { P.send(f); });  // pass 2: palette, frames mapped
    avcodec_send_frame(P.enc, nullptr);
    P.drain_packets();
    const int e = av_write_trailer(P.fmt);
    avio_closep(&P.fmt->pb);
    if (e < 0) throw std::runtime_error("cannot finish '" + P.s.path + "': " + av_err(e));
    std::error_code ec;
    std::filesystem::rename(P.tmp, P.s.path, ec);
    if (ec)
      throw std::runtime_error("cannot move the video into place at '" + P.s.path + "': " + ec.message());
  }
  P.finished = true;
}

long VideoWriter::frames() const {
  return p_->nframes;
}
std::string VideoWriter::encoder_name() const {
  return p_->enc && p_->enc->codec ? p_->enc->codec->name : "";
}
const std::string& VideoWriter::encoder_note() const {
  return p_->note;
}

double VideoWriter::encode_seconds() const {
  return p_->busy;
}

}  // namespace simreel
