// Live sources with FFmpeg: libavformat's demuxers and protocols (UDP, RTP, RTSP, RTMP, SRT,
// HTTP, files), libavdevice's V4L2 input. The open and every read are bounded by an interrupt
// callback with a deadline (a source that never sends, a stream that stops) and by Stop(). Each
// video packet is copied into the recording (MPEG-TS, flushed packet by packet) and into a
// memory ring for clips, then decoded and scaled to grey for the analyses.

#include "acro/capture/live_source.h"

extern "C" {
#include <libavcodec/avcodec.h>
#include <libavdevice/avdevice.h>
#include <libavformat/avformat.h>
#include <libavutil/error.h>
#include <libavutil/opt.h>
#include <libswscale/swscale.h>
}

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <deque>
#include <map>
#include <mutex>
#include <thread>

#include <fmt/format.h>

#include "acro/base/file_io.h"
#include "acro/base/input_error.h"
#include "acro/base/temporaries.h"
#include "internal/ffmpeg.h"

namespace acro::capture {

double LiveClockNow() {
  static const auto origin = std::chrono::steady_clock::now();
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - origin).count();
}

namespace {

using internal::AvError;

void InitialiseFfmpegInputs() {
  static std::once_flag once;
  std::call_once(once, [] {
    avformat_network_init();
    avdevice_register_all();
  });
}

bool IsNetworkUrl(const std::string& url) {
  return url.find("://") != std::string::npos;
}

// A camera device: a character device, or a name under /dev/ that is not there (a camera
// unplugged). A regular file under /dev/shm is a file.
bool IsDevicePath(const std::string& url) {
  struct stat st {};
  if (::stat(url.c_str(), &st) == 0) return S_ISCHR(st.st_mode);
  return url.rfind("/dev/", 0) == 0;
}

}  // namespace

std::string RedactedUrl(const std::string& url) {
  const size_t scheme = url.find("://");
  if (scheme == std::string::npos) return url;
  const size_t host = scheme + 3;
  const size_t end = url.find_first_of("/?#", host);
  const size_t at = url.rfind('@', end == std::string::npos ? std::string::npos : end);
  if (at == std::string::npos || at < host) return url;
  return url.substr(0, host) + "***@" + url.substr(at + 1);
}

std::string LiveSourceName(const std::string& url) {
  std::string name;
  if (IsNetworkUrl(url)) {
    // Host and port, never a user name or password given before an '@'.
    name = url.substr(url.find("://") + 3);
    name = name.substr(0, name.find_first_of("/?#"));
    if (name.find('@') != std::string::npos) name = name.substr(name.rfind('@') + 1);
  } else {
    name = std::filesystem::path(url).stem().string();
  }
  for (char& c : name)
    if (!std::isalnum(static_cast<unsigned char>(c)) && c != '-' && c != '_') c = '_';
  return name.empty() ? std::string("source") : name;
}

namespace {

// One video packet kept for clips: its stream time and whether a clip may start there.
struct KeptPacket {
  AVPacket* packet = nullptr;
  double time_s = 0.0;
  bool key = false;
};

// An MPEG-TS file written as packets come: flushed after each one, so that what is on disk is
// always a playable stream (a TS reader resynchronises on the next packet start).
class TsWriter {
 public:
  TsWriter(const std::filesystem::path& path,
           const AVCodecParameters* in,
           AVRational in_time_base,
           bool exclusive)
      : path_(path), in_time_base_(in_time_base) {
    try {
      Open(in, exclusive);
    } catch (...) {
      Free();  // the destructor does not run for a constructor that throws
      throw;
    }
  }
  ~TsWriter() { Free(); }
  TsWriter(const TsWriter&) = delete;
  TsWriter& operator=(const TsWriter&) = delete;

