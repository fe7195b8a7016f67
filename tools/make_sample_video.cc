// Makes the sample routine's video (samples/trials/trampoline_routine/side_camera.mp4) with the
// project's own renderer: the routine's true motion (the noise-free coordinates of
// tools/sample_routine.h, not a reconstruction) rendered through a calibrated virtual camera 9.5 m
// beside the trampoline (side_camera.toml: fx ≠ fy, an off-centre principal point, barrel
// distortion), in a gym (floor, walls with mats and banners, the trampoline with its frame,
// springs and legs), with motion blur (three renders over a 1/60 s shutter) and sensor noise, and
// an offset between the mocap and the video start that `acrolab sync` must find
// (video_truth.json). 1920 × 1080, 30 fps, H.264.
// With --views, the multi-camera sample instead (docs/markerless.md): three phones around the bed
// (end_camera.mp4, corner_camera.mp4, far_camera.mp4), each started at its own moment, and
// views.toml (the side camera and the phones) with views_truth.json (each video's first sample).
//
// With --faults large, the routine with the execution assistant's large faults put in (the
// generator's SampleFault, as tests/analysis/assess/execution_faults does it from the markers):
// knees bent 45° in the back pike (skill 2), legs 40 cm apart in the barani (skill 3), the double
// back's tuck opened to 110° (skill 5) — for the faults found from video (docs/scoring.md), with
// faults.json saying what was put where.
//
// usage: make_sample_video ATHLETE.yaml OUT_DIR [--frame K OUT.png]   (--frame: that frame only)
//        make_sample_video ATHLETE.yaml OUT_DIR --views [CAMERA K OUT.png]
//        make_sample_video ATHLETE.yaml OUT_DIR --faults large [--views]
// (from the repository root: build/bin/make_sample_video samples/athletes/sample_athlete.yaml
//  samples/trials/trampoline_routine)

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include <fmt/format.h>
#include <Eigen/Geometry>

#include "acro/athlete/athlete_profile.h"
#include "acro/athlete/body_mesh.h"
#include "acro/base/file_io.h"
#include "acro/base/input_error.h"
#include "acro/capture/frame_output.h"
#include "acro/capture/video.h"
#include "acro/dynamics/configuration.h"
#include "acro/dynamics/kinematics.h"
#include "acro/dynamics/workspace.h"
#include "acro/scene/athlete_scene.h"
#include "acro/scene/place_scene.h"
#include "acro/views/camera_composite.h"
#include "acro/views/display.h"
#include "acro/views/scene_renderer.h"
#include "acro/vision/camera.h"
#include "sample_routine.h"

namespace {

using acro::analysis::Rgba;
using acro::analysis::SceneMesh;

constexpr double kFps = 30.0;
/// The video time of the trial's first sample: the video starts 0.575 s (17.25 frames, 69 samples
/// at 120 Hz) after the mocap, so frame k shows sample 4k + 69.
constexpr double kOffsetS = -0.575;

// An axis-aligned box as a mesh (12 triangles, outward).
SceneMesh Box(const Eigen::Vector3d& lo, const Eigen::Vector3d& hi, Rgba colour, const char* name) {
  SceneMesh m;
  m.name = name;
  m.colour = colour;
  m.vertices_W.resize(3, 8);
  for (int c = 0; c < 8; ++c)
    m.vertices_W.col(c) = Eigen::Vector3d(
        (c & 1) ? hi.x() : lo.x(), (c & 2) ? hi.y() : lo.y(), (c & 4) ? hi.z() : lo.z());
  const int faces[6][4] = {
      {0, 2, 3, 1}, {4, 5, 7, 6}, {0, 1, 5, 4}, {2, 6, 7, 3}, {0, 4, 6, 2}, {1, 3, 7, 5}};
  m.triangles.resize(3, 12);
  for (int f = 0; f < 6; ++f) {
    m.triangles.col(2 * f) = Eigen::Vector3i(faces[f][0], faces[f][1], faces[f][2]);
    m.triangles.col(2 * f + 1) = Eigen::Vector3i(faces[f][0], faces[f][2], faces[f][3]);
  }
  return m;
}

acro::vision::Camera SideCamera(const Eigen::Vector3d& bed_centre) {
  acro::vision::Camera c;
  c.name = "side";
  c.width_px = 1920;
  c.height_px = 1080;
  c.K << 1482.0, 0.0, 968.4, 0.0, 1478.5, 536.1, 0.0, 0.0, 1.0;
  c.distortion = {-0.062, 0.018, 0.0004, -0.0003};
  // 9.5 m in front of the bed's centre across its long axis, 3.4 m above the floor, looking
  // level along +y (image x = world x, image y = −world z): from the floor to 6.9 m, the highest
  // head at 6.3 m.
  const Eigen::Vector3d centre(bed_centre.x(), bed_centre.y() - 9.5, 3.4);
  c.R_KW << 1, 0, 0, 0, 0, -1, 0, 1, 0;
  c.t_KW = -c.R_KW * centre;
  return c;
}

}  // namespace

