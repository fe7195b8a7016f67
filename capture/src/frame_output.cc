#include "acro/capture/frame_output.h"

extern "C" {
#include <libavcodec/avcodec.h>
#include <libavutil/imgutils.h>
}

#include <cstring>
#include <optional>
#include <random>

#include <fmt/format.h>

#include "acro/base/file_io.h"
#include "acro/base/input_error.h"
#include "acro/base/temporaries.h"
#include "internal/ffmpeg.h"

namespace acro::capture {

namespace fs = std::filesystem;

bool IsFrameFileName(const std::string& name) {
  return name.size() == 16 && name.rfind("frame_", 0) == 0 && name.substr(12) == ".png" &&
         name.substr(6, 6).find_first_not_of("0123456789") == std::string::npos;
}

std::vector<std::uint8_t> EncodeRgbPng(int width,
                                       int height,
                                       const std::vector<std::uint8_t>& rgb) {
  if (width <= 0 || height <= 0 || rgb.size() != size_t(width) * size_t(height) * 3)
    throw std::invalid_argument("EncodeRgbPng: the pixels are not width × height × 3 bytes");
  const AVCodec* codec = avcodec_find_encoder(AV_CODEC_ID_PNG);
  if (codec == nullptr) throw InputError("", "PNG", "this FFmpeg has no PNG encoder");
  struct Owned {
    AVCodecContext* context = nullptr;
    AVFrame* frame = nullptr;
    AVPacket* packet = nullptr;
    ~Owned() {
      avcodec_free_context(&context);
      av_frame_free(&frame);
      av_packet_free(&packet);
    }
  } o;
  o.context = avcodec_alloc_context3(codec);
  o.frame = av_frame_alloc();
  o.packet = av_packet_alloc();
  if (o.context == nullptr || o.frame == nullptr || o.packet == nullptr) throw std::bad_alloc();
  o.context->width = width;
  o.context->height = height;
  o.context->pix_fmt = AV_PIX_FMT_RGB24;
  o.context->time_base = AVRational{1, 25};
  if (const int r = avcodec_open2(o.context, codec, nullptr); r < 0)
    throw InputError("", "PNG", "the encoder does not open: " + internal::AvError(r));
  o.frame->format = AV_PIX_FMT_RGB24;
  o.frame->width = width;
  o.frame->height = height;
  if (av_frame_get_buffer(o.frame, 0) < 0) throw std::bad_alloc();
  for (int y = 0; y < height; ++y)
    std::memcpy(o.frame->data[0] + size_t(y) * size_t(o.frame->linesize[0]),
                rgb.data() + size_t(y) * size_t(width) * 3,
                size_t(width) * 3);
  std::vector<std::uint8_t> bytes;
  int r = avcodec_send_frame(o.context, o.frame);
  if (r >= 0) r = avcodec_send_frame(o.context, nullptr);
  while (r >= 0) {
    r = avcodec_receive_packet(o.context, o.packet);
    if (r < 0) break;
    bytes.insert(bytes.end(), o.packet->data, o.packet->data + o.packet->size);
    av_packet_unref(o.packet);
  }
  if (r != AVERROR_EOF || bytes.empty())
    throw InputError("", "PNG", "encoding failed: " + internal::AvError(r));
  return bytes;
}

struct FrameOutput::Impl {
  fs::path path, staging;
  int width = 0, height = 0;
  std::optional<VideoWriter> writer;
  std::optional<ScopedTemporary> registered;
  int written = 0;

  ~Impl() {
    if (!staging.empty()) {
      std::error_code ec;
      fs::remove_all(staging, ec);
    }
  }
};

FrameOutput::FrameOutput(const fs::path& path,
                         int width,
                         int height,
                         const VideoWriterOptions& video)
    : impl_(std::make_unique<Impl>()) {
  // "frames/" names the directory "frames" (its staging directory goes beside it, not inside).
  fs::path target = path.lexically_normal();
  if (!target.has_filename() && target.has_parent_path()) target = target.parent_path();
  impl_->path = target;
  impl_->width = width;
  impl_->height = height;
  const std::string ext = LowerExtension(target);
  if (ext == "mp4") {
    impl_->writer.emplace(target, width, height, video);
    return;
  }
  // One rule for every door: another extension is not silently a folder of PNGs named x.avi.
  if (!ext.empty() && !IsDirectory(target))
    throw InputError(target.string(),
                     "",
                     "." + ext + " cannot be written: an .mp4 video, or a folder for PNG frames");
  if (fs::exists(target)) {
    if (!fs::is_directory(target))
      throw InputError(target.string(), "", "exists and is not a directory (frames go into one)");
    for (const auto& entry : fs::directory_iterator(target))
      if (!IsFrameFileName(entry.path().filename().string()))
        throw InputError(target.string(),
                         "",
                         "holds " + entry.path().filename().string() +
                             ", not only frame_NNNNNN.png: not replaced");
  }
  std::random_device rd;
  fs::path staging = target;
  staging += fmt::format(".tmp-{:08x}", rd());
  std::error_code ec;
  if (!fs::create_directories(staging, ec))
    throw InputError(staging.string(), "", "cannot create the directory: " + ec.message());
  impl_->staging = staging;
  impl_->registered.emplace(staging);
}

FrameOutput::~FrameOutput() = default;

bool FrameOutput::is_video() const {
  return impl_->writer.has_value();
}

void FrameOutput::Write(int index, const std::vector<std::uint8_t>& rgb) {
  if (impl_->writer) {
    impl_->writer->Write(rgb);
  } else {
    const fs::path file = impl_->staging / fmt::format("frame_{:06d}.png", index);
    const std::vector<std::uint8_t> png = EncodeRgbPng(impl_->width, impl_->height, rgb);
    WriteFileAtomically(file, std::string(png.begin(), png.end()));
  }
  ++impl_->written;
}

void FrameOutput::Finish() {
  if (impl_->writer) {
    impl_->writer->Finish();
    return;
  }
  std::error_code ec;
  if (fs::exists(impl_->path)) fs::remove_all(impl_->path, ec);
  fs::rename(impl_->staging, impl_->path, ec);
  if (ec)
    throw InputError(
        impl_->path.string(), "", "cannot move the frames into place: " + ec.message());
  impl_->staging.clear();
  impl_->registered.reset();
}

int FrameOutput::frames_written() const {
  return impl_->written;
}

}  // namespace acro::capture