 private:
  void Free() {
    if (out_ != nullptr) {
      if (out_->pb != nullptr) avio_closep(&out_->pb);
      avformat_free_context(out_);
      out_ = nullptr;
    }
  }
  void Open(const AVCodecParameters* in, bool exclusive) {
    const std::filesystem::path& path = path_;
    if (exclusive) {
      // Never replace what is there (a previous recording, a device, a link): created anew here.
      const int fd = ::open(path.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, 0644);
      if (fd < 0)
        throw InputError(path.string(),
                         "",
                         errno == EEXIST ? "already exists; a recording never replaces a file"
                                         : std::string("cannot be created: ") + strerror(errno));
      ::close(fd);
    }
    int rc = avformat_alloc_output_context2(&out_, nullptr, "mpegts", path.c_str());
    if (rc < 0 || out_ == nullptr) Fail("cannot make an MPEG-TS muxer: " + AvError(rc));
    AVStream* st = avformat_new_stream(out_, nullptr);
    if (st == nullptr) Fail("out of memory for the stream");
    rc = avcodec_parameters_copy(st->codecpar, in);
    if (rc < 0) Fail("cannot copy the stream's parameters: " + AvError(rc));
    st->codecpar->codec_tag = 0;
    st->time_base = in_time_base_;
    rc = avio_open(&out_->pb, path.c_str(), AVIO_FLAG_WRITE);
    if (rc < 0) Fail("cannot be opened for writing: " + AvError(rc));
    out_->flags |= AVFMT_FLAG_FLUSH_PACKETS;
    rc = avformat_write_header(out_, nullptr);
    if (rc < 0) Fail("cannot write the stream's header: " + AvError(rc));
    out_time_base_ = st->time_base;
  }

 public:
  void Write(const AVPacket* packet) {
    AVPacket* p = av_packet_clone(packet);
    if (p == nullptr) Fail("out of memory for a packet");
    p->stream_index = 0;
    av_packet_rescale_ts(p, in_time_base_, out_time_base_);
    const int rc = av_write_frame(out_, p);
    av_packet_free(&p);
    if (rc < 0) Fail("cannot be written (disk full?): " + AvError(rc));
    avio_flush(out_->pb);
    if (out_->pb->error < 0) Fail("cannot be written (disk full?): " + AvError(out_->pb->error));
    ++packets_;
  }
  void Close() {
    if (out_ == nullptr || out_->pb == nullptr) return;
    av_write_trailer(out_);
    avio_closep(&out_->pb);
  }
  long long packets() const { return packets_; }

 private:
  [[noreturn]] void Fail(const std::string& problem) const {
    throw InputError(path_.string(), "", problem);
  }
  std::filesystem::path path_;
  AVFormatContext* out_ = nullptr;
  AVRational in_time_base_, out_time_base_{1, 90000};
  long long packets_ = 0;
};

}  // namespace

struct LiveSource::Impl {
  std::string url, name;
  LiveSourceOptions options;
  AVFormatContext* format = nullptr;
  AVCodecContext* decoder = nullptr;
  SwsContext* scaler = nullptr;
  SwsContext* full_scaler = nullptr;
  AVPacket* packet = nullptr;
  AVFrame* frame = nullptr;
  int stream = -1;
  AVRational time_base{1, 1};
  int width = 0, height = 0, out_width = 0, out_height = 0;
  double fps = 0.0;

  // The blocking read's limits, checked by FFmpeg's interrupt callback.
  std::atomic<bool> stop{false};
  std::atomic<double> deadline{0.0};
  bool timed_out = false;

  // Times: the first packet's timestamp, the pace of a played file.
  std::int64_t first_pts = AV_NOPTS_VALUE;
  double pace_origin = -1.0;
  bool paced = false;
  bool started = false;  // a keyframe has come: packets before it decode to nothing
  std::map<std::int64_t, double> arrival_by_pts;  // packets sent to the decoder, not yet out
  // Where the input stood after each read (bytes taken from the stream) and when: a packet
  // arrived when its first byte did. A demuxer hands a packet over only when it is whole, and
  // MPEG-TS knows a picture is whole only when the next one begins — a frame later.
  std::deque<std::pair<std::int64_t, double>> read_log;
  double ArrivalOf(std::int64_t pos, double now) const {
    if (pos < 0 || paced) return now;
    for (const auto& [bytes, at] : read_log)
      if (bytes > pos) return at;
    return now;
  }

  // A source whose video MPEG-TS cannot carry (a webcam's raw YUYV or MJPEG) is encoded for the
  // recording and the clips: H.264 from the decoded frames, at full size.
  AVCodecContext* encoder = nullptr;
  AVCodecParameters* recorded_params = nullptr;  // what the recording and clips hold
  SwsContext* encode_scaler = nullptr;
  AVFrame* encode_frame = nullptr;
  AVPacket* encoded = nullptr;
  bool writer_ok = true;  // false once the recording could not be written
  void OpenEncoder(const AVStream* st);
  void Encode(const AVFrame* f);  // a decoded frame into the recording and the clips' memory
  void StoreEncoded();

