#include "render/segment_join.hpp"

extern "C" {
#include <libavcodec/avcodec.h>
#include <libavformat/avformat.h>
}

#include <unistd.h>

#include <cmath>
#include <cstring>
#include <filesystem>
#include <stdexcept>

#include <simreel/error.hpp>
#include "render/av_error.hpp"

namespace simreel {

namespace {

struct Input {
  AVFormatContext* fmt = nullptr;
  int stream = -1;
  explicit Input(const std::string& path) {
    int e = avformat_open_input(&fmt, path.c_str(), nullptr, nullptr);
    if (e < 0) throw InputError(path + ": cannot open the segment (" + av_err(e) + ")");
    if ((e = avformat_find_stream_info(fmt, nullptr)) < 0)
      throw InputError(path + ": cannot read the segment (" + av_err(e) + ")");
    stream = av_find_best_stream(fmt, AVMEDIA_TYPE_VIDEO, -1, -1, nullptr, 0);
    if (stream < 0) throw InputError(path + ": the segment holds no video stream");
  }
  ~Input() { avformat_close_input(&fmt); }
  Input(const Input&) = delete;
  Input& operator=(const Input&) = delete;
  const AVStream* st() const { return fmt->streams[stream]; }
};

// What must be equal for a packet copy to be legal: the decoder is set up once, from the first
// segment's parameters and header bytes (H.264's SPS/PPS in avcC, VP9's codec private data).
std::string differs(const AVCodecParameters* a, const AVCodecParameters* b) {
  if (a->codec_id != b->codec_id)
    return std::string("codec ") + avcodec_get_name(b->codec_id) + ", not " + avcodec_get_name(a->codec_id);
  if (a->width != b->width || a->height != b->height)
    return std::to_string(b->width) + "x" + std::to_string(b->height) + " frames, not " +
           std::to_string(a->width) + "x" + std::to_string(a->height);
  if (a->format != b->format) return "another pixel format";
  if (a->extradata_size != b->extradata_size ||
      (a->extradata_size > 0 && std::memcmp(a->extradata, b->extradata, (size_t)a->extradata_size) != 0))
    return "other encoder settings (the stream's header bytes differ: another --crf, --encoder or size?)";
  return "";
}

}  // namespace

JoinResult join_segments(const std::vector<JoinSegment>& segments, double fps, const std::string& out) {
  if (segments.empty()) throw InputError("no segments to join");
  av_log_set_level(AV_LOG_ERROR);  // the muxer's +faststart pass is not news for the user's terminal
  namespace fs = std::filesystem;
  const fs::path target(out);
  const std::string tmp = (target.parent_path() / (target.stem().string() + ".partial-" +
                                                   std::to_string(getpid()) + target.extension().string()))
                              .string();
  AVFormatContext* ofmt = nullptr;
  AVPacket* pkt = av_packet_alloc();
  JoinResult result;
  bool opened = false;
  try {
    Input first(segments[0].path);
    if (avformat_alloc_output_context2(&ofmt, nullptr, nullptr, out.c_str()) < 0 || !ofmt)
      throw std::runtime_error("no video format for '" + out + "' (use .mp4, .mov, .mkv or .webm)");
    AVStream* ost = avformat_new_stream(ofmt, nullptr);
    avcodec_parameters_copy(ost->codecpar, first.st()->codecpar);
    ost->codecpar->codec_tag = 0;  // the output container chooses its own tag
    ost->time_base = first.st()->time_base;
    ost->avg_frame_rate = first.st()->avg_frame_rate;
    ost->r_frame_rate = first.st()->r_frame_rate;
    av_freep(&ofmt->url);
    ofmt->url = av_strdup(tmp.c_str());  // +faststart reopens its url
    int e = avio_open(&ofmt->pb, tmp.c_str(), AVIO_FLAG_WRITE);
    if (e < 0) throw std::runtime_error("cannot write '" + tmp + "': " + av_err(e));
    opened = true;
    AVDictionary* mopts = nullptr;
    const std::string ext = target.extension().string();
    if (ext == ".mp4" || ext == ".mov") av_dict_set(&mopts, "movflags", "+faststart", 0);
    e = avformat_write_header(ofmt, &mopts);
    av_dict_free(&mopts);
    if (e < 0) throw std::runtime_error("cannot start '" + out + "': " + av_err(e));

    const AVRational in_tb = first.st()->time_base;
    int64_t last_dts = AV_NOPTS_VALUE, max_pts = AV_NOPTS_VALUE;
    for (const JoinSegment& seg : segments) {
      Input in(seg.path);
      if (const std::string d = differs(first.st()->codecpar, in.st()->codecpar); !d.empty())
        throw InputError(seg.path + ": cannot be joined to " + segments[0].path +
                         " without re-encoding: " + d);
      if (av_cmp_q(in.st()->time_base, in_tb) != 0)
        throw InputError(seg.path + ": another time base than " + segments[0].path);
      // The frames it holds, by presentation time: exactly seg.first .. seg.last.
      long n = 0, lo = -1, hi = -1;
      while ((e = av_read_frame(in.fmt, pkt)) >= 0) {
        if (pkt->stream_index != in.stream) {
          av_packet_unref(pkt);
          continue;
        }
        if (pkt->pts == AV_NOPTS_VALUE) throw InputError(seg.path + ": a packet without a timestamp");
        const long k = std::lround((double)pkt->pts * av_q2d(in_tb) * fps);
        lo = n == 0 ? k : std::min(lo, k);
        hi = n == 0 ? k : std::max(hi, k);
        ++n;
        if (last_dts != AV_NOPTS_VALUE && pkt->dts != AV_NOPTS_VALUE && pkt->dts <= last_dts)
          throw InputError(seg.path + ": overlaps the segment before it (decoding times go back)");
        if (pkt->dts != AV_NOPTS_VALUE) last_dts = pkt->dts;
        max_pts = max_pts == AV_NOPTS_VALUE ? pkt->pts : std::max(max_pts, pkt->pts);
        pkt->stream_index = ost->index;
        av_packet_rescale_ts(pkt, in_tb, ost->time_base);
        pkt->pos = -1;
        if ((e = av_interleaved_write_frame(ofmt, pkt)) < 0)
          throw std::runtime_error("writing '" + out + "' failed: " + av_err(e));
        ++result.packets;
      }
      if (e != AVERROR_EOF) throw InputError(seg.path + ": cannot read a packet (" + av_err(e) + ")");
      if (n != seg.last - seg.first + 1 || lo != seg.first || hi != seg.last)
        throw InputError(seg.path + ": holds " + std::to_string(n) + " frames, " + std::to_string(lo) +
                         " to " + std::to_string(hi) + ", where frames " + std::to_string(seg.first) +
                         " to " + std::to_string(seg.last) + " were expected");
    }
    if ((e = av_write_trailer(ofmt)) < 0)
      throw std::runtime_error("cannot finish '" + out + "': " + av_err(e));
    avio_closep(&ofmt->pb);
    opened = false;
    result.duration = (double)max_pts * av_q2d(in_tb) + 1 / fps;
    std::error_code ec;
    fs::rename(tmp, out, ec);
    if (ec) throw std::runtime_error("cannot move the video into place at '" + out + "': " + ec.message());
  } catch (...) {
    if (opened) avio_closep(&ofmt->pb);
    if (ofmt) avformat_free_context(ofmt);
    av_packet_free(&pkt);
    std::error_code ec;
    fs::remove(tmp, ec);
    throw;
  }
  avformat_free_context(ofmt);
  av_packet_free(&pkt);
  return result;
}

}  // namespace simreel
