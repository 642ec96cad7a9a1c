// Decodes a video file with libavformat/libavcodec, for tests that check what was written.
#pragma once
extern "C" {
#include <libavcodec/avcodec.h>
#include <libavformat/avformat.h>
#include <libavutil/pixdesc.h>
#include <libswscale/swscale.h>
}

#include <string>
#include <vector>

namespace simreel::test {

// Decodes a video file: codec, pixel format, size, frame count, rate, duration, first frame RGBA;
// with `all`, every frame's RGBA and time (s).
struct Decoded {
  std::string codec, pix_fmt, chroma_location;
  int width = 0, height = 0, frames = 0;
  double fps = 0, duration = 0;
  std::vector<uint8_t> first_rgba;
  std::vector<std::vector<uint8_t>> rgba;  ///< with `all`
  std::vector<double> times;               ///< with `all`
};
inline Decoded decode(const std::string& path, bool all = false) {
  Decoded d;
  AVFormatContext* fmt = nullptr;
  if (avformat_open_input(&fmt, path.c_str(), nullptr, nullptr) < 0) return d;
  avformat_find_stream_info(fmt, nullptr);
  const int si = av_find_best_stream(fmt, AVMEDIA_TYPE_VIDEO, -1, -1, nullptr, 0);
  AVStream* st = fmt->streams[si];
  const AVCodec* codec = avcodec_find_decoder(st->codecpar->codec_id);
  AVCodecContext* dec = avcodec_alloc_context3(codec);
  avcodec_parameters_to_context(dec, st->codecpar);
  avcodec_open2(dec, codec, nullptr);
  d.codec = codec->name;
  d.pix_fmt = av_get_pix_fmt_name((AVPixelFormat)st->codecpar->format);
  if (const char* cl = av_chroma_location_name(st->codecpar->chroma_location)) d.chroma_location = cl;
  d.width = st->codecpar->width;
  d.height = st->codecpar->height;
  d.fps = av_q2d(st->avg_frame_rate);
  d.duration = fmt->duration / (double)AV_TIME_BASE;
  AVPacket* pkt = av_packet_alloc();
  AVFrame* fr = av_frame_alloc();
  auto take = [&] {
    while (avcodec_receive_frame(dec, fr) == 0) {
      if (d.frames++ == 0 || all) {
        d.first_rgba.resize((size_t)fr->width * fr->height * 4);
        SwsContext* sws =
            sws_getContext(fr->width, fr->height, (AVPixelFormat)fr->format, fr->width, fr->height,
                           AV_PIX_FMT_RGBA, SWS_BILINEAR, nullptr, nullptr, nullptr);
        const int* coef = sws_getCoefficients(SWS_CS_ITU709);
        sws_setColorspaceDetails(sws, coef, 0, coef, 1, 0, 1 << 16, 1 << 16);
        uint8_t* dst[1] = {d.first_rgba.data()};
        const int stride[1] = {fr->width * 4};
        sws_scale(sws, fr->data, fr->linesize, 0, fr->height, dst, stride);
        sws_freeContext(sws);
        if (all) {
          d.rgba.push_back(d.first_rgba);
          d.times.push_back(fr->best_effort_timestamp * av_q2d(st->time_base));
        }
      }
    }
  };
  while (av_read_frame(fmt, pkt) >= 0) {
    if (pkt->stream_index == si) {
      avcodec_send_packet(dec, pkt);
      take();
    }
    av_packet_unref(pkt);
  }
  avcodec_send_packet(dec, nullptr);
  take();
  if (all && !d.rgba.empty()) d.first_rgba = d.rgba.front();
  av_frame_free(&fr);
  av_packet_free(&pkt);
  avcodec_free_context(&dec);
  avformat_close_input(&fmt);
  return d;
}

}  // namespace simreel::test
