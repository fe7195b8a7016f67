#pragma once

// Two jumps side by side (`acrolab compare`): each athlete posed by its own analysed trial, the
// second placed at the first's take-off — its take-off feet on the first's, its heading (the
// pelvis's forward axis, horizontal) turned onto the first's, its time counted from its own
// take-off — so that where the two skills part is where they differ. Plain data in the first
// jump's lab frame; the curves (COM height, somersault and twist angles over the flight) for the
// chart under the views.

#include <string>
#include <vector>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "acro/assess/trial_analysis.h"
#include "acro/scene/athlete_scene.h"
#include "acro/scene/skill_ghost.h"

namespace acro::analysis {

/// One jump to compare: an analysed trial, the body it was analysed for, the mesh to draw, and
/// the jump's index (1-based, as jumps.json numbers them) — or a designed skill.
struct CompareJump {
  const capture::Trial* trial = nullptr;
  const TrialAnalysis* analysis = nullptr;
  const AthleteBody* body = nullptr;
  BodyMesh mesh;
  int jump = 1;
  std::string label;  ///< "A: 40o back somersault"
  /// Instead of a trial's jump, a designed skill (ReadSkillGhost or MakeSkillGhost) posed on
  /// `body`'s standard human: `trial` and `analysis` stay null, `jump` is not used. It must
  /// outlive the scene.
  const SkillGhost* design = nullptr;
};

/// One instant, τ seconds after both take-offs.
struct CompareFrame {
  double tau_s = 0.0;
  AthletePose a;
  AthletePose b;  ///< placed at A's take-off (CompareScene::b_to_a)
  bool a_in_flight = false;
  bool b_in_flight = false;
};

/// A jump's curves over its flight, τ from take-off (s), in A's frame.
struct JumpCurves {
  std::vector<double> tau_s;
  std::vector<double> com_height_m;
  std::vector<double> somersault_deg;  ///< forward positive, from take-off
  std::vector<double> twist_deg;
};

/// The take-off of jump `jump` (1-based) of `analysis`: its feet position and heading (the pelvis's
/// forward axis at the take-off frame, horizontal, unit). Throws acro::InputError (where "jump")
/// for an index out of range.
struct TakeoffPlacement {
  Eigen::Vector3d feet_W = Eigen::Vector3d::Zero();
  Eigen::Vector3d heading_W = Eigen::Vector3d::UnitX();
  double takeoff_s = 0.0;
  double landing_s = 0.0;
};
TakeoffPlacement FindTakeoff(const TrialAnalysis& analysis, int jump);

/// How a comparison names a jump: "40o back somersault (jump 2)" (empty for a jump not there).
std::string JumpLabel(const TrialAnalysis& analysis, int jump);

/// The take-off of a designed skill (ReadSkillGhost for `model`, its standard human): the feet
/// and heading of its first frame, time 0, landing at its flight time.
TakeoffPlacement FindDesignTakeoff(const SkillGhost& design,
                                   const dynamics::Model<double>& model);

/// The rigid motion that puts a jump taking off at `from` onto the take-off `onto`: its heading
/// turned onto `onto`'s about the vertical, then its take-off feet onto `onto`'s.
Eigen::Isometry3d PlaceAtTakeoff(const TakeoffPlacement& from, const TakeoffPlacement& onto);

/// Moves a pose by `X` (mesh, skeleton and COM).
void TransformPose(const Eigen::Isometry3d& X, AthletePose* pose);

class CompareScene {
 public:
  /// Throws acro::InputError (where "jump") when a jump index is not a flight of its trial, and
  /// std::invalid_argument when a jump lacks its trial, analysis or body (or its design and body).
  CompareScene(CompareJump a, CompareJump b);

  /// τ from the take-offs (0) to a quarter second after the later landing.
  double start_s() const { return start_s_; }
  double end_s() const { return end_s_; }
  /// The rigid motion that places B's jump at A's take-off.
  const Eigen::Isometry3d& b_to_a() const { return b_to_a_; }
  const CompareJump& a() const { return a_; }
  const CompareJump& b() const { return b_; }

  void Frame(double tau_s, CompareFrame* out);
  JumpCurves CurvesA() const;
  JumpCurves CurvesB() const;

 private:
  CompareJump a_, b_;
  AthleteScene scene_a_, scene_b_;
  TakeoffPlacement pa_, pb_;
  Eigen::Isometry3d b_to_a_ = Eigen::Isometry3d::Identity();
  double start_s_ = 0.0, end_s_ = 0.0;
  /// A design's centre of mass per frame of its motion (a jump's is its analysis').
  Eigen::Matrix3Xd design_com_a_, design_com_b_;
  JumpCurves Curves(const CompareJump& j,
                    const TakeoffPlacement& p,
                    const Eigen::Matrix3Xd& design_com,
                    const Eigen::Isometry3d& to_a) const;
};

}  // namespace acro::analysis
