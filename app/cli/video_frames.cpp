#include "app/cli/video_frames.hpp"

extern "C" {
#include <libavcodec/avcodec.h>
#include <libavformat/avformat.h>
#include <libswscale/swscale.h>
}

#include <simreel/error.hpp>

namespace simreel {

struct VideoFrames::Impl {
  std::string path;
  AVFormatContext* fmt = nullptr;
  AVCodecContext* dec = nullptr;
  AVPacket* pkt = nullptr;
  AVFrame* frame = nullptr;
  SwsContext* sws = nullptr;
  int stream = -1;
  double time_base = 0, start = 0;
  bool flushed = false, done = false;

  ~Impl() {
    sws_freeContext(sws);
    av_frame_free(&frame);
    av_packet_free(&pkt);
    avcodec_free_context(&dec);
    if (fmt) avformat_close_input(&fmt);
  }

  void convert(Image& out) {
    out.width = frame->width;
    out.height = frame->height;
    out.rgba.resize((size_t)out.width * out.height * 4);
    sws = sws_getCachedContext(sws, frame->width, frame->height, (AVPixelFormat)frame->format, frame->width,
                               frame->height, AV_PIX_FMT_RGBA, SWS_BILINEAR, nullptr, nullptr, nullptr);
    if (!sws) throw InputError(path + ": cannot convert its pixel format to RGBA");
    // simreel writes BT.709 limited range (render/yuv.hpp); honour what the stream says.
    const int cs = frame->colorspace == AVCOL_SPC_BT470BG || frame->colorspace == AVCOL_SPC_SMPTE170M
                       ? SWS_CS_ITU601
                       : SWS_CS_ITU709;
    const int* coef = sws_getCoefficients(cs);
    const int src_full = frame->color_range == AVCOL_RANGE_JPEG ? 1 : 0;
    sws_setColorspaceDetails(sws, coef, src_full, coef, 1, 0, 1 << 16, 1 << 16);
    uint8_t* dst[1] = {out.rgba.data()};
    const int stride[1] = {out.width * 4};
    sws_scale(sws, frame->data, frame->linesize, 0, frame->height, dst, stride);
  }
};

VideoFrames::VideoFrames(const std::string& path) : p_(std::make_unique<Impl>()) {
  Impl& P = *p_;
  P.path = path;
  av_log_set_level(AV_LOG_ERROR);
  if (avformat_open_input(&P.fmt, path.c_str(), nullptr, nullptr) < 0)
    throw InputError(path + ": not a video simreel can read");
  if (avformat_find_stream_info(P.fmt, nullptr) < 0)
    throw InputError(path + ": cannot read the video's streams");
  P.stream = av_find_best_stream(P.fmt, AVMEDIA_TYPE_VIDEO, -1, -1, nullptr, 0);
  if (P.stream < 0) throw InputError(path + ": holds no video stream");
  AVStream* st = P.fmt->streams[P.stream];
  const AVCodec* codec = avcodec_find_decoder(st->codecpar->codec_id);
  if (!codec) throw InputError(path + ": no decoder for its video codec");
  P.dec = avcodec_alloc_context3(codec);
  if (!P.dec || avcodec_parameters_to_context(P.dec, st->codecpar) < 0 ||
      avcodec_open2(P.dec, codec, nullptr) < 0)
    throw InputError(path + ": cannot open its video decoder");
  P.pkt = av_packet_alloc();
  P.frame = av_frame_alloc();
  P.time_base = av_q2d(st->time_base);
  // Timestamps are the stream's own, so a partial render (render --frames 40:49, whose first
  // frame is stamped 40 / fps) lines up with the same frames of a full one. Only formats whose
  // clock starts anywhere (MPEG-TS: AVFMT_TS_DISCONT) count from their first timestamp.
  if ((P.fmt->iformat->flags & AVFMT_TS_DISCONT) && st->start_time != AV_NOPTS_VALUE)
    P.start = (double)st->start_time * P.time_base;
}

VideoFrames::~VideoFrames() = default;

bool VideoFrames::next(Image& out, double& time) {
  Impl& P = *p_;
  for (;;) {
    const int r = avcodec_receive_frame(P.dec, P.frame);
    if (r == 0) {
      const int64_t pts = P.frame->best_effort_timestamp;
      time = pts == AV_NOPTS_VALUE ? 0.0 : (double)pts * P.time_base - P.start;
      P.convert(out);
      return true;
    }
    if (r == AVERROR_EOF) return false;
    if (r != AVERROR(EAGAIN)) throw InputError(P.path + ": the video's data is corrupt");
    if (P.flushed) return false;
    // Feed the decoder the next packet of our stream.
    for (;;) {
      const int e = av_read_frame(P.fmt, P.pkt);
      if (e < 0) {
        avcodec_send_packet(P.dec, nullptr);
        P.flushed = true;
        break;
      }
      const bool ours = P.pkt->stream_index == P.stream;
      if (ours && avcodec_send_packet(P.dec, P.pkt) < 0) {
        av_packet_unref(P.pkt);
        throw InputError(P.path + ": the video's data is corrupt");
      }
      av_packet_unref(P.pkt);
      if (ours) break;
    }
  }
}

double VideoFrames::fps() const {
  // The base rate first: a partial render with gaps (render --frames 40:49,100) averages 5.4
  // frames per second over its span, but it is a 30 fps video.
  const AVStream* st = p_->fmt->streams[p_->stream];
  if (st->r_frame_rate.den && st->r_frame_rate.num > 0) return av_q2d(st->r_frame_rate);
  return st->avg_frame_rate.den ? av_q2d(st->avg_frame_rate) : 0.0;
}
int VideoFrames::width() const {
  return p_->dec->width;
}
int VideoFrames::height() const {
  return p_->dec->height;
}

}  // namespace simreel