// The athlete dressed so that a person detector sees a person (docs/pose.md, "The sample
// routine"): a plain skin-coloured figure has no front or back, and BlazePose fitted it upside
// down or swapped its sides. A leotard (pelvis and thorax), white socks (feet), and a head with
// hair over the top and back, two eyes and a mouth on the front. The mesh's triangles are split
// into one mesh per colour; every mesh keeps all the vertices, so each is posed by the same
// vertex update. Directions in H: x anterior, y left, z up (docs/notation.md).
std::vector<SceneMesh> DressedAthlete(const acro::analysis::BodyMesh& mesh,
                                      const SceneMesh& posed) {
  struct Group {
    const char* name;
    Rgba colour;
  };
  const std::vector<Group> groups = {{"skin", {0.86f, 0.62f, 0.5f, 1}},
                                     {"leotard", {0.55f, 0.08f, 0.32f, 1}},
                                     {"socks", {0.93f, 0.93f, 0.9f, 1}},
                                     {"hair", {0.22f, 0.13f, 0.07f, 1}},
                                     {"eyes", {0.06f, 0.05f, 0.05f, 1}},
                                     {"mouth", {0.55f, 0.18f, 0.18f, 1}}};
  constexpr int kPelvis = 0, kThorax = 1, kHead = 2, kRightFoot = 11, kLeftFoot = 14;
  // The head's centre and size in H, from its vertices.
  Eigen::Vector3d lo = Eigen::Vector3d::Constant(1e9), hi = -lo;
  for (int t = 0; t < mesh.num_triangles(); ++t)
    if (mesh.part_segment[mesh.triangle_part[t]] == kHead)
      for (int k = 0; k < 3; ++k) {
        lo = lo.cwiseMin(mesh.vertices_H.col(mesh.triangles(k, t)));
        hi = hi.cwiseMax(mesh.vertices_H.col(mesh.triangles(k, t)));
      }
  // The face's centre: the upper part of the head's ellipsoid (its lower part is the neck).
  const Eigen::Vector3d centre(
      0.5 * (lo.x() + hi.x()), 0.5 * (lo.y() + hi.y()), lo.z() + 0.62 * (hi.z() - lo.z()));
  const auto angle = [](const Eigen::Vector3d& a, const Eigen::Vector3d& b) {
    return std::acos(std::clamp(a.normalized().dot(b.normalized()), -1.0, 1.0));
  };
  std::vector<std::vector<int>> members(groups.size());
  for (int t = 0; t < mesh.num_triangles(); ++t) {
    const int segment = mesh.part_segment[mesh.triangle_part[t]];
    int group = 0;
    if (segment == kPelvis || segment == kThorax) group = 1;
    if (segment == kRightFoot || segment == kLeftFoot) group = 2;
    if (segment == kHead) {
      const Eigen::Vector3d p =
          (mesh.vertices_H.col(mesh.triangles(0, t)) + mesh.vertices_H.col(mesh.triangles(1, t)) +
           mesh.vertices_H.col(mesh.triangles(2, t))) /
          3.0;
      const Eigen::Vector3d d = p - centre;
      if (angle(d, {1, 0.36, 0.22}) < 0.16 || angle(d, {1, -0.36, 0.22}) < 0.16)
        group = 4;
      else if (angle(d, {1, 0, -0.38}) < 0.2 && std::abs(d.normalized().y()) < 0.2)
        group = 5;
      else if (d.normalized().z() > 0.45 ||
               (d.normalized().x() < 0.05 && d.normalized().z() > -0.35))
        group = 3;
    }
    members[group].push_back(t);
  }
  std::vector<SceneMesh> out;
  for (std::size_t g = 0; g < groups.size(); ++g) {
    if (members[g].empty()) continue;
    SceneMesh m;
    m.name = std::string("athlete ") + groups[g].name;
    m.colour = groups[g].colour;
    m.vertices_W = posed.vertices_W;
    m.triangles.resize(3, static_cast<Eigen::Index>(members[g].size()));
    for (std::size_t k = 0; k < members[g].size(); ++k)
      m.triangles.col(static_cast<Eigen::Index>(k)) = mesh.triangles.col(members[g][k]);
    out.push_back(std::move(m));
  }
  return out;
}

