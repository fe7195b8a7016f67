#include "acro/scene/trial_scene.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <map>
#include <sstream>
#include <stdexcept>

#include <fmt/format.h>

#include "acro/athlete/standard_human.h"
#include "acro/base/input_error.h"
#include "acro/scene/compare_scene.h"

namespace acro::analysis {

namespace {

// A joint's name reduced to side + joint: "RHip", "right_hip", "r_hip", "R.Hip" → "rhip";
// Plug-in Gait's four-letter names map to the same words (RKNE → rknee).
std::string Canonical(const std::string& name) {
  std::string s;
  for (char c : name)
    if (std::isalnum(static_cast<unsigned char>(c)))
      s += char(std::tolower(static_cast<unsigned char>(c)));
  for (const auto& [long_form, short_form] :
       {std::pair<std::string, std::string>{"right", "r"}, {"left", "l"}})
    if (s.rfind(long_form, 0) == 0) s = short_form + s.substr(long_form.size());
  static const std::map<std::string, std::string> kPluginGait = {{"rkne", "rknee"},
                                                                 {"lkne", "lknee"},
                                                                 {"rank", "rankle"},
                                                                 {"lank", "lankle"},
                                                                 {"rsho", "rshoulder"},
                                                                 {"lsho", "lshoulder"},
                                                                 {"relb", "relbow"},
                                                                 {"lelb", "lelbow"},
                                                                 {"rwra", "rwrist"},
                                                                 {"lwra", "lwrist"},
                                                                 {"rhee", "rheel"},
                                                                 {"lhee", "lheel"},
                                                                 {"rtoe", "rbigtoe"},
                                                                 {"ltoe", "lbigtoe"},
                                                                 {"rasi", "rhip"},
                                                                 {"lasi", "lhip"},
                                                                 {"c7", "neck"},
                                                                 {"midhip", "hip"},
                                                                 {"pelvis", "hip"}};
  if (const auto it = kPluginGait.find(s); it != kPluginGait.end()) return it->second;
  return s;
}

}  // namespace

SceneShow ParseSceneShow(const std::string& text) {
  SceneShow show;
  std::stringstream words(text);
  std::string word;
  while (std::getline(words, word, ',')) {
    if (word == "mesh") {
      show.mesh = true;
    } else if (word == "skeleton") {
      show.skeleton = true;
    } else if (word == "markers" || word == "keypoints") {
      show.markers = true;
    } else if (word == "com") {
      show.com = true;
    } else if (word == "residual") {
      show.residual = true;
    } else if (word == "mismatch") {
      show.mismatch = true;
    } else {
      throw InputError(
          "",
          "--show",
          "'" + word + "' is not one of mesh, skeleton, markers, com, residual, mismatch");
    }
  }
  return show;
}

Rgba VerdictColour(bool judged, bool pass) {
  if (!judged) return {0.95f, 0.95f, 0.95f, 1.0f};
  return pass ? Rgba{0.35f, 0.9f, 0.35f, 1.0f} : Rgba{1.0f, 0.35f, 0.3f, 1.0f};
}

std::vector<std::pair<int, int>> KeypointLinks(const std::vector<std::string>& names) {
  std::map<std::string, int> index;
  for (size_t i = 0; i < names.size(); ++i) index.emplace(Canonical(names[i]), int(i));
  static const char* kPairs[][2] = {
      {"rhip", "rknee"},       {"rknee", "rankle"},      {"rankle", "rheel"},
      {"rankle", "rbigtoe"},   {"rbigtoe", "rsmalltoe"}, {"rheel", "rbigtoe"},
      {"lhip", "lknee"},       {"lknee", "lankle"},      {"lankle", "lheel"},
      {"lankle", "lbigtoe"},   {"lbigtoe", "lsmalltoe"}, {"lheel", "lbigtoe"},
      {"rshoulder", "relbow"}, {"relbow", "rwrist"},     {"lshoulder", "lelbow"},
      {"lelbow", "lwrist"},    {"rhip", "lhip"},         {"rshoulder", "lshoulder"},
      {"neck", "head"},        {"head", "nose"},         {"neck", "nose"},
      {"hip", "neck"},         {"rshoulder", "rhip"},    {"lshoulder", "lhip"},
      {"nose", "reye"},        {"nose", "leye"},         {"reye", "rear"},
      {"leye", "lear"}};
  std::vector<std::pair<int, int>> links;
  for (const auto& pair : kPairs) {
    const auto a = index.find(pair[0]), b = index.find(pair[1]);
    if (a == index.end() || b == index.end()) continue;
    links.emplace_back(a->second, b->second);
  }
  return links;
}

std::vector<BodySide> KeypointLinkSides(const std::vector<std::string>& names,
                                        const std::vector<std::pair<int, int>>& links) {
  std::vector<BodySide> sides;
  for (const auto& [a, b] : links) {
    // A link is on a side when both its ends are (the hips across are the centre).
    const BodySide sa = SideOfName(names[size_t(a)]), sb = SideOfName(names[size_t(b)]);
    sides.push_back(sa == sb ? sa : BodySide::kCentre);
  }
  return sides;
}

BodyMeshOptions OverlayBodyMeshOptions() {
  BodyMeshOptions options;
  options.points_per_semicircle = 16;
  options.ellipsoid_bands = 10;
  return options;
}

TrialScene::TrialScene(const capture::Trial& trial, const vision::AxisMapping& axes)
    : trial_(trial), axes_(axes) {
  std::vector<std::string> names;
  for (const capture::PointInfo& p : trial.points) names.push_back(p.label);
  links_ = KeypointLinks(names);
  link_sides_ = KeypointLinkSides(names, links_);
}

TrialScene::TrialScene(const capture::Trial& trial,
                       const TrialAnalysis& analysis,
                       const AthleteBody& body,
                       BodyMesh mesh)
    : TrialScene(trial, vision::AxisMapping{}) {
  const Motion& motion = analysis.reconstruction.motion;
  if (motion.num_frames() != trial.num_frames)
    throw std::invalid_argument("the analysis has " + std::to_string(motion.num_frames()) +
                                " frames, the trial " + std::to_string(trial.num_frames));
  analysis_ = &analysis;
  athlete_ =
      std::make_unique<AthleteScene>(body, std::move(mesh), motion, analysis.reconstruction.model);
}

struct TrialScene::Ghost {
  int own_jump = 0;                          // a jump of this trial: not shown in its own flight
  std::string label;                         // "jump 2", "back tuck (design)"
  TakeoffPlacement takeoff;                  // the ghost's own
  Motion design_motion;                      // a design's motion
  const Motion* motion = nullptr;            // the ghost's motion (a jump's is its analysis')
  std::unique_ptr<AthleteScene> athlete;     // posing the ghost
  std::vector<Eigen::Isometry3d> placement;  // per flight: the ghost onto its take-off
  bool shown_in(int flight) const { return flight >= 0 && flight + 1 != own_jump; }
};

TrialScene::~TrialScene() = default;

namespace {

// Per flight of `analysis`: the rigid motion that places a ghost taking off at `ghost` on that
// flight's take-off (identity for a flight that is not a jump).
std::vector<Eigen::Isometry3d> PlaceOnEveryFlight(const TrialAnalysis& analysis,
                                                  const TakeoffPlacement& ghost) {
  std::vector<Eigen::Isometry3d> placement;
  for (size_t k = 0; k < analysis.phases.flights.size(); ++k) {
    Eigen::Isometry3d X = Eigen::Isometry3d::Identity();
    for (const JumpMetrics& j : analysis.jumps)
      if (j.index == int(k) + 1) X = PlaceAtTakeoff(ghost, FindTakeoff(analysis, j.index));
    placement.push_back(X);
  }
  return placement;
}

}  // namespace

void TrialScene::SetGhostJump(int jump) {
  if (!athlete_) throw std::invalid_argument("TrialScene::SetGhostJump: the scene has no athlete");
  auto ghost = std::make_unique<Ghost>();
  ghost->own_jump = jump;
  ghost->label = fmt::format("jump {}", jump);
  ghost->takeoff = FindTakeoff(*analysis_, jump);
  ghost->motion = &analysis_->reconstruction.motion;
  ghost->athlete = std::make_unique<AthleteScene>(*athlete_);
  ghost->placement = PlaceOnEveryFlight(*analysis_, ghost->takeoff);
  ghost_ = std::move(ghost);
}

void TrialScene::SetGhostJump(const TrialAnalysis& other,
                              const AthleteBody& body,
                              BodyMesh mesh,
                              int jump,
                              const std::string& label) {
  if (!athlete_) throw std::invalid_argument("TrialScene::SetGhostJump: the scene has no athlete");
  auto ghost = std::make_unique<Ghost>();
  ghost->label = label;
  ghost->takeoff = FindTakeoff(other, jump);
  ghost->motion = &other.reconstruction.motion;
  ghost->athlete = std::make_unique<AthleteScene>(
      body, std::move(mesh), other.reconstruction.motion, other.reconstruction.model);
  ghost->placement = PlaceOnEveryFlight(*analysis_, ghost->takeoff);
  ghost_ = std::move(ghost);
}

void TrialScene::SetGhostDesign(const SkillGhost& design, const AthleteBody& body) {
  if (!athlete_)
    throw std::invalid_argument("TrialScene::SetGhostDesign: the scene has no athlete");
  auto ghost = std::make_unique<Ghost>();
  ghost->label = design.name + " (design)";
  ghost->design_motion = design.motion;
  ghost->motion = &ghost->design_motion;
  ghost->takeoff = FindDesignTakeoff(design, MakeStandardHumanModel(body));
  ghost->athlete = std::make_unique<AthleteScene>(body, athlete_->mesh(), ghost->design_motion);
  ghost->placement = PlaceOnEveryFlight(*analysis_, ghost->takeoff);
  ghost_ = std::move(ghost);
}

void TrialScene::ClearGhost() {
  ghost_.reset();
}

int TrialScene::FlightAt(int sample) const {
  if (analysis_ == nullptr) return -1;
  const std::vector<Flight>& flights = analysis_->phases.flights;
  for (size_t k = 0; k < flights.size(); ++k)
    if (sample >= flights[k].takeoff_frame && sample < flights[k].landing_frame) return int(k);
  return -1;
}

void TrialScene::Frame(int sample, TrialFrame* out) {
  if (sample < 0 || sample >= trial_.num_frames)
    throw std::out_of_range("sample " + std::to_string(sample) + " of " +
                            std::to_string(trial_.num_frames));
  out->sample = sample;
  out->time_s = trial_.point_rate_hz > 0 ? sample / trial_.point_rate_hz : 0.0;
  // Measured points: the buffer is reallocated only when the number present changes.
  int present = 0;
  for (int p = 0; p < trial_.num_points(); ++p) present += trial_.valid(sample, p) ? 1 : 0;
  out->markers_W.resize(3, present);
  for (int p = 0, k = 0; p < trial_.num_points(); ++p)
    if (trial_.valid(sample, p))
      out->markers_W.col(k++) = axes_.ToWorld(trial_.position(sample, p));
  // The keypoint skeleton: a missing end puts both ends on the other (a zero-length segment), so
  // the segment count never changes.
  out->keypoint_links.name = "keypoints";
  out->keypoint_links.colour = {0.1f, 0.9f, 1.0f, 1.0f};
  out->keypoint_links.segment_sides = link_sides_;
  out->keypoint_links.points_W.resize(3, 2 * Eigen::Index(links_.size()));
  for (size_t k = 0; k < links_.size(); ++k) {
    const auto [a, b] = links_[k];
    const bool va = trial_.valid(sample, a), vb = trial_.valid(sample, b);
    const Eigen::Vector3d pa =
        va ? axes_.ToWorld(trial_.position(sample, a))
           : (vb ? axes_.ToWorld(trial_.position(sample, b)) : Eigen::Vector3d(0, 0, -1000));
    const Eigen::Vector3d pb = vb ? axes_.ToWorld(trial_.position(sample, b)) : pa;
    out->keypoint_links.points_W.col(2 * Eigen::Index(k)) = pa;
    out->keypoint_links.points_W.col(2 * Eigen::Index(k) + 1) = pb;
  }
  out->heads_up = fmt::format("{:7.3f} s", out->time_s);
  out->heads_up_colour = VerdictColour(false, false);
  if (!athlete_) return;

  athlete_->Pose(sample, &out->athlete);
  const PhysicalCheck& check = analysis_->check;
  const int flight = FlightAt(sample);
  out->ghost_shown = false;
  if (ghost_ && ghost_->shown_in(flight)) {
    // The ghost at the same time from its own take-off, until it lands.
    const double tau = out->time_s - analysis_->phases.flights[size_t(flight)].takeoff_s;
    const double t = std::min(ghost_->takeoff.takeoff_s + tau, ghost_->takeoff.landing_s);
    ghost_->athlete->Pose(FrameNearestTime(*ghost_->motion, t), &out->ghost);
    TransformPose(ghost_->placement[size_t(flight)], &out->ghost);
    out->ghost_shown = true;
  }
  // The COM's path from this flight's take-off (the trail stays empty in contact).
  const int first = flight >= 0 ? analysis_->phases.flights[size_t(flight)].takeoff_frame : sample;
  out->com_trail.name = "COM path";
  out->com_trail.colour = {1.0f, 0.85f, 0.0f, 1.0f};
  out->com_trail.points_W.resize(3, 2 * (sample - first));
  for (int k = first; k < sample; ++k) {
    out->com_trail.points_W.col(2 * (k - first)) = check.frames.com_W.col(k);
    out->com_trail.points_W.col(2 * (k - first) + 1) = check.frames.com_W.col(k + 1);
  }
  out->residual.name = "residual force";
  out->residual.colour = {1.0f, 0.2f, 0.9f, 1.0f};
  out->residual.width_px = 5.0;
  out->residual.points_W.resize(3, 2);
  out->residual.points_W.col(0) = out->athlete.com_W;
  out->residual.points_W.col(1) = out->athlete.com_W + check.frames.force_bw.col(sample);
  const double residual_bw = check.frames.force_bw.col(sample).norm();
  if (flight < 0) {
    out->heads_up += fmt::format("  contact  residual {:.2f} BW", residual_bw);
    return;
  }
  const JumpMetrics* jump = nullptr;
  for (const JumpMetrics& j : analysis_->jumps)
    if (j.index == flight + 1) jump = &j;
  out->heads_up += fmt::format("  flight {}", flight + 1);
  if (jump != nullptr && !jump->fig_code.empty()) out->heads_up += "  " + jump->fig_code;
  out->heads_up += fmt::format("  residual {:.2f} BW", residual_bw);
  if (jump != nullptr && jump->check) {
    out->heads_up += jump->check->pass ? "  pass" : "  fail";
    out->heads_up_colour = VerdictColour(true, jump->check->pass);
  }
  if (out->ghost_shown) out->heads_up += "  ghost: " + ghost_->label;
}

}  // namespace acro::analysis
