// Frame-exact video input with FFmpeg (libavformat, libavcodec, libswscale). The packet index is
// built on open; random access seeks to the keyframe before the target in presentation order and
// decodes forward to the target's timestamp, stepping back a keyframe when the target is a leading
// picture of an open GOP. Colour conversion to RGB24 uses the frame's own YUV matrix and range
// with bicubic chroma (as the ffmpeg command line's scaler does), then the display rotation.

#include "acro/capture/video.h"

extern "C" {
#include <libavcodec/avcodec.h>
#include <libavformat/avformat.h>
#include <libavutil/display.h>
#include <libavutil/error.h>
#include <libswscale/swscale.h>
}

#include <algorithm>
#include <array>
#include <atomic>
#include <cmath>
#include <cstring>
#include <thread>

#include <fmt/format.h>

#include "acro/base/input_error.h"
#include "internal/ffmpeg.h"

namespace acro::capture {
namespace {

// A field FFmpeg copies from the bitstream unchecked (colour space, colour range), read as the int
// it is stored as: a damaged file holds any number there, which is no value of the enum, and
// loading it as one is undefined (UBSan's finding on the video corpus).
template <class Enum>
int StoredInt(const Enum& field) {
  static_assert(sizeof(Enum) == sizeof(int));
  int value = 0;
  std::memcpy(&value, &field, sizeof(int));
  return value;
}

using internal::AvError;

// The clockwise rotation (0, 90, 180, 270) that shows the stream upright, from its display
// matrix, as the ffmpeg command line's autorotation reads it.
int DisplayRotation(const AVStream* stream) {
  const std::uint8_t* matrix = av_stream_get_side_data(stream, AV_PKT_DATA_DISPLAYMATRIX, nullptr);
  if (matrix == nullptr) return 0;
  double theta =
      -std::round(av_display_rotation_get(reinterpret_cast<const std::int32_t*>(matrix)));
  theta -= 360.0 * std::floor(theta / 360.0 + 0.9 / 360.0);
  for (int r : {90, 180, 270})
    if (std::abs(theta - r) < 1.0) return r;
  return 0;
}

// Rotates an RGB image clockwise by 90, 180 or 270 degrees.
void RotatePixels(int rotation_deg, VideoFrame* f) {
  if (rotation_deg == 0) return;
  const int w = f->width, h = f->height, c = f->channels;
  std::vector<std::uint8_t> out(f->pixels.size());
  const bool quarter = rotation_deg != 180;
  const int ow = quarter ? h : w;
  for (int y = 0; y < h; ++y) {
    for (int x = 0; x < w; ++x) {
      int ox = 0, oy = 0;
      if (rotation_deg == 90) {
        ox = h - 1 - y;
        oy = x;
      } else if (rotation_deg == 180) {
        ox = w - 1 - x;
        oy = h - 1 - y;
      } else {
        ox = y;
        oy = w - 1 - x;
      }
      std::copy_n(&f->pixels[c * (static_cast<size_t>(y) * w + x)],
                  c,
                  &out[c * (static_cast<size_t>(oy) * ow + ox)]);
    }
  }
  f->pixels.swap(out);
  if (quarter) std::swap(f->width, f->height);
}

}  // namespace

struct VideoReader::Impl {
  std::string path;
  VideoInfo info;
  AVFormatContext* format = nullptr;
  AVCodecContext* decoder = nullptr;
  SwsContext* scaler = nullptr;
  AVPacket* packet = nullptr;
  AVFrame* frame = nullptr;
  int stream = -1;
  AVRational time_base{1, 1};
  std::vector<std::int64_t> pts;           // presentation order
  std::vector<std::int64_t> keyframe_pts;  // ascending
  std::vector<double> times_s;
  bool input_done = false;            // the demuxer is at its end: the decoder is being drained
  int next_sequential = 0;            // index the next ReadNext returns
  std::vector<std::uint8_t> scratch;  // swscale's output, rows padded
  std::int64_t last_pts = AV_NOPTS_VALUE;  // of the last frame decoded since the last seek
  // Random access: the frame wanted. Packets of frames shown before it are sent with
  // skip_frame = AVDISCARD_NONREF: a frame no other frame refers to is not decoded at all, which
  // cannot change any frame that is decoded (by definition of a non-reference frame), so the
  // output stays bit-exact; frames shown after it are all decoded, so that a sequential pass or a
  // forward step can go on from the target. AV_NOPTS_VALUE: decode everything.
  std::int64_t wanted_pts = AV_NOPTS_VALUE;
  VideoPixels pixels = VideoPixels::kRgb;  // what Convert hands out
  // GreyFromLuma's table, for one pixel format and range.
  std::array<std::uint8_t, 256> grey_table{};
  AVPixelFormat grey_table_format = AV_PIX_FMT_NONE;
  int grey_table_range = -1;