  // Recording and clips.
  std::unique_ptr<TsWriter> writer;
  std::vector<std::filesystem::path> segments;
  double segment_start_s = 0.0;
  long long recorded = 0;
  std::deque<KeptPacket> kept;
  std::int64_t kept_bytes = 0;

  int decoded = 0;
  std::string end_reason;
  bool ended_normally = false;
  LiveEnd end_cause = LiveEnd::kRunning;
  bool draining = false;

  ~Impl() {
    try {
      if (writer) writer->Close();
    } catch (...) {
    }
    for (KeptPacket& k : kept) av_packet_free(&k.packet);
    avcodec_free_context(&encoder);
    avcodec_parameters_free(&recorded_params);
    sws_freeContext(encode_scaler);
    av_frame_free(&encode_frame);
    av_packet_free(&encoded);
    sws_freeContext(scaler);
    sws_freeContext(full_scaler);
    av_frame_free(&frame);
    av_packet_free(&packet);
    avcodec_free_context(&decoder);
    avformat_close_input(&format);
  }

  [[noreturn]] void Fail(const std::string& problem) const {
    throw InputError(RedactedUrl(url), "", problem);
  }

  bool Stopping() const { return stop.load() || (options.stop != nullptr && options.stop->load()); }
  static int Interrupt(void* opaque) {
    auto* self = static_cast<Impl*>(opaque);
    if (self->Stopping()) return 1;
    if (LiveClockNow() > self->deadline.load()) {
      self->timed_out = true;
      return 1;
    }
    return 0;
  }

  double StreamTime(std::int64_t pts) const {
    if (pts == AV_NOPTS_VALUE || first_pts == AV_NOPTS_VALUE) return 0.0;
    return static_cast<double>(pts - first_pts) * av_q2d(time_base);
  }

  void Open();
  void OpenSegment();
  void Record(const AVPacket* p, double time_s);
  void Keep(const AVPacket* p, double time_s);
  // Reads the next video packet into `packet`; false at the end (end_reason set).
  bool ReadPacket();
  bool Receive(LiveFrame* out);
  void Convert(const AVFrame* f, int w, int h, bool rgb, SwsContext** ctx, VideoFrame* out);
  void End(const std::string& reason, LiveEnd why) {
    if (end_reason.empty()) {
      end_reason = reason;
      end_cause = why;
      ended_normally = why == LiveEnd::kFileEnded;
    }
    // A copied stream's packets are all written: its recording closes now. An encoded source's
    // last frames may still come out of its decoder (Next drains it): its recording closes after
    // them — unless it cannot be written.
    if (encoder == nullptr || why == LiveEnd::kRecordError) CloseRecording();
  }
  // The encoder's last packets (none, tuned for no latency; asked for all the same) written, and
  // the recording closed. Once.
  void CloseRecording() {
    if (encoder != nullptr && writer_ok) {
      try {
        if (avcodec_send_frame(encoder, nullptr) >= 0) StoreEncoded();
      } catch (const InputError&) {
      }
    }
    if (writer) {
      writer->Close();
      writer.reset();
    }
    writer_ok = false;
  }
};