// The gym: floor, back and side walls, mats and banners, the trampoline at `bed`.
static void AddGym(const Eigen::Vector3d& bed, acro::ui::SceneRenderer& renderer) {
  renderer.AddMesh(Box({-12, -14, -0.05}, {12, 8, 0}, {0.55f, 0.5f, 0.45f, 1}, "floor"));
  renderer.AddMesh(Box({-12, 8, 0}, {12, 8.3, 9}, {0.8f, 0.82f, 0.85f, 1}, "back wall"));
  renderer.AddMesh(Box({-12.3, -14, 0}, {-12, 8, 9}, {0.78f, 0.78f, 0.75f, 1}, "left wall"));
  renderer.AddMesh(Box({12, -14, 0}, {12.3, 8, 9}, {0.78f, 0.78f, 0.75f, 1}, "right wall"));
  renderer.AddMesh(Box({-9, 7.6, 0}, {-4, 8, 2.2}, {0.2f, 0.35f, 0.7f, 1}, "wall mats"));
  renderer.AddMesh(Box({4.5, 7.6, 0}, {9.5, 8, 2.2}, {0.2f, 0.35f, 0.7f, 1}, "wall mats"));
  renderer.AddMesh(Box({-6, 7.9, 5.2}, {-2, 8, 6.2}, {0.75f, 0.15f, 0.15f, 1}, "banner"));
  renderer.AddMesh(Box({2.5, 7.9, 5.0}, {7.0, 8, 6.0}, {0.95f, 0.75f, 0.1f, 1}, "banner"));
  renderer.AddMesh(Box({bed.x() - 3.5, bed.y() + 2.2, 0},
                       {bed.x() + 3.5, bed.y() + 4.2, 0.3},
                       {0.15f, 0.3f, 0.65f, 1},
                       "end mat"));
  acro::analysis::BedGeometry geometry;
  geometry.centre_W = bed;
  const acro::analysis::TrampolineScene trampoline = acro::analysis::MakeTrampolineScene(geometry);
  SceneMesh bed_mesh = trampoline.bed;
  bed_mesh.colour = {0.08f, 0.08f, 0.1f, 1};
  renderer.AddMesh(bed_mesh);
  SceneMesh frame = trampoline.frame;
  frame.colour = {0.1f, 0.3f, 0.75f, 1};
  renderer.AddMesh(frame);
  for (acro::analysis::SceneLines lines : {trampoline.springs, trampoline.legs}) {
    lines.colour = {0.55f, 0.55f, 0.58f, 1};
    lines.width_px = 3;
    renderer.AddLines(lines);
  }
}

