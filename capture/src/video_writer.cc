// H.264 in MP4 with FFmpeg's libx264 wrapper: RGB frames padded to even sizes, converted to yuv420p
// with swscale, encoded with a constant rate factor, muxed with the index at the front
// (movflags +faststart), written to a temporary file and renamed when complete.

#include "acro/capture/video.h"

extern "C" {
#include <libavcodec/avcodec.h>
#include <libavformat/avformat.h>
#include <libavutil/error.h>
#include <libavutil/opt.h>
#include <libswscale/swscale.h>
}

#include <algorithm>
#include <cmath>
#include <condition_variable>
#include <deque>
#include <filesystem>
#include <mutex>
#include <optional>
#include <random>
#include <string>
#include <thread>

#include <fmt/format.h>

#include "acro/base/file_io.h"
#include "acro/base/input_error.h"
#include "acro/base/temporaries.h"
#include "internal/ffmpeg.h"

namespace acro::capture {
namespace {

using internal::AvError;

}  // namespace

struct VideoWriter::Impl {
  std::filesystem::path path, temp;
  OutputTarget target;
  int width = 0, height = 0;              // as given
  int coded_width = 0, coded_height = 0;  // even
  AVFormatContext* format = nullptr;
  AVCodecContext* encoder = nullptr;
  AVStream* stream = nullptr;
  AVFrame* frame = nullptr;
  AVPacket* packet = nullptr;
  SwsContext* scaler = nullptr;
  int written = 0;  // frames given to Write()
  int encoded = 0;  // frames sent to the encoder (by the encoding thread)
  bool finished = false;
  std::optional<ScopedTemporary> registered;  // the temporary file, while it exists

  // The encoding thread: Write() copies each frame (padded to the even size) into a free slot and
  // queues it; the thread converts it to yuv420p and encodes it, so that the caller draws the next
  // frame meanwhile. An error there is kept and thrown by the next Write() or Finish().
  static constexpr size_t kSlots = 3;
  std::thread worker;
  std::mutex mutex;
  std::condition_variable changed;
  std::deque<std::vector<std::uint8_t>> queued;  // RGB at the even size, in order
  std::vector<std::vector<std::uint8_t>> spare;  // slots to reuse
  size_t slots = 0;                              // slots made
  bool closing = false;
  std::optional<std::string> error;

  void Work() {
    for (;;) {
      std::vector<std::uint8_t> rgb;
      {
        std::unique_lock<std::mutex> lock(mutex);
        changed.wait(lock, [this] { return closing || !queued.empty(); });
        if (queued.empty()) return;
        rgb = std::move(queued.front());
        queued.pop_front();
      }
      try {
        if (!error) {
          int rc = av_frame_make_writable(frame);
          if (rc < 0) Fail("frame buffer: " + AvError(rc));
          const std::uint8_t* src[1] = {rgb.data()};
          const int src_stride[1] = {3 * coded_width};
          sws_scale(scaler, src, src_stride, 0, coded_height, frame->data, frame->linesize);
          frame->pts = encoded++;
          Encode(frame);
        }
      } catch (const std::exception& e) {
        const std::lock_guard<std::mutex> lock(mutex);
        error = e.what();
      }
      {
        const std::lock_guard<std::mutex> lock(mutex);
        spare.push_back(std::move(rgb));
      }
      changed.notify_all();
    }
  }

  // Stops the thread after the queued frames; true when it was running.
  bool StopWorker() {
    if (!worker.joinable()) return false;
    {
      const std::lock_guard<std::mutex> lock(mutex);
      closing = true;
    }
    changed.notify_all();
    worker.join();
    return true;
  }

  ~Impl() {
    StopWorker();
    sws_freeContext(scaler);
    av_frame_free(&frame);
    av_packet_free(&packet);
    avcodec_free_context(&encoder);
    if (format != nullptr) {
      if (format->pb != nullptr) avio_closep(&format->pb);
      avformat_free_context(format);
    }
    if (!finished && !temp.empty()) {
      std::error_code ec;
      std::filesystem::remove(temp, ec);
    }
  }

  [[noreturn]] void Fail(const std::string& problem) const {
    throw InputError(path.string(), "", problem);
  }