void LiveSource::Impl::Open() {
  InitialiseFfmpegInputs();
  internal::SilenceFfmpegLog();
  const AVInputFormat* input_format = nullptr;
  AVDictionary* opts = nullptr;
  if (IsDevicePath(url)) {
    struct stat st {};
    if (::stat(url.c_str(), &st) != 0) Fail("no such device");
    if (!S_ISCHR(st.st_mode)) Fail("not a camera device (not a character device)");
    input_format = av_find_input_format("video4linux2");
    if (input_format == nullptr) Fail("this FFmpeg has no V4L2 input");
  } else if (!IsNetworkUrl(url)) {
    std::error_code ec;
    if (!std::filesystem::is_regular_file(url, ec)) Fail("no such file, device or URL");
    paced = options.pace_files;
  } else if (url.rfind("udp://", 0) == 0) {
    // A receive buffer of its own thread's (FFmpeg's default), larger, and an overrun said rather
    // than fatal: a frame lost is better than a recording stopped.
    av_dict_set(&opts, "fifo_size", "65536", 0);
    av_dict_set(&opts, "buffer_size", "8388608", 0);
    av_dict_set(&opts, "overrun_nonfatal", "1", 0);
  }
  format = avformat_alloc_context();
  if (format == nullptr) Fail("out of memory");
  format->interrupt_callback.callback = &Impl::Interrupt;
  format->interrupt_callback.opaque = this;
  deadline = LiveClockNow() + options.open_timeout_s;
  timed_out = false;
  int rc = avformat_open_input(&format, url.c_str(), input_format, &opts);
  av_dict_free(&opts);
  if (rc < 0) {
    format = nullptr;  // freed by FFmpeg on failure
    if (Stopping()) Fail("stopped before it opened");
    if (timed_out)
      Fail(fmt::format("sent nothing within {:g} s (is it sending, to this address?)",
                       options.open_timeout_s));
    Fail("cannot be opened: " + AvError(rc));
  }
  // The packets read to learn the stream's size come out in a burst after it (their arrival
  // unknown): a keyframe and a few frames are enough, not FFmpeg's default 5 s.
  format->max_analyze_duration = AV_TIME_BASE / 2;
  format->fps_probe_size = 3;
  rc = avformat_find_stream_info(format, nullptr);
  if (rc < 0) {
    if (timed_out)
      Fail(fmt::format("sent no readable video within {:g} s", options.open_timeout_s));
    Fail("cannot read the stream information: " + AvError(rc));
  }
  const AVCodec* codec = nullptr;
  stream = av_find_best_stream(format, AVMEDIA_TYPE_VIDEO, -1, -1, &codec, 0);
  if (stream < 0 || codec == nullptr) Fail("no video stream that FFmpeg can decode");
  AVStream* st = format->streams[stream];
  time_base = st->time_base;
  width = st->codecpar->width;
  height = st->codecpar->height;
  if (width <= 0 || height <= 0 || width > 16384 || height > 16384)
    Fail(fmt::format("a picture {} x {} px", width, height));
  fps = st->r_frame_rate.den > 0 ? av_q2d(st->r_frame_rate) : 0.0;
  out_width = options.analysis_width > 0 ? std::min(options.analysis_width, width) : width;
  out_height = std::max(2, static_cast<int>(std::lround(double(height) * out_width / width)));
  decoder = avcodec_alloc_context3(codec);
  if (decoder == nullptr) Fail("out of memory for the decoder");
  rc = avcodec_parameters_to_context(decoder, st->codecpar);
  if (rc < 0) Fail("bad codec parameters: " + AvError(rc));
  decoder->thread_count = std::max(1, options.decoder_threads);
  rc = avcodec_open2(decoder, codec, nullptr);
  if (rc < 0) Fail("cannot open the " + std::string(codec->name) + " decoder: " + AvError(rc));
  packet = av_packet_alloc();
  frame = av_frame_alloc();
  if (packet == nullptr || frame == nullptr) Fail("out of memory");
  // The recording and the clips copy packets into MPEG-TS, which carries these; a webcam's raw
  // YUYV or MJPEG it does not (such a recording would not read back as video): those are encoded.
  const AVCodecID id = st->codecpar->codec_id;
  if (id != AV_CODEC_ID_H264 && id != AV_CODEC_ID_HEVC && id != AV_CODEC_ID_MPEG2VIDEO &&
      id != AV_CODEC_ID_MPEG1VIDEO && id != AV_CODEC_ID_MPEG4)
    OpenEncoder(st);
  recorded_params = avcodec_parameters_alloc();
  if (recorded_params == nullptr) Fail("out of memory");
  rc = encoder != nullptr ? avcodec_parameters_from_context(recorded_params, encoder)
                          : avcodec_parameters_copy(recorded_params, st->codecpar);
  if (rc < 0) Fail("cannot copy the stream's parameters: " + AvError(rc));
  if (!options.record_prefix.empty()) {
    std::error_code ec;
    std::filesystem::create_directories(options.record_prefix.parent_path(), ec);
  }
}

