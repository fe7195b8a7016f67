#include "acro/views/filmstrip.h"

#include <algorithm>
#include <cmath>
#include <memory>
#include <stdexcept>

#include "acro/base/file_io.h"
#include "acro/base/progress.h"
#include "acro/base/input_error.h"
#include "acro/capture/frame_output.h"
#include "acro/scene/compare_scene.h"
#include "acro/views/camera_composite.h"
#include "acro/views/display.h"
#include "acro/views/scene_renderer.h"

namespace acro::ui {

namespace {

constexpr double kMarginM = 0.3;       // around the poses, in each row
constexpr float kPassedAlpha = 0.35f;  // the copies left at passed instants (video)

void CheckRows(const std::vector<FilmstripRow>& rows) {
  if (rows.empty()) throw std::invalid_argument("filmstrip: no row");
  for (const FilmstripRow& row : rows) {
    if (row.scene == nullptr || row.frames.empty() || !(row.rate_hz > 0))
      throw std::invalid_argument("filmstrip: a row without its scene, frames or rate");
    for (size_t k = 0; k < row.frames.size(); ++k) {
      const int f = row.frames[k];
      if (f < 0 || f >= row.scene->num_frames() || (k > 0 && f < row.frames[k - 1]))
        throw std::invalid_argument("filmstrip: frame " + std::to_string(f) + " of " +
                                    std::to_string(row.scene->num_frames()) +
                                    " (frames increase, within the motion)");
    }
  }
}

// Where motion frame f lies along a row's strip, in instants: k at instant k, fractions between.
double StripPosition(const FilmstripRow& row, int f) {
  const std::vector<int>& fr = row.frames;
  if (f <= fr.front()) return 0.0;
  for (size_t k = 0; k + 1 < fr.size(); ++k)
    if (f < fr[k + 1]) return double(k) + double(f - fr[k]) / double(fr[k + 1] - fr[k]);
  return double(fr.size() - 1);
}

// The rows laid out one above the other at one scale, seen from the athlete's left in a parallel
// projection: each pose moved along its strip (its height kept), each row moved down into its
// band of `options.height` pixels.
class StripLayout {
 public:
  // `whole_flight`: the bounds cover every frame between a row's first and last instants (the
  // video), not only the instants.
  StripLayout(const std::vector<FilmstripRow>& rows,
              const Eigen::Vector3d& heading_W,
              const FilmstripOptions& options,
              bool whole_flight)
      : rows_(rows), spacing_m_(options.spacing_m) {
    Eigen::Vector3d forward(heading_W.x(), heading_W.y(), 0.0);
    forward =
        forward.norm() > 1e-9 ? Eigen::Vector3d(forward.normalized()) : Eigen::Vector3d::UnitX();
    left_ = Eigen::Vector3d::UnitZ().cross(forward);
    // Seen from the athlete's left, the picture's right is the athlete's back (−forward): the
    // strip runs that way, so time goes left to right.
    along_ = -forward;
    analysis::AthletePose pose;
    double lo_a = 1e300, hi_a = -1e300, band_m = 0.0, depth = 0.0;
    std::vector<double> lo_z(rows.size(), 1e300), hi_z(rows.size(), -1e300);
    for (size_t r = 0; r < rows.size(); ++r) {
      const FilmstripRow& row = rows[r];
      row.scene->Pose(row.frames.front(), &pose);
      first_com_.push_back(pose.com_W);
      depth += pose.com_W.dot(left_) / double(rows.size());
      std::vector<int> frames = row.frames;
      if (whole_flight) {
        frames.clear();
        for (int f = row.frames.front(); f <= row.frames.back(); ++f) frames.push_back(f);
      }
      for (const int f : frames) {
        row.scene->Pose(f, &pose);
        const Eigen::Vector3d shift = Shift(r, StripPosition(row, f), pose.com_W, 0.0);
        const Eigen::VectorXd a = (pose.mesh.vertices_W.colwise() + shift).transpose() * along_;
        lo_a = std::min(lo_a, a.minCoeff());
        hi_a = std::max(hi_a, a.maxCoeff());
        lo_z[r] = std::min(lo_z[r], pose.mesh.vertices_W.row(2).minCoeff());
        hi_z[r] = std::max(hi_z[r], pose.mesh.vertices_W.row(2).maxCoeff());
      }
    }
    band_m = *std::max_element(hi_z.begin(), hi_z.end()) -
             *std::min_element(lo_z.begin(), lo_z.end()) + 2 * kMarginM;
    // Metres per pixel: every row's poses in its band, the strip across the width.
    const double m_per_px =
        std::max(band_m / options.height, (hi_a - lo_a + 2 * kMarginM) / options.width);
    band_m = m_per_px * options.height;
    // One height reference for every row (the bands' middles at the middle of all the poses), so
    // that heights compare across rows too.
    const double lo = *std::min_element(lo_z.begin(), lo_z.end());
    const double hi = *std::max_element(hi_z.begin(), hi_z.end());
    for (size_t r = 0; r < rows.size(); ++r)
      dz_.push_back(-(double(r) + 0.5) * band_m - 0.5 * (lo + hi));
    const double half_height = 0.5 * band_m * double(rows.size());
    view_.target_W =
        0.5 * (lo_a + hi_a) * along_ + depth * left_ - half_height * Eigen::Vector3d::UnitZ();
    view_.eye_W = view_.target_W + 20.0 * left_;
    view_.parallel_scale_m = half_height;
  }