  // Sends a frame (or the end, nullptr) and writes every packet the encoder returns.
  void Encode(AVFrame* input) {
    int rc = avcodec_send_frame(encoder, input);
    if (rc < 0) Fail("the encoder refused a frame: " + AvError(rc));
    for (;;) {
      rc = avcodec_receive_packet(encoder, packet);
      if (rc == AVERROR(EAGAIN) || rc == AVERROR_EOF) return;
      if (rc < 0) Fail("encoding failed: " + AvError(rc));
      av_packet_rescale_ts(packet, encoder->time_base, stream->time_base);
      packet->stream_index = stream->index;
      rc = av_interleaved_write_frame(format, packet);
      if (rc < 0) Fail("writing failed (disk full?): " + AvError(rc));
    }
  }
};

VideoWriter::VideoWriter(const std::filesystem::path& path,
                         int width,
                         int height,
                         const VideoWriterOptions& options)
    : impl_(std::make_unique<Impl>()) {
  internal::SilenceFfmpegLog();
  Impl& m = *impl_;
  m.path = path;
  if (width <= 0 || height <= 0 || width > 16384 || height > 16384)
    m.Fail(fmt::format("a video cannot be {} x {} pixels", width, height));
  if (!(options.fps > 0.0 && options.fps <= 1000.0))
    m.Fail(fmt::format("frame rate {} is not in (0, 1000]", options.fps));
  m.width = width;
  m.height = height;
  m.coded_width = width + (width % 2);
  m.coded_height = height + (height % 2);
  // Through a link to its target, into /dev/null or a FIFO by a copy when finished (OutputTarget).
  m.target = ResolveOutputTarget(path);
  m.temp = TemporaryPathFor(m.target, ".mp4");
  m.registered.emplace(m.temp);

  // The encoder: libx264, yuv420p, constant quality, one keyframe a second.
  const AVCodec* codec = avcodec_find_encoder_by_name("libx264");
  if (codec == nullptr) codec = avcodec_find_encoder(AV_CODEC_ID_H264);
  if (codec == nullptr) m.Fail("this FFmpeg has no H.264 encoder");
  int rc = avformat_alloc_output_context2(&m.format, nullptr, "mp4", m.temp.c_str());
  if (rc < 0 || m.format == nullptr) m.Fail("cannot make an MP4 muxer: " + AvError(rc));
  m.stream = avformat_new_stream(m.format, nullptr);
  m.encoder = avcodec_alloc_context3(codec);
  if (m.stream == nullptr || m.encoder == nullptr) m.Fail("out of memory for the encoder");
  const AVRational rate = av_d2q(options.fps, 100000);
  m.encoder->width = m.coded_width;
  m.encoder->height = m.coded_height;
  m.encoder->pix_fmt = AV_PIX_FMT_YUV420P;
  m.encoder->time_base = av_inv_q(rate);
  m.encoder->framerate = rate;
  m.encoder->gop_size = std::max(1, static_cast<int>(std::lround(options.fps)));
  m.encoder->thread_count =
      options.num_threads > 0 ? options.num_threads
                              : static_cast<int>(std::max(1u, std::thread::hardware_concurrency()));
  if (m.format->oformat->flags & AVFMT_GLOBALHEADER)
    m.encoder->flags |= AV_CODEC_FLAG_GLOBAL_HEADER;
  av_opt_set(m.encoder->priv_data, "preset", options.preset.c_str(), 0);
  av_opt_set(m.encoder->priv_data, "crf", std::to_string(options.crf).c_str(), 0);
  rc = avcodec_open2(m.encoder, codec, nullptr);
  if (rc < 0) m.Fail("cannot open the H.264 encoder: " + AvError(rc));
  rc = avcodec_parameters_from_context(m.stream->codecpar, m.encoder);
  if (rc < 0) m.Fail("bad encoder parameters: " + AvError(rc));
  m.stream->time_base = m.encoder->time_base;
  m.stream->avg_frame_rate = rate;

  // The file, index at the front.
  rc = avio_open(&m.format->pb, m.temp.c_str(), AVIO_FLAG_WRITE);
  if (rc < 0) m.Fail("cannot create the output: " + AvError(rc));
  AVDictionary* muxer_options = nullptr;
  av_dict_set(&muxer_options, "movflags", "+faststart", 0);
  rc = avformat_write_header(m.format, &muxer_options);
  av_dict_free(&muxer_options);
  if (rc < 0) m.Fail("cannot write the MP4 header: " + AvError(rc));

  m.frame = av_frame_alloc();
  m.packet = av_packet_alloc();
  m.frame->format = AV_PIX_FMT_YUV420P;
  m.frame->width = m.coded_width;
  m.frame->height = m.coded_height;
  rc = av_frame_get_buffer(m.frame, 0);
  if (rc < 0) m.Fail("out of memory for a frame: " + AvError(rc));
  m.scaler = sws_getContext(m.coded_width,
                            m.coded_height,
                            AV_PIX_FMT_RGB24,
                            m.coded_width,
                            m.coded_height,
                            AV_PIX_FMT_YUV420P,
                            SWS_BICUBIC,
                            nullptr,
                            nullptr,
                            nullptr);
  if (m.scaler == nullptr) m.Fail("no RGB to yuv420p conversion");
  m.worker = std::thread([&m] { m.Work(); });
}

VideoWriter::~VideoWriter() = default;

int VideoWriter::frames_written() const {
  return impl_->written;
}

void VideoWriter::Write(const std::vector<std::uint8_t>& rgb) {
  Impl& m = *impl_;
  if (m.finished || m.closing) m.Fail("a frame after Finish()");
  if (rgb.size() != 3 * static_cast<size_t>(m.width) * m.height)
    m.Fail(fmt::format(
        "frame {} has {} bytes, not {} x {} RGB", m.written, rgb.size(), m.width, m.height));
  // A free slot: a spare one, a new one while fewer than kSlots exist, or wait for the encoder.
  std::vector<std::uint8_t> slot;
  {
    std::unique_lock<std::mutex> lock(m.mutex);
    m.changed.wait(
        lock, [&m] { return m.error.has_value() || !m.spare.empty() || m.slots < Impl::kSlots; });
    if (m.error) throw InputError("", "", *m.error);  // it names the file
    if (!m.spare.empty()) {
      slot = std::move(m.spare.back());
      m.spare.pop_back();
    } else {
      ++m.slots;
      // Padded rows (swscale reads whole vectors) at the even size.
      slot.assign(3 * static_cast<size_t>(m.coded_width) * m.coded_height + 64, 0);
    }
  }
  // Copy into the even-sized picture, repeating the last column and row.
  const size_t row = 3 * static_cast<size_t>(m.coded_width);
  for (int y = 0; y < m.height; ++y) {
    std::uint8_t* dst = slot.data() + y * row;
    std::copy_n(rgb.data() + 3 * static_cast<size_t>(y) * m.width, 3 * m.width, dst);
    if (m.coded_width > m.width) std::copy_n(dst + 3 * (m.width - 1), 3, dst + 3 * m.width);
  }
  if (m.coded_height > m.height)
    std::copy_n(slot.data() + (m.height - 1) * row, row, slot.data() + m.height * row);
  {
    const std::lock_guard<std::mutex> lock(m.mutex);
    m.queued.push_back(std::move(slot));
  }
  m.changed.notify_all();
  ++m.written;
}

void VideoWriter::Finish() {
  Impl& m = *impl_;
  if (m.finished) return;
  if (m.written == 0) m.Fail("no frame was written");
  m.StopWorker();  // encodes what is queued
  if (m.error) throw InputError("", "", *m.error);
  m.Encode(nullptr);
  int rc = av_write_trailer(m.format);
  if (rc < 0) m.Fail("cannot write the MP4 index: " + AvError(rc));
  avio_closep(&m.format->pb);
  m.finished = true;  // the temporary is PlaceFinishedOutput's from here
  // As one step the interrupt handler waits for, and counts as kept: a Ctrl-C just after the rename
  // must not find a finished video it does not know about.
  RunUninterrupted([&m] { PlaceFinishedOutput(m.temp, m.target); });
}

}  // namespace acro::capture