// H.264 for a source MPEG-TS cannot carry: x264 at CRF 18 (visually lossless), tuned for no
// latency (no B-frames, no look-ahead: each frame's packet comes out with it), a keyframe a second
// (where segments and clips can start), at the picture's full size (even: 4:2:0 needs it).
void LiveSource::Impl::OpenEncoder(const AVStream* st) {
  const AVCodec* h264 = avcodec_find_encoder_by_name("libx264");
  if (h264 == nullptr) h264 = avcodec_find_encoder(AV_CODEC_ID_H264);
  if (h264 == nullptr)
    Fail(
        fmt::format("sends {} video, which is recorded encoded as H.264, and this FFmpeg has no "
                    "H.264 encoder",
                    avcodec_get_name(st->codecpar->codec_id)));
  encoder = avcodec_alloc_context3(h264);
  encode_frame = av_frame_alloc();
  encoded = av_packet_alloc();
  if (encoder == nullptr || encode_frame == nullptr || encoded == nullptr)
    Fail("out of memory for the encoder");
  encoder->width = width & ~1;
  encoder->height = height & ~1;
  encoder->pix_fmt = AV_PIX_FMT_YUV420P;
  encoder->time_base = time_base;
  const AVRational rate =
      st->r_frame_rate.num > 0 && st->r_frame_rate.den > 0 ? st->r_frame_rate : AVRational{30, 1};
  encoder->framerate = rate;
  encoder->gop_size = std::max(1, static_cast<int>(std::lround(av_q2d(rate))));
  encoder->max_b_frames = 0;
  encoder->thread_count = 1;
  av_opt_set(encoder->priv_data, "preset", "ultrafast", 0);
  av_opt_set(encoder->priv_data, "tune", "zerolatency", 0);
  av_opt_set(encoder->priv_data, "crf", "18", 0);
  const int rc = avcodec_open2(encoder, h264, nullptr);
  if (rc < 0) Fail("cannot open the H.264 encoder for its recording: " + AvError(rc));
  encode_frame->format = encoder->pix_fmt;
  encode_frame->width = encoder->width;
  encode_frame->height = encoder->height;
  if (av_frame_get_buffer(encode_frame, 0) < 0) Fail("out of memory for the encoder's picture");
}

void LiveSource::Impl::Encode(const AVFrame* f) {
  if (f->width < encoder->width || f->height < encoder->height)
    throw InputError(RedactedUrl(url),
                     "",
                     fmt::format("its pictures changed size, {} x {} px to {} x {}: the recording "
                                 "stops here",
                                 width,
                                 height,
                                 f->width,
                                 f->height));
  if (av_frame_make_writable(encode_frame) < 0) Fail("out of memory for the encoder's picture");
  // (an odd last column and row cut off, not the picture resampled: the source's size read over
  // the encoder's)
  encode_scaler = sws_getCachedContext(encode_scaler,
                                       encoder->width,
                                       encoder->height,
                                       static_cast<AVPixelFormat>(f->format),
                                       encoder->width,
                                       encoder->height,
                                       AV_PIX_FMT_YUV420P,
                                       SWS_POINT,  // the same size: a conversion, no filter
                                       nullptr,
                                       nullptr,
                                       nullptr);
  if (encode_scaler == nullptr) Fail("cannot convert its pictures for the recording");
  sws_scale(encode_scaler,
            f->data,
            f->linesize,
            0,
            encoder->height,
            encode_frame->data,
            encode_frame->linesize);
  encode_frame->pts =
      f->best_effort_timestamp != AV_NOPTS_VALUE ? f->best_effort_timestamp : f->pts;
  const int rc = avcodec_send_frame(encoder, encode_frame);
  if (rc < 0) Fail("cannot encode a frame for its recording: " + AvError(rc));
  StoreEncoded();
}

void LiveSource::Impl::StoreEncoded() {
  while (avcodec_receive_packet(encoder, encoded) >= 0) {
    const std::int64_t p = encoded->pts != AV_NOPTS_VALUE ? encoded->pts : encoded->dts;
    const double t = StreamTime(p);
    Record(encoded, t);  // an InputError: the recording cannot be written (the caller ends)
    Keep(encoded, t);
    av_packet_unref(encoded);
  }
}