  const FreeViewpoint& view() const { return view_; }
  // Lights from the viewer's side and above, so that what is seen is lit whichever way the
  // athlete faces.
  std::vector<Eigen::Vector3d> Lights() const {
    const Eigen::Vector3d down = -Eigen::Vector3d::UnitZ();
    return {down - 0.5 * left_ + 0.3 * along_, down - 0.2 * left_ - 0.4 * along_};
  }

  // Row r's pose (COM com_W) at strip position `s`, moved into place.
  Eigen::Vector3d Shift(size_t r, double s, const Eigen::Vector3d& com_W, double dz) const {
    const double n = double(rows_[r].frames.size());
    Eigen::Vector3d shift = first_com_[r] + (s - (n - 1) / 2) * spacing_m_ * along_ - com_W;
    shift.z() = dz;
    return shift;
  }
  void Place(size_t r, double s, const analysis::AthletePose& pose, Eigen::Matrix3Xd* v) const {
    *v = pose.mesh.vertices_W.colwise() + Shift(r, s, pose.com_W, dz_[r]);
  }

 private:
  const std::vector<FilmstripRow>& rows_;
  double spacing_m_;
  Eigen::Vector3d along_, left_;
  std::vector<Eigen::Vector3d> first_com_;
  std::vector<double> dz_;
  FreeViewpoint view_;
};

std::unique_ptr<SceneRenderer> MakeRenderer(const FilmstripOptions& options,
                                            int rows,
                                            const StripLayout& layout) {
  auto renderer = std::make_unique<SceneRenderer>(options.width, options.height * rows, 4);
  renderer->SetBackground({1, 1, 1, 1});
  renderer->SetSceneLights(layout.Lights(), 0.5, 0.5);
  return renderer;
}

// The render as RGB with each row's label at its top left.
void Compose(const RenderImage& image,
             const std::vector<FilmstripRow>& rows,
             const FilmstripOptions& options,
             std::vector<std::uint8_t>* rgb) {
  const int width = options.width, height = options.height * int(rows.size());
  rgb->resize(size_t(width) * size_t(height) * 3);
  for (size_t i = 0, n = size_t(width) * size_t(height); i < n; ++i)
    for (int c = 0; c < 3; ++c) (*rgb)[3 * i + size_t(c)] = image.rgba[4 * i + size_t(c)];
  const int text_px = std::max(12, options.height / 18);
  RenderImage text;
  for (size_t r = 0; r < rows.size(); ++r) {
    if (rows[r].label.empty()) continue;
    RenderTextLine(rows[r].label, text_px, {1, 1, 1, 1}, &text);
    BlendOver(text, text_px / 2, int(r) * options.height + text_px / 2, width, height, rgb);
  }
}

}  // namespace

std::vector<int> EvenlySpacedFrames(int first, int last, int count) {
  std::vector<int> frames;
  if (count <= 0 || last < first) return frames;
  if (count == 1) return {first};
  for (int k = 0; k < count; ++k)
    frames.push_back(first +
                     static_cast<int>(std::lround(double(k) * (last - first) / (count - 1))));
  return frames;
}

std::vector<std::uint8_t> RenderFilmstrip(analysis::AthleteScene& scene,
                                          const std::vector<int>& frames,
                                          const Eigen::Vector3d& heading_W,
                                          const FilmstripOptions& options) {
  FilmstripRow row;
  row.scene = &scene;
  row.frames = frames;
  row.rate_hz = 1.0;  // a still: no clock
  row.colour = options.colour;
  return RenderFilmstrips({row}, heading_W, options);
}

std::vector<std::uint8_t> RenderFilmstrips(const std::vector<FilmstripRow>& rows,
                                           const Eigen::Vector3d& heading_W,
                                           const FilmstripOptions& options) {
  CheckRows(rows);
  const XDisplay display;
  const StripLayout layout(rows, heading_W, options, false);
  const std::unique_ptr<SceneRenderer> renderer = MakeRenderer(options, int(rows.size()), layout);
  analysis::AthletePose pose;
  for (size_t r = 0; r < rows.size(); ++r)
    for (size_t k = 0; k < rows[r].frames.size(); ++k) {
      rows[r].scene->Pose(rows[r].frames[k], &pose);
      analysis::SceneMesh mesh = pose.mesh;
      layout.Place(r, double(k), pose, &mesh.vertices_W);
      mesh.colour = rows[r].colour;
      renderer->AddMesh(mesh);
    }
  renderer->LookFrom(layout.view());
  RenderImage image;
  renderer->Render(&image);
  std::vector<std::uint8_t> rgb;
  Compose(image, rows, options, &rgb);
  return rgb;
}

int WriteFilmstripVideo(const std::vector<FilmstripRow>& rows,
                        const Eigen::Vector3d& heading_W,
                        const std::filesystem::path& path,
                        const FilmstripOptions& options,
                        const FilmstripVideoOptions& video) {
  CheckRows(rows);
  if (!(video.fps > 0) || video.slow < 1 || !(video.hold_s >= 0))
    throw std::invalid_argument("WriteFilmstripVideo: fps > 0, slow ≥ 1, hold ≥ 0");
  const XDisplay display;
  const StripLayout layout(rows, heading_W, options, true);
  const std::unique_ptr<SceneRenderer> renderer = MakeRenderer(options, int(rows.size()), layout);
  // Per row: a translucent copy at each instant (shown once passed) and the moving athlete.
  analysis::AthletePose pose;
  std::vector<std::vector<int>> passed(rows.size());
  std::vector<int> moving;
  double span_s = 0.0;
  for (size_t r = 0; r < rows.size(); ++r) {
    const FilmstripRow& row = rows[r];
    for (size_t k = 0; k < row.frames.size(); ++k) {
      row.scene->Pose(row.frames[k], &pose);
      analysis::SceneMesh mesh = pose.mesh;
      layout.Place(r, double(k), pose, &mesh.vertices_W);
      mesh.colour = row.colour;
      mesh.colour.a = kPassedAlpha;
      passed[r].push_back(renderer->AddMesh(mesh));
      renderer->SetVisible(passed[r].back(), false);
    }
    row.scene->Pose(row.frames.front(), &pose);
    analysis::SceneMesh mesh = pose.mesh;
    mesh.colour = row.colour;
    moving.push_back(renderer->AddMesh(mesh));
    span_s = std::max(span_s, (row.frames.back() - row.frames.front()) / row.rate_hz);
  }
  renderer->LookFrom(layout.view());

  const int width = options.width, height = options.height * int(rows.size());
  capture::VideoWriterOptions w;
  w.fps = video.fps;
  w.preset = "superfast";
  capture::FrameOutput out(path, width, height, w);
  const int flight_frames = int(std::floor(span_s * video.fps * video.slow + 1e-9)) + 1;
  const int total = flight_frames + int(std::lround(video.hold_s * video.fps));
  RenderImage image;
  std::vector<std::uint8_t> rgb;
  Eigen::Matrix3Xd vertices;
  for (int i = 0; i < total; ++i) {
    const double t = std::min(i, flight_frames - 1) / (video.fps * video.slow);
    for (size_t r = 0; r < rows.size(); ++r) {
      const FilmstripRow& row = rows[r];
      const int f =
          std::min(row.frames.back(), row.frames.front() + int(std::lround(t * row.rate_hz)));
      row.scene->Pose(f, &pose);
      layout.Place(r, StripPosition(row, f), pose, &vertices);
      renderer->UpdateMesh(moving[r], vertices);
      for (size_t k = 0; k < row.frames.size(); ++k)
        renderer->SetVisible(passed[r][k], row.frames[k] <= f);
    }
    renderer->Render(&image);
    Compose(image, rows, options, &rgb);
    out.Write(i, rgb);
    if (video.progress && !video.progress(i + 1, total))
      throw Cancelled(path.string() + ": cancelled; nothing written");
  }
  out.Finish();
  return out.frames_written();
}

JumpFilmstrips WriteJumpFilmstrips(analysis::AthleteScene& athlete, const analysis::TrialAnalysis& analysis,
                                   const std::filesystem::path& dir, bool videos,
                                   const std::function<bool(int, int)>& progress) {
  JumpFilmstrips out;
  const FilmstripOptions size;
  for (const analysis::JumpMetrics& j : analysis.jumps) {
    if (j.partial()) continue;
    const std::vector<int> frames = EvenlySpacedFrames(j.flight.takeoff_frame, j.flight.landing_frame - 1, 8);
    const Eigen::Vector3d heading = analysis::FindTakeoff(analysis, j.index).heading_W;
    const std::vector<std::uint8_t> rgb = RenderFilmstrip(athlete, frames, heading);
    const std::vector<std::uint8_t> png = capture::EncodeRgbPng(size.width, size.height, rgb);
    const std::string file = "filmstrip_jump_" + std::to_string(j.index) + ".png";
    WriteFileAtomically(dir / file, std::string(png.begin(), png.end()));
    out.pictures.emplace_back(j.index, file);
    if (!videos) continue;
    // The strip as a video too: it fills in as the flight goes.
    const std::string mp4 = "filmstrip_jump_" + std::to_string(j.index) + ".mp4";
    FilmstripRow row;
    row.scene = &athlete;
    row.frames = frames;
    row.rate_hz = analysis.reconstruction.motion.rate_hz;
    FilmstripVideoOptions video;
    video.progress = progress;
    WriteFilmstripVideo({row}, heading, dir / mp4, size, video);
    out.videos.emplace_back(j.index, mp4);
  }
  return out;
}

}  // namespace acro::ui