  ~Impl() {
    sws_freeContext(scaler);
    av_frame_free(&frame);
    av_packet_free(&packet);
    avcodec_free_context(&decoder);
    avformat_close_input(&format);
  }

  [[noreturn]] void Fail(const std::string& where, const std::string& problem) const {
    throw InputError(path, where, problem);
  }

  void Open(const VideoReaderOptions& options);
  // Grey straight from the luma plane when the format allows; false: use swscale.
  bool GreyFromLuma(VideoFrame* out);
  void Index();
  void Rewind(std::int64_t to_pts);
  // The next decoded frame in presentation order into `frame`; false at the end of the stream.
  bool DecodeNext();
  int IndexOfPts(std::int64_t p) const;
  // The decoded frame as RGB into *out (whose pixel buffer is reused).
  void Convert(int index, VideoFrame* out);
};

void VideoReader::Impl::Open(const VideoReaderOptions& options) {
  // Container and stream.
  int rc = avformat_open_input(&format, path.c_str(), nullptr, nullptr);
  if (rc < 0) Fail("", "cannot open as a video: " + AvError(rc));
  rc = avformat_find_stream_info(format, nullptr);
  if (rc < 0) Fail("", "cannot read the stream information: " + AvError(rc));
  const AVCodec* codec = nullptr;
  stream = av_find_best_stream(format, AVMEDIA_TYPE_VIDEO, -1, -1, &codec, 0);
  if (stream < 0 || codec == nullptr) Fail("", "no video stream that FFmpeg can decode");
  AVStream* st = format->streams[stream];
  time_base = st->time_base;

  // Decoder, threaded.
  decoder = avcodec_alloc_context3(codec);
  if (decoder == nullptr) Fail("", "out of memory for the decoder");
  rc = avcodec_parameters_to_context(decoder, st->codecpar);
  if (rc < 0) Fail("", "bad codec parameters: " + AvError(rc));
  pixels = options.pixels;
  decoder->thread_count = options.num_threads > 0
                              ? options.num_threads
                              : static_cast<int>(std::max(1u, std::thread::hardware_concurrency()));
  decoder->thread_type = FF_THREAD_FRAME | FF_THREAD_SLICE;
  rc = avcodec_open2(decoder, codec, nullptr);
  if (rc < 0) Fail("", "cannot open the " + std::string(codec->name) + " decoder: " + AvError(rc));
  packet = av_packet_alloc();
  frame = av_frame_alloc();

  // What the file says about itself.
  info.path = path;
  info.container = format->iformat->name;
  info.codec = codec->name;
  info.coded_width = st->codecpar->width;
  info.coded_height = st->codecpar->height;
  info.rotation_deg = DisplayRotation(st);
  const bool quarter = info.rotation_deg == 90 || info.rotation_deg == 270;
  info.width = quarter ? info.coded_height : info.coded_width;
  info.height = quarter ? info.coded_width : info.coded_height;
  info.nominal_fps = st->r_frame_rate.den > 0 ? av_q2d(st->r_frame_rate) : 0.0;
  for (unsigned s = 0; s < format->nb_streams; ++s) {
    const AVCodecParameters* p = format->streams[s]->codecpar;
    if (p->codec_type == AVMEDIA_TYPE_AUDIO)
      info.audio_codecs.push_back(avcodec_get_name(p->codec_id));
  }
  Index();
}

void VideoReader::Impl::Index() {
  // Every packet of the video stream, in file order: its presentation time and whether it is a
  // keyframe. Damage ends the index: the frames before it stay readable.
  for (;;) {
    const int rc = av_read_frame(format, packet);
    if (rc < 0) break;
    if (packet->stream_index == stream && packet->size > 0 &&
        !(packet->flags & AV_PKT_FLAG_DISCARD)) {
      const std::int64_t p = packet->pts != AV_NOPTS_VALUE ? packet->pts : packet->dts;
      if (p != AV_NOPTS_VALUE) {
        pts.push_back(p);
        if (packet->flags & AV_PKT_FLAG_KEY) keyframe_pts.push_back(p);
      }
    }
    av_packet_unref(packet);
  }
  if (pts.empty()) Fail("", "the video stream holds no frame");
  std::sort(pts.begin(), pts.end());
  pts.erase(std::unique(pts.begin(), pts.end()), pts.end());
  std::sort(keyframe_pts.begin(), keyframe_pts.end());
  if (keyframe_pts.empty() || keyframe_pts.front() > pts.front())
    keyframe_pts.insert(keyframe_pts.begin(), pts.front());

  // Times from the first frame, rates, regularity.
  const double tb = av_q2d(time_base);
  info.num_frames = static_cast<int>(pts.size());
  info.num_keyframes = static_cast<int>(keyframe_pts.size());
  info.start_time_s = pts.front() * tb;
  times_s.resize(pts.size());
  for (size_t i = 0; i < pts.size(); ++i) times_s[i] = (pts[i] - pts.front()) * tb;
  std::vector<double> intervals;
  for (size_t i = 1; i < times_s.size(); ++i) intervals.push_back(times_s[i] - times_s[i - 1]);
  double median = info.nominal_fps > 0 ? 1.0 / info.nominal_fps : 0.0;
  if (!intervals.empty()) {
    std::vector<double> sorted = intervals;
    std::nth_element(sorted.begin(), sorted.begin() + sorted.size() / 2, sorted.end());
    median = sorted[sorted.size() / 2];
    const auto [lo, hi] = std::minmax_element(intervals.begin(), intervals.end());
    info.variable_frame_rate = *hi - *lo > 0.1 * median;
    info.average_fps = (info.num_frames - 1) / times_s.back();
  } else {
    info.average_fps = info.nominal_fps;
  }
  info.duration_s = times_s.back() + median;
  Rewind(pts.front());
}

void VideoReader::Impl::Rewind(std::int64_t to_pts) {
  // MPEG transport and program streams carry no index: FFmpeg seeks them by searching timestamps
  // in the bytes, and for the first keyframe lands on the second (the recordings of `acrolab
  // live` lost their first group of pictures so). The start is byte 0.
  const std::string name = format->iformat->name;
  if (to_pts <= keyframe_pts.front() && (name == "mpegts" || name == "mpeg")) {
    if (av_seek_frame(format, -1, 0, AVSEEK_FLAG_BYTE) >= 0) {
      avcodec_flush_buffers(decoder);
      input_done = false;
      last_pts = AV_NOPTS_VALUE;
      return;
    }
  }
  const int rc = av_seek_frame(format, stream, to_pts, AVSEEK_FLAG_BACKWARD);
  if (rc < 0) Fail(fmt::format("timestamp {}", to_pts), "cannot seek: " + AvError(rc));
  avcodec_flush_buffers(decoder);
  input_done = false;
  last_pts = AV_NOPTS_VALUE;
}

bool VideoReader::Impl::DecodeNext() {
  for (;;) {
    const int rc = avcodec_receive_frame(decoder, frame);
    if (rc == 0) {
      last_pts = frame->pts != AV_NOPTS_VALUE ? frame->pts : frame->best_effort_timestamp;
      return true;
    }
    if (rc == AVERROR_EOF) return false;
    if (rc != AVERROR(EAGAIN))
      Fail(fmt::format("frame {}", next_sequential), "cannot decode: " + AvError(rc));
    // The decoder wants input: the next packet of the stream, or the end (drain).
    if (input_done) return false;
    int read = 0;
    while ((read = av_read_frame(format, packet)) >= 0 && packet->stream_index != stream)
      av_packet_unref(packet);
    if (read < 0) {
      input_done = true;
      avcodec_send_packet(decoder, nullptr);
      continue;
    }
    const std::int64_t byte = packet->pos;
    // Frame threads copy this setting from our context when the packet is submitted.
    decoder->skip_frame =
        wanted_pts != AV_NOPTS_VALUE && packet->pts != AV_NOPTS_VALUE && packet->pts < wanted_pts
            ? AVDISCARD_NONREF
            : AVDISCARD_DEFAULT;
    const int sent = avcodec_send_packet(decoder, packet);
    av_packet_unref(packet);
    if (sent < 0 && sent != AVERROR(EAGAIN) && sent != AVERROR_INVALIDDATA)
      Fail(fmt::format("byte {}", byte), "cannot decode: " + AvError(sent));
  }
}

int VideoReader::Impl::IndexOfPts(std::int64_t p) const {
  const auto it = std::lower_bound(pts.begin(), pts.end(), p);
  return it != pts.end() && *it == p ? static_cast<int>(it - pts.begin()) : -1;
}

bool VideoReader::Impl::GreyFromLuma(VideoFrame* out) {
  // 8-bit formats whose first plane is the luma: grey is that plane through a table of what
  // swscale makes of each of the 256 values with this frame's range — the same numbers as its
  // GRAY8 conversion (which maps each pixel alone), at the cost of a table lookup.
  const auto pix = static_cast<AVPixelFormat>(frame->format);
  static const AVPixelFormat kLumaFirst[] = {AV_PIX_FMT_YUV420P,
                                             AV_PIX_FMT_YUVJ420P,
                                             AV_PIX_FMT_YUV422P,
                                             AV_PIX_FMT_YUVJ422P,
                                             AV_PIX_FMT_YUV444P,
                                             AV_PIX_FMT_YUVJ444P,
                                             AV_PIX_FMT_NV12,
                                             AV_PIX_FMT_NV21};
  if (std::find(std::begin(kLumaFirst), std::end(kLumaFirst), pix) == std::end(kLumaFirst))
    return false;
  const int stored_range = StoredInt(frame->color_range);
  const int range = stored_range == AVCOL_RANGE_JPEG || pix == AV_PIX_FMT_YUVJ420P ||
                            pix == AV_PIX_FMT_YUVJ422P || pix == AV_PIX_FMT_YUVJ444P
                        ? 1
                        : 0;
  if (grey_table_format != pix || grey_table_range != stored_range) {
    // A 256 × 2 frame of this format holding every luma value once per row, through swscale.
    const int w = 256, h = 2;
    AVFrame* probe = av_frame_alloc();
    if (probe == nullptr) return false;
    probe->format = pix;
    probe->width = w;
    probe->height = h;
    if (av_frame_get_buffer(probe, 0) < 0) {
      av_frame_free(&probe);
      return false;
    }
    for (int y = 0; y < h; ++y)
      for (int x = 0; x < w; ++x) probe->data[0][y * probe->linesize[0] + x] = std::uint8_t(x);
    for (int p = 1; p < 4 && probe->data[p] != nullptr; ++p)
      std::fill_n(probe->data[p], probe->linesize[p] * h, std::uint8_t(128));
    SwsContext* sws =
        sws_getContext(w, h, pix, w, h, AV_PIX_FMT_GRAY8, SWS_BICUBIC, nullptr, nullptr, nullptr);
    if (sws == nullptr) {
      av_frame_free(&probe);
      return false;
    }
    sws_setColorspaceDetails(sws,
                             sws_getCoefficients(SWS_CS_DEFAULT),
                             range,
                             sws_getCoefficients(SWS_CS_DEFAULT),
                             1,
                             0,
                             1 << 16,
                             1 << 16);
    std::vector<std::uint8_t> row(static_cast<size_t>(w) * h + 64);
    std::uint8_t* dst[1] = {row.data()};
    const int dst_stride[1] = {w};
    sws_scale(sws, probe->data, probe->linesize, 0, h, dst, dst_stride);
    sws_freeContext(sws);
    av_frame_free(&probe);
    std::copy_n(row.begin(), 256, grey_table.begin());
    grey_table_format = pix;
    grey_table_range = stored_range;
  }
  for (int y = 0; y < out->height; ++y) {
    const std::uint8_t* src = frame->data[0] + static_cast<std::ptrdiff_t>(y) * frame->linesize[0];
    std::uint8_t* dst = out->pixels.data() + static_cast<size_t>(y) * out->width;
    for (int x = 0; x < out->width; ++x) dst[x] = grey_table[src[x]];
  }
  return true;
}

void VideoReader::Impl::Convert(int index, VideoFrame* frame_out) {
  VideoFrame& out = *frame_out;  // its pixel buffer is reused from call to call
  out.index = index;
  out.time_s = times_s[static_cast<size_t>(index)];
  out.width = frame->width;
  out.height = frame->height;
  const bool grey = pixels == VideoPixels::kGrey;
  out.channels = grey ? 1 : 3;
  out.pixels.resize(out.channels * static_cast<size_t>(out.width) * out.height);
  if (grey && GreyFromLuma(&out)) {
    RotatePixels(info.rotation_deg, &out);
    return;
  }
  scaler = sws_getCachedContext(scaler,
                                frame->width,
                                frame->height,
                                static_cast<AVPixelFormat>(frame->format),
                                frame->width,
                                frame->height,
                                grey ? AV_PIX_FMT_GRAY8 : AV_PIX_FMT_RGB24,
                                SWS_BICUBIC,
                                nullptr,
                                nullptr,
                                nullptr);
  if (scaler == nullptr)
    Fail(fmt::format("frame {}", index), "no conversion of its pixel format to RGB");
  // The frame's own matrix and range (the command line's scaler does the same, "auto").
  // Grey is luma alone: no matrix applies, only the range (with a matrix set, swscale leaves its
  // exact luma path for a dithered one).
  const int stored_colorspace = StoredInt(frame->colorspace);
  const int stored_range = StoredInt(frame->color_range);
  const bool known = stored_colorspace > 0 && stored_colorspace < AVCOL_SPC_NB &&
                     stored_colorspace != AVCOL_SPC_UNSPECIFIED;
  const int colorspace = !known || grey ? SWS_CS_DEFAULT : stored_colorspace;
  sws_setColorspaceDetails(scaler,
                           sws_getCoefficients(colorspace),
                           stored_range == AVCOL_RANGE_JPEG ? 1 : 0,
                           sws_getCoefficients(SWS_CS_DEFAULT),
                           1,
                           0,
                           1 << 16,
                           1 << 16);
  // swscale's SIMD writes whole vectors: convert into rows padded to 64 bytes (and a padded end),
  // then pack them.
  const int row_bytes = out.channels * out.width;
  const int stride = (row_bytes + 63) / 64 * 64;
  scratch.resize(static_cast<size_t>(stride) * out.height + 64);
  std::uint8_t* dst[1] = {scratch.data()};
  const int dst_stride[1] = {stride};
  sws_scale(scaler, frame->data, frame->linesize, 0, frame->height, dst, dst_stride);
  for (int y = 0; y < out.height; ++y)
    std::copy_n(scratch.data() + static_cast<size_t>(y) * stride,
                row_bytes,
                out.pixels.data() + static_cast<size_t>(y) * row_bytes);
  RotatePixels(info.rotation_deg, &out);
}

namespace {
std::atomic<long long> opened_count{0};
}  // namespace

long long VideoReader::OpenedCount() {
  return opened_count.load();
}

void VideoReader::SetPixels(VideoPixels pixels) {
  impl_->pixels = pixels;
}

VideoPixels VideoReader::pixels() const {
  return impl_->pixels;
}

VideoReader::VideoReader(const std::filesystem::path& path, const VideoReaderOptions& options)
    : impl_(std::make_unique<Impl>()) {
  ++opened_count;
  internal::SilenceFfmpegLog();
  impl_->path = path.string();
  std::error_code ec;
  if (!std::filesystem::is_regular_file(path, ec))
    throw InputError(impl_->path, "", "not a regular file");
  impl_->Open(options);
}

VideoReader::~VideoReader() = default;
VideoReader::VideoReader(VideoReader&&) noexcept = default;
VideoReader& VideoReader::operator=(VideoReader&&) noexcept = default;

const VideoInfo& VideoReader::info() const {
  return impl_->info;
}

const std::vector<double>& VideoReader::frame_times_s() const {
  return impl_->times_s;
}

int VideoReader::FrameAt(double time_s) const {
  const std::vector<double>& t = impl_->times_s;
  const auto it = std::upper_bound(t.begin(), t.end(), time_s + 1e-9);
  return it == t.begin() ? 0 : static_cast<int>(it - t.begin()) - 1;
}

VideoFrame VideoReader::Frame(int index) {
  Impl& m = *impl_;
  if (index < 0 || index >= m.info.num_frames)
    throw InputError(m.path,
                     fmt::format("frame {}", index),
                     fmt::format("not among the {} frames", m.info.num_frames));
  const std::int64_t target = m.pts[static_cast<size_t>(index)];
  m.wanted_pts = target;
  struct Reset {
    Impl& m;
    ~Reset() { m.wanted_pts = AV_NOPTS_VALUE; }
  } reset{m};
  // The keyframe at or before the target; one further back when the target is a leading picture.
  auto key = std::upper_bound(m.keyframe_pts.begin(), m.keyframe_pts.end(), target) - 1;
  // Forward in the same group of pictures as the last decoded frame: go on decoding, no seek.
  if (m.last_pts != AV_NOPTS_VALUE && m.last_pts < target && *key <= m.last_pts) {
    while (m.DecodeNext()) {
      if (m.last_pts == target) {
        VideoFrame out;
        m.Convert(index, &out);
        m.next_sequential = index + 1;
        return out;
      }
      if (m.last_pts > target) break;
    }
  }
  for (;;) {
    m.Rewind(*key);
    // A seek that lands past the target, or (an MPEG-TS's search by timestamp) past the last
    // frame, steps back a keyframe.
    bool overshot = true;
    while (m.DecodeNext()) {
      overshot = false;
      const std::int64_t p = m.last_pts;
      if (p == target) {
        VideoFrame out;
        m.Convert(index, &out);
        m.next_sequential = index + 1;
        return out;
      }
      if (p > target) {
        overshot = true;
        break;
      }
    }
    if (overshot && key != m.keyframe_pts.begin()) {
      --key;
      continue;
    }
    throw InputError(
        m.path, fmt::format("frame {}", index), "the decoder does not produce this frame");
  }
}

bool VideoReader::ReadNext(VideoFrame* out) {
  Impl& m = *impl_;
  if (m.next_sequential >= m.info.num_frames) return false;
  while (m.DecodeNext()) {
    const int index = m.IndexOfPts(m.last_pts);
    if (index < m.next_sequential) continue;  // before the pass's position (after a seek)
    m.Convert(index, out);
    m.next_sequential = index + 1;
    return true;
  }
  if (m.next_sequential < m.info.num_frames)
    throw InputError(m.path,
                     fmt::format("frame {}", m.next_sequential),
                     fmt::format("the stream ends after {} of its {} indexed frames",
                                 m.next_sequential,
                                 m.info.num_frames));
  return false;
}

std::uint64_t HashFrame(const VideoFrame& frame) {
  std::uint64_t h = 1469598103934665603ull;
  for (std::uint8_t b : frame.pixels) {
    h ^= b;
    h *= 1099511628211ull;
  }
  return h;
}

}  // namespace acro::capture