void LiveSource::Impl::OpenSegment() {
  if (writer) writer->Close();
  const std::filesystem::path path =
      options.record_prefix.string() + fmt::format("-{:03d}.ts", static_cast<int>(segments.size()));
  writer = std::make_unique<TsWriter>(path, recorded_params, time_base, true);
  segments.push_back(path);
}

void LiveSource::Impl::Record(const AVPacket* p, double time_s) {
  if (options.record_prefix.empty()) return;
  const bool key = (p->flags & AV_PKT_FLAG_KEY) != 0;
  if (!writer || (key && time_s - segment_start_s >= options.segment_s)) {
    OpenSegment();
    segment_start_s = time_s;
  }
  writer->Write(p);
  ++recorded;
}

void LiveSource::Impl::Keep(const AVPacket* p, double time_s) {
  KeptPacket k{av_packet_clone(p), time_s, (p->flags & AV_PKT_FLAG_KEY) != 0};
  if (k.packet == nullptr) Fail("out of memory for a packet");
  // Time that runs backwards (an encoder restarted in the stream) starts the memory afresh.
  if (!kept.empty() && time_s < kept.back().time_s - 1.0) {
    for (KeptPacket& old : kept) av_packet_free(&old.packet);
    kept.clear();
    kept_bytes = 0;
  }
  kept.push_back(k);
  kept_bytes += k.packet->size;
  // At most 256 MB whatever the stream's keyframes: the oldest packets go first.
  while (kept.size() > 1 && kept_bytes > (std::int64_t(256) << 20)) {
    kept_bytes -= kept.front().packet->size;
    av_packet_free(&kept.front().packet);
    kept.pop_front();
  }
  // Keep from the last keyframe at or before (now − memory): a clip can start there.
  const double keep_from = time_s - options.clip_memory_s;
  while (kept.size() > 1) {
    auto second_key =
        std::find_if(kept.begin() + 1, kept.end(), [](const KeptPacket& q) { return q.key; });
    if (second_key == kept.end() || second_key->time_s > keep_from) break;
    while (kept.begin() != second_key) {
      kept_bytes -= kept.front().packet->size;
      av_packet_free(&kept.front().packet);
      kept.pop_front();
      second_key =
          std::find_if(kept.begin(), kept.end(), [](const KeptPacket& q) { return q.key; });
    }
  }
}

bool LiveSource::Impl::ReadPacket() {
  for (;;) {
    // (timed_out stays set once the deadline has cut a read short: FFmpeg's I/O keeps that error
    // and later reads return it without asking again)
    deadline = LiveClockNow() + (started ? options.stall_timeout_s : options.open_timeout_s);
    av_packet_unref(packet);
    const int rc = av_read_frame(format, packet);
    if (rc < 0) {
      if (Stopping())
        End("stopped", LiveEnd::kStopped);
      else if (timed_out)
        End(fmt::format("stopped sending after {:g} s",
                        started ? options.stall_timeout_s : options.open_timeout_s),
            LiveEnd::kStalled);
      else if (rc == AVERROR_EOF && !IsNetworkUrl(url) && !IsDevicePath(url))
        End("the file ended", LiveEnd::kFileEnded);
      else if (rc == AVERROR_EOF)
        End("the stream ended (the sender closed it)", LiveEnd::kStreamEnded);
      else
        End("cannot be read: " + AvError(rc), LiveEnd::kReadError);
      return false;
    }
    const double now = LiveClockNow();
    if (format->pb != nullptr) {
      read_log.emplace_back(avio_tell(format->pb), now);
      if (read_log.size() > 512) read_log.pop_front();
    }
    if (packet->stream_index != stream || packet->size <= 0) continue;
    if (!started) {
      if (!(packet->flags & AV_PKT_FLAG_KEY)) continue;  // joined mid-GOP: wait for a keyframe
      started = true;
    }
    const std::int64_t p = packet->pts != AV_NOPTS_VALUE ? packet->pts : packet->dts;
    if (first_pts == AV_NOPTS_VALUE) first_pts = p;
    const double t = StreamTime(p);
    if (paced) {
      const std::int64_t d = packet->dts != AV_NOPTS_VALUE ? packet->dts : p;
      const double due = StreamTime(d);
      if (pace_origin < 0) pace_origin = LiveClockNow() - due;
      while (!Stopping()) {
        const double wait = pace_origin + due - LiveClockNow();
        if (wait <= 0) break;
        std::this_thread::sleep_for(std::chrono::duration<double>(std::min(wait, 0.05)));
      }
      if (Stopping()) {
        End("stopped", LiveEnd::kStopped);
        return false;
      }
    }
    if (encoder == nullptr) {  // (encoded sources are recorded as they are decoded)
      try {
        Record(packet, t);
      } catch (const InputError& e) {
        // A disk that fills, a file in the way: the recording stops here, closed, what is on disk
        // playable; the source ends with the line that names the file.
        writer.reset();
        End(std::string("recording stopped: ") + e.what(), LiveEnd::kRecordError);
        return false;
      }
      Keep(packet, t);
    }
    arrival_by_pts[p] = ArrivalOf(packet->pos, LiveClockNow());
    if (arrival_by_pts.size() > 256) arrival_by_pts.erase(arrival_by_pts.begin());
    return true;
  }
}