// Renders the routine through `camera` from trial sample `first_sample` on, every 4th sample (30
// fps), to `out` (or, with preview_frame ≥ 0, that frame only to `preview_png`). Returns the
// number of frames (−1: the preview frame is not in the video).
static int RenderCamera(const acro::samples::SampleRoutine& routine,
                        acro::analysis::AthleteScene& athlete_scene,
                        const acro::analysis::BodyMesh& body_mesh_H,
                        const acro::vision::Camera& camera,
                        int first_sample,
                        const std::filesystem::path& out,
                        int preview_frame,
                        const std::string& preview_png) {
  const bool preview = preview_frame >= 0;
  const Eigen::Vector3d bed = routine.options.bed_centre_m;
  const acro::ui::CameraComposite composite(camera);
  const acro::vision::Camera& pinhole = composite.render_camera();
  acro::ui::SceneRenderer renderer(pinhole.width_px, pinhole.height_px, 8);
  renderer.LookThrough(pinhole);
  renderer.SetBackground({0.55f, 0.6f, 0.68f, 1.0f});  // the hall beyond the walls
  // Ceiling lights slanting down, and a dimmer light from the camera.
  renderer.SetSceneLights({{0.3, 0.5, -1}, {-0.4, 0.2, -1}, {0.0, -0.4, -1}}, 0.45, 0.5);

  AddGym(bed, renderer);

  acro::analysis::AthletePose pose;
  athlete_scene.Pose(0, &pose);
  std::vector<int> body_ids;
  for (const SceneMesh& part : DressedAthlete(body_mesh_H, pose.mesh))
    body_ids.push_back(renderer.AddMesh(part));

  acro::capture::VideoWriterOptions w;
  w.fps = kFps;
  w.crf = 26;
  w.preset = "slow";
  std::optional<acro::capture::VideoWriter> writer;
  if (!preview) writer.emplace(out, camera.width_px, camera.height_px, w);
  const double rate = routine.trial.point_rate_hz;
  const int step = static_cast<int>(std::lround(rate / kFps));
  std::vector<double> sum(size_t(camera.width_px) * camera.height_px * 3);
  std::vector<std::uint8_t> rgb(sum.size());
  acro::ui::RenderImage render;
  std::uint64_t seed = 20261202;
  const auto gaussian = [&seed]() {
    // Box–Muller on a 64-bit LCG (Knuth's MMIX constants): the same video on every run.
    const auto uniform = [&seed]() {
      seed = seed * 6364136223846793005ULL + 1442695040888963407ULL;
      return (double((seed >> 11) & ((1ULL << 53) - 1)) + 0.5) / double(1ULL << 53);
    };
    return std::sqrt(-2 * std::log(uniform())) * std::cos(2 * M_PI * uniform());
  };
  int frames = 0;
  for (int s = first_sample; s + 1 < routine.trial.num_frames; s += step, ++frames) {
    if (preview && frames != preview_frame) continue;
    // A 1/60 s shutter: the samples before, at and after the frame's, weighted ¼ ½ ¼.
    std::fill(sum.begin(), sum.end(), 0.0);
    for (const auto& [ds, weight] : {std::pair{-1, 0.25}, {0, 0.5}, {1, 0.25}}) {
      athlete_scene.Pose(std::max(0, s + ds), &pose);
      for (int id : body_ids) renderer.UpdateMesh(id, pose.mesh.vertices_W);
      renderer.Render(&render);
      std::fill(rgb.begin(), rgb.end(), 0);
      composite.Composite(render, &rgb);
      for (size_t k = 0; k < rgb.size(); ++k) sum[k] += weight * rgb[k];
    }
    // Sensor noise: Gaussian, 2.5 levels.
    for (size_t k = 0; k < rgb.size(); ++k)
      rgb[k] =
          static_cast<std::uint8_t>(std::clamp(std::lround(sum[k] + 2.5 * gaussian()), 0L, 255L));
    if (preview) {
      const std::vector<std::uint8_t> png =
          acro::capture::EncodeRgbPng(camera.width_px, camera.height_px, rgb);
      acro::WriteFileAtomically(preview_png, std::string(png.begin(), png.end()));
      std::printf("wrote %s (frame %d, sample %d)\n", preview_png.c_str(), frames, s);
      return frames;
    }
    writer->Write(rgb);
  }
  if (preview) return -1;
  writer->Finish();
  return frames;
}