void LiveSource::Impl::Convert(
    const AVFrame* f, int w, int h, bool rgb, SwsContext** ctx, VideoFrame* out) {
  *ctx = sws_getCachedContext(*ctx,
                              f->width,
                              f->height,
                              static_cast<AVPixelFormat>(f->format),
                              w,
                              h,
                              rgb ? AV_PIX_FMT_RGB24 : AV_PIX_FMT_GRAY8,
                              SWS_AREA,
                              nullptr,
                              nullptr,
                              nullptr);
  if (*ctx == nullptr) Fail("cannot convert its pictures");
  out->width = w;
  out->height = h;
  out->channels = rgb ? 3 : 1;
  out->pixels.resize(static_cast<size_t>(w) * h * out->channels);
  std::uint8_t* dst[4] = {out->pixels.data(), nullptr, nullptr, nullptr};
  int stride[4] = {w * out->channels, 0, 0, 0};
  sws_scale(*ctx, f->data, f->linesize, 0, f->height, dst, stride);
}

bool LiveSource::Impl::Receive(LiveFrame* out) {
  const int rc = avcodec_receive_frame(decoder, frame);
  if (rc < 0) return false;
  const std::int64_t p =
      frame->best_effort_timestamp != AV_NOPTS_VALUE ? frame->best_effort_timestamp : frame->pts;
  out->picture.index = decoded++;
  out->picture.time_s = StreamTime(p);
  if (encoder != nullptr && writer_ok) {
    try {
      Encode(frame);
    } catch (const InputError& e) {
      // As for a copied packet: the recording stops here, closed and playable; the source ends
      // after this frame with the line that names the file.
      writer_ok = false;
      writer.reset();
      End(std::string("recording stopped: ") + e.what(), LiveEnd::kRecordError);
    }
  }
  const auto a = arrival_by_pts.find(p);
  out->arrival_s = a != arrival_by_pts.end() ? a->second : LiveClockNow();
  if (a != arrival_by_pts.end()) arrival_by_pts.erase(arrival_by_pts.begin(), std::next(a));
  Convert(frame,
          out_width,
          out_height,
          options.analysis_pixels == VideoPixels::kRgb,
          &scaler,
          &out->picture);
  return true;
}

LiveSource::LiveSource(const std::string& url, const LiveSourceOptions& options)
    : impl_(std::make_unique<Impl>()) {
  Impl& m = *impl_;
  m.url = url;
  m.options = options;
  m.name = options.name.empty() ? LiveSourceName(url) : options.name;
  if (!(options.open_timeout_s > 0) || !(options.stall_timeout_s > 0) || !(options.segment_s > 0) ||
      !(options.clip_memory_s >= 0))
    m.Fail("timeouts, segment length and clip memory must be positive");
  m.Open();
}

LiveSource::~LiveSource() = default;

bool LiveSource::Next(LiveFrame* out) {
  Impl& m = *impl_;
  for (;;) {
    if (m.Receive(out)) return true;
    if (m.draining || !m.end_reason.empty()) {
      m.CloseRecording();  // (an encoded source's: after the decoder's last frames)
      return false;
    }
    if (!m.ReadPacket()) {
      // Drain the decoder: the frames it still holds are part of what was sent.
      avcodec_send_packet(m.decoder, nullptr);
      m.draining = true;
      continue;
    }
    const int rc = avcodec_send_packet(m.decoder, m.packet);
    if (rc < 0 && rc != AVERROR(EAGAIN)) continue;  // a damaged packet: its frame is lost
  }
}

VideoFrame LiveSource::FullSizeGrey() {
  Impl& m = *impl_;
  VideoFrame out;
  if (m.frame->width <= 0) return out;
  m.Convert(m.frame, m.frame->width, m.frame->height, false, &m.full_scaler, &out);
  out.index = m.decoded - 1;
  if (m.encoder != nullptr && (out.width != m.encoder->width || out.height != m.encoder->height)) {
    // The size recorded (an odd last column and row cut for the H.264 encoding): the bed found
    // here must fit the clips' frames.
    const int w = std::min(out.width, m.encoder->width),
              h = std::min(out.height, m.encoder->height);
    std::vector<std::uint8_t> cut(static_cast<size_t>(w) * h);
    for (int y = 0; y < h; ++y)
      std::copy_n(out.pixels.begin() + static_cast<std::ptrdiff_t>(y) * out.width,
                  w,
                  cut.begin() + static_cast<std::ptrdiff_t>(y) * w);
    out.width = w;
    out.height = h;
    out.pixels = std::move(cut);
  }
  return out;
}

void LiveSource::Stop() {
  impl_->stop = true;
}

const std::string& LiveSource::name() const {
  return impl_->name;
}
const std::string& LiveSource::url() const {
  return impl_->url;
}
int LiveSource::width() const {
  return impl_->width;
}
int LiveSource::height() const {
  return impl_->height;
}
double LiveSource::nominal_fps() const {
  return impl_->fps;
}
const std::string& LiveSource::end_reason() const {
  return impl_->end_reason;
}
LiveEnd LiveSource::end_cause() const {
  return impl_->end_cause;
}
bool LiveSource::may_come_back() const {
  const LiveEnd c = impl_->end_cause;
  return (c == LiveEnd::kStalled || c == LiveEnd::kStreamEnded || c == LiveEnd::kReadError) &&
         (IsNetworkUrl(impl_->url) || IsDevicePath(impl_->url));
}
bool LiveSource::ended_normally() const {
  return impl_->ended_normally;
}
const std::vector<std::filesystem::path>& LiveSource::segments() const {
  return impl_->segments;
}
int LiveSource::frames_decoded() const {
  return impl_->decoded;
}
long long LiveSource::packets_recorded() const {
  return impl_->recorded;
}

double LiveSource::SaveClip(double from_s,
                            double to_s,
                            const std::filesystem::path& path,
                            double* end_s) const {
  const Impl& m = *impl_;
  if (!(to_s >= from_s)) throw InputError(path.string(), "", "a clip that ends before it starts");
  // The keyframe at or before `from_s`.
  auto start = m.kept.end();
  for (auto it = m.kept.begin(); it != m.kept.end(); ++it) {
    if (it->time_s > from_s) break;
    if (it->key) start = it;
  }
  if (start == m.kept.end()) {
    if (m.kept.empty() || !m.kept.front().key || m.kept.front().time_s > from_s + 1.0)
      throw InputError(
          path.string(), "", fmt::format("{:.2f} s of {} is no longer in memory", from_s, m.name));
    start = m.kept.begin();
  }
  const OutputTarget target = ResolveOutputTarget(path);
  const std::filesystem::path temp = TemporaryPathFor(target, ".ts");
  const ScopedTemporary registered(temp);
  try {
    TsWriter clip(temp, m.recorded_params, m.time_base, false);
    // Whole groups of pictures in decode order, up to the first keyframe after the end: a frame
    // shown before the end may refer to a packet timed after it (B-frames), so a cut inside a
    // group would leave frames that do not decode.
    double last = start->time_s;
    for (auto it = start; it != m.kept.end(); ++it) {
      if (it != start && it->key && it->time_s > to_s) break;
      clip.Write(it->packet);
      last = std::max(last, it->time_s);
    }
    if (end_s != nullptr) *end_s = last;
    clip.Close();
    RunUninterrupted([&] { PlaceFinishedOutput(temp, target); });
  } catch (...) {
    std::error_code ec;
    std::filesystem::remove(temp, ec);
    throw;
  }
  return start->time_s;
}

}  // namespace acro::capture