// A phone on a tripod at `centre` looking at `target` (x right, y down in the image, the image's
// x axis level): 1920 × 1080, a wider lens than the side camera's, its own distortion.
static acro::vision::Camera Phone(const std::string& name,
                                  const Eigen::Vector3d& centre,
                                  const Eigen::Vector3d& target,
                                  double f,
                                  double k1) {
  acro::vision::Camera c;
  c.name = name;
  c.width_px = 1920;
  c.height_px = 1080;
  c.K << f, 0.0, 958.0 + 6.0 * k1, 0.0, f * 1.0015, 541.5, 0.0, 0.0, 1.0;
  c.distortion = {k1, 0.03, 0.0002, -0.0002};
  acro::vision::AimCamera(&c, centre, target);
  return c;
}

// The large faults (above): each hip abducted so that the ankles are `spread_m` further apart than
// the hips (2·L·sin a, L hip to ankle of the generator's athlete standing).
std::vector<acro::samples::SampleFault> LargeFaults(const std::filesystem::path& athlete,
                                                    const std::string& label,
                                                    double spread_m,
                                                    double* abduction_deg) {
  acro::samples::SampleRoutineOptions one;
  one.num_skills = 1;
  const acro::samples::SampleRoutine clean = acro::samples::MakeSampleRoutine(athlete, label, one);
  const auto& model = clean.model;
  acro::dynamics::Workspace<double> ws(model);
  acro::dynamics::CalcForwardKinematics(model, ws, acro::dynamics::MakeNeutralConfiguration(model));
  const auto point = [&](const char* name) {
    const auto& p = model.point(model.FindPoint(name));
    const auto& X = ws.X_WB[static_cast<size_t>(p.segment)];
    return Eigen::Vector3d(X.rotation() * p.p_BoP_B + X.translation());
  };
  const double leg = (point("r_ankle_jc") - point("r_hip_jc")).norm();
  *abduction_deg = std::asin(spread_m / (2 * leg)) * 180 / M_PI;
  using Kind = acro::samples::SampleFault::Kind;
  const auto fault = [](int skill, Kind kind, double value) {
    acro::samples::SampleFault f;
    f.skill = skill;
    f.kind = kind;
    f.value = value;
    return f;
  };
  return {fault(2, Kind::kKneesBent, 45),
          fault(3, Kind::kLegsApart, *abduction_deg),
          fault(5, Kind::kTuckAngle, 110)};
}

namespace {

// What every camera renders: the routine, its athlete and the side camera's timing.
struct Render {
  const acro::samples::SampleRoutine& routine;
  acro::analysis::AthleteScene& scene;
  const acro::analysis::BodyMesh& mesh;
  int first_sample = 0;  // the side camera's
  int step = 1;          // trial samples per video frame
};

void WriteFaultsJson(const std::filesystem::path& dir, double abduction_deg) {
  std::filesystem::create_directories(dir);
  acro::WriteFileAtomically(
      dir / "faults.json",
      fmt::format("{{\n  \"note\": \"the large faults put into the sample routine (skills "
                  "0-based: 0 the straight jump, the video's partial first flight)\",\n"
                  "  \"faults\": [\n"
                  "    {{\"skill\": 2, \"fault\": \"knees_bent\", \"value\": 45, "
                  "\"unit\": \"deg\"}},\n"
                  "    {{\"skill\": 3, \"fault\": \"legs_apart\", \"value\": 0.40, "
                  "\"unit\": \"m\", \"abduction_deg\": {:.3f}}},\n"
                  "    {{\"skill\": 5, \"fault\": \"tuck_open\", \"value\": 110, "
                  "\"unit\": \"deg\"}}\n  ]\n}}\n",
                  abduction_deg));
}

// Three phones around the bed as a hall would place them, each started by hand at its own moment
// (a fraction of a frame apart too) and before the first jump's take-off (sample 22), which the
// side camera misses: at the bed's end, at a corner, high on the far side. With the side camera,
// the multi-camera sample (docs/markerless.md). `preview`: {CAMERA, K, OUT.png} or empty.
int RenderPhones(const Render& r,
                 const acro::vision::Camera& side,
                 const std::filesystem::path& dir,
                 const std::vector<std::string>& preview) {
  const Eigen::Vector3d bed = r.routine.options.bed_centre_m;
  const Eigen::Vector3d look = bed + Eigen::Vector3d(0, 0, 2.6);
  struct View {
    acro::vision::Camera camera;
    int first_sample;
  };
  const std::vector<View> phones = {
      {Phone("end", bed + Eigen::Vector3d(-8.6, -1.2, 0.4), look, 1250.0, -0.05),
       r.first_sample - 54},
      {Phone("corner", bed + Eigen::Vector3d(6.4, -6.2, 0.2), look, 1230.0, -0.07),
       r.first_sample - 68},
      {Phone("far", bed + Eigen::Vector3d(-2.5, 6.9, 2.9), look, 1270.0, -0.04),
       r.first_sample - 63}};
  if (!preview.empty()) {
    for (const View& v : phones)
      if (v.camera.name == preview[0])
        return RenderCamera(r.routine,
                            r.scene,
                            r.mesh,
                            v.camera,
                            v.first_sample,
                            {},
                            std::stoi(preview[1]),
                            preview[2]) >= 0
                   ? 0
                   : 2;
    std::fprintf(
        stderr, "make_sample_video: no phone named %s (end, corner, far)\n", preview[0].c_str());
    return 2;
  }
  std::vector<acro::vision::Camera> all = {side};
  std::string truth =
      "{\n  \"note\": \"frame k of each video shows the trial's sample first_sample + step k "
      "(the true motion, "
      "noise-free); offset_frames: where each video's frame 0 falls in the side video's "
      "frames\",\n  \"fps\": " +
      fmt::format("{}", kFps) + ",\n  \"step\": " + std::to_string(r.step) + ",\n  \"videos\": [\n";
  truth += fmt::format(
      "    {{\"camera\": \"side\", \"video\": \"side_camera.mp4\", \"first_sample\": {}, "
      "\"offset_frames\": 0}}",
      r.first_sample);
  for (const View& v : phones) {
    const std::string name = v.camera.name + "_camera.mp4";
    const int frames =
        RenderCamera(r.routine, r.scene, r.mesh, v.camera, v.first_sample, dir / name, -1, "");
    std::printf("wrote %s: %d frames from sample %d\n",
                (dir / name).string().c_str(),
                frames,
                v.first_sample);
    all.push_back(v.camera);
    truth += fmt::format(
        ",\n    {{\"camera\": \"{}\", \"video\": \"{}\", \"first_sample\": {}, "
        "\"offset_frames\": {}}}",
        v.camera.name,
        name,
        v.first_sample,
        double(v.first_sample - r.first_sample) / r.step);
  }
  truth += "\n  ]\n}\n";
  acro::vision::WritePose2SimToml(all, dir / "views.toml");
  acro::WriteFileAtomically(dir / "views_truth.json", truth);
  std::printf("wrote %s and %s\n",
              (dir / "views.toml").string().c_str(),
              (dir / "views_truth.json").string().c_str());
  return 0;
}

// The side camera's video, its calibration and its truth (or one frame of it: `preview` {K,
// OUT.png}).
int RenderSide(const Render& r,
               const acro::vision::Camera& camera,
               const std::filesystem::path& dir,
               const std::vector<std::string>& preview) {
  const bool one_frame = !preview.empty();
  if (!one_frame) acro::vision::WritePose2SimToml({camera}, dir / "side_camera.toml");
  const int frames = RenderCamera(r.routine,
                                  r.scene,
                                  r.mesh,
                                  camera,
                                  r.first_sample,
                                  dir / "side_camera.mp4",
                                  one_frame ? std::stoi(preview[0]) : -1,
                                  one_frame ? preview[1] : "");
  if (one_frame) {
    if (frames >= 0) return 0;
    std::fprintf(stderr, "make_sample_video: frame %s is not in the video\n", preview[0].c_str());
    return 2;
  }
  acro::WriteFileAtomically(
      dir / "video_truth.json",
      fmt::format(
          "{{\n  \"video\": \"side_camera.mp4\",\n  \"calibration\": \"side_camera.toml\",\n"
          "  \"camera\": \"side\",\n  \"fps\": {},\n  \"offset_s\": {},\n"
          "  \"note\": \"video time = offset_s + trial time: frame k shows the trial's "
          "sample {} + {}k (the true motion, noise-free)\"\n}}\n",
          kFps,
          kOffsetS,
          r.first_sample,
          r.step));
  std::printf("wrote %s: %d frames at %g fps, offset %g s; %s\n",
              (dir / "side_camera.mp4").string().c_str(),
              frames,
              kFps,
              kOffsetS,
              (dir / "side_camera.toml").string().c_str());
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  const bool preview = argc == 6 && std::string(argv[3]) == "--frame";
  const bool faults = (argc == 5 || (argc == 6 && std::string(argv[5]) == "--views")) &&
                      std::string(argv[3]) == "--faults" && std::string(argv[4]) == "large";
  const bool views = (argc >= 4 && std::string(argv[3]) == "--views") || (faults && argc == 6);
  if (argc != 3 && !preview && !faults && !(views && (argc == 4 || argc == 7))) {
    std::fprintf(stderr,
                 "usage: make_sample_video ATHLETE.yaml OUT_DIR [--frame K OUT.png]\n"
                 "       make_sample_video ATHLETE.yaml OUT_DIR --views [CAMERA K OUT.png]\n"
                 "       make_sample_video ATHLETE.yaml OUT_DIR --faults large [--views]\n");
    return 2;
  }
  const std::filesystem::path athlete = argv[1];
  const std::filesystem::path dir = argv[2];
  try {
    const std::string label = "samples/athletes/" + athlete.filename().string();
    acro::samples::SampleRoutineOptions routine_options;
    double abduction_deg = 0;
    if (faults) routine_options.faults = LargeFaults(athlete, label, 0.40, &abduction_deg);
    const acro::samples::SampleRoutine routine =
        acro::samples::MakeSampleRoutine(athlete, label, routine_options);
    if (faults) WriteFaultsJson(dir, abduction_deg);
    const acro::analysis::AthleteBody body =
        acro::analysis::MakeAthleteBody(acro::analysis::ReadAthleteProfile(athlete));
    acro::analysis::Motion motion;
    motion.q = routine.q;
    const acro::analysis::BodyMesh body_mesh_H = acro::analysis::MakeEllipsoidBodyMesh(body);
    acro::analysis::AthleteScene athlete_scene(body, body_mesh_H, motion, routine.model);

    const acro::vision::Camera camera = SideCamera(routine.options.bed_centre_m);
    const double rate = routine.trial.point_rate_hz;
    const Render render{routine,
                        athlete_scene,
                        body_mesh_H,
                        static_cast<int>(std::lround(-kOffsetS * rate)),
                        static_cast<int>(std::lround(rate / kFps))};
    std::filesystem::create_directories(dir);
    const acro::ui::XDisplay display;
    if (views)
      return RenderPhones(render,
                          camera,
                          dir,
                          argc == 7 ? std::vector<std::string>{argv[4], argv[5], argv[6]}
                                    : std::vector<std::string>{});
    return RenderSide(
        render,
        camera,
        dir,
        preview ? std::vector<std::string>{argv[4], argv[5]} : std::vector<std::string>{});
  } catch (const std::exception& e) {
    std::fprintf(stderr, "make_sample_video: %s\n", e.what());
    return 1;
  }
}
