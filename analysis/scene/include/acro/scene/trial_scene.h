#pragma once

// A trial as drawn, sample by sample: the measured markers or keypoints (joined as a skeleton when
// their names say which joint they are), and — when the trial was analysed for an athlete — the
// athlete's mesh and skeleton posed by the reconstruction, the centre of mass with its path over
// the current flight, the root residual force as an arrow at the COM, and the heads-up line (time,
// phase, jump code, residual). Built once per trial; Frame() reuses the caller's buffers.

#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "acro/assess/trial_analysis.h"
#include "acro/capture/trial.h"
#include "acro/scene/athlete_scene.h"
#include "acro/scene/skill_ghost.h"
#include "acro/scene/scene.h"
#include "acro/vision/projection.h"

namespace acro::analysis {

/// What an overlay shows (`--show mesh,skeleton,markers,com,residual`).
struct SceneShow {
  bool mesh = false;
  bool skeleton = false;
  bool markers = false;
  bool com = false;
  bool residual = false;
  /// The silhouettes' mismatch tinted on the video (an overlay with a background model): red where
  /// the video shows the athlete and the model is not, yellow where the model is and the video
  /// shows no athlete; the heads-up adds their IoU.
  bool mismatch = false;
};

/// Parses a comma-separated list of mesh, skeleton, markers, com, residual, mismatch. Throws
/// acro::InputError (where "--show") naming an unknown word.
SceneShow ParseSceneShow(const std::string& text);

/// The heads-up colours by meaning: a flight that passes the physical check, one that fails, and
/// contact.
Rgba VerdictColour(bool judged, bool pass);

/// One sample of the trial as drawn.
struct TrialFrame {
  int sample = -1;
  double time_s = 0.0;
  /// The measured points present at this sample (gaps left out), W.
  Eigen::Matrix3Xd markers_W;
  /// The measured keypoints joined as a skeleton: a segment with one end missing has both ends on
  /// the other (zero length), one with both missing sits at z = −1000 m (out of sight).
  SceneLines keypoint_links;
  /// With an athlete: the posed mesh, its skeleton and its COM.
  AthletePose athlete;
  /// With an athlete: the COM's path from the current flight's take-off to now, as segments
  /// between consecutive samples (none in contact).
  SceneLines com_trail;
  /// With an athlete: the root residual force at the COM, 1 m per body weight (one segment).
  SceneLines residual;
  /// With a ghost (TrialScene::SetGhostJump, SetGhostDesign), in the flights it is shown in: that
  /// jump or design placed at this flight's take-off (feet, heading, time), when `ghost_shown`.
  bool ghost_shown = false;
  AthletePose ghost;
  /// "3.512 s  flight 2  40<  residual 0.02 BW  pass  ghost: back tuck (design)" or
  /// "3.512 s  contact  residual 1.02 BW".
  std::string heads_up;
  Rgba heads_up_colour;
};

class TrialScene {
 public:
  /// The measured points alone (keypoint trials, checks of a calibration). `axes` maps the file's
  /// axes to the lab's.
  TrialScene(const capture::Trial& trial, const vision::AxisMapping& axes);
  /// With the athlete: `analysis` of `trial` (AnalyzeTrial) for `body`, drawn with `mesh`.
  TrialScene(const capture::Trial& trial,
             const TrialAnalysis& analysis,
             const AthleteBody& body,
             BodyMesh mesh);
  ~TrialScene();

  const capture::Trial& trial() const { return trial_; }
  bool has_athlete() const { return athlete_ != nullptr; }
  int num_samples() const { return trial_.num_frames; }
  double rate_hz() const { return trial_.point_rate_hz; }
  /// The index of the flight (into the analysis' flights) sample `sample` is in, or −1.
  int FlightAt(int sample) const;

  /// Shows jump `jump` (1-based, as jumps.json numbers it) as a ghost in every other flight, placed
  /// at that flight's take-off: its take-off feet on the flight's, its heading turned onto the
  /// flight's, its time counted from its own take-off (the ghost stays at its landing pose once it
  /// has landed). Throws acro::InputError (where "jump") for a jump that is not there, and
  /// std::invalid_argument for a scene without an athlete.
  void SetGhostJump(int jump);
  /// Shows jump `jump` of another analysed trial (`other`, reconstructed for `body`, drawn with
  /// `mesh`) as a ghost in every flight of this one, placed the same way; the heads-up line names
  /// it `label`. `other` must outlive the ghost. Throws as SetGhostJump.
  void SetGhostJump(const TrialAnalysis& other,
                    const AthleteBody& body,
                    BodyMesh mesh,
                    int jump,
                    const std::string& label);
  /// Shows a designed skill (ReadSkillGhost for `body`'s standard human) as a ghost in every
  /// flight, placed the same way at each flight's take-off: where the real jump departs from the
  /// design is where the two part. `body` is the athlete's (the design is posed on its mesh).
  /// Throws std::invalid_argument for a scene without an athlete.
  void SetGhostDesign(const SkillGhost& design, const AthleteBody& body);
  bool has_ghost() const { return ghost_ != nullptr; }
  void ClearGhost();

  void Frame(int sample, TrialFrame* out);

 private:
  struct Ghost;
  std::unique_ptr<Ghost> ghost_;
  const capture::Trial& trial_;
  vision::AxisMapping axes_;
  const TrialAnalysis* analysis_ = nullptr;
  std::unique_ptr<AthleteScene> athlete_;
  /// Pairs of point indices joined in the keypoint skeleton, and the side of each.
  std::vector<std::pair<int, int>> links_;
  std::vector<BodySide> link_sides_;
};

/// The body mesh's resolution for drawing over video: about 20 000 triangles (15 ellipsoids of 10
/// bands and 16 points per half circle), what a software rasteriser draws at video rate; the
/// default resolution (180 000) is for inertia and stills.
BodyMeshOptions OverlayBodyMeshOptions();

/// The pairs of `names` that are joined in a human skeleton, recognised whatever the naming
/// (RHip, right_hip, r_hip, RKNE…): hips–knees–ankles–feet, shoulders–elbows–wrists, the hips and
/// the shoulders across, the neck to head and nose, and the trunk.
std::vector<std::pair<int, int>> KeypointLinks(const std::vector<std::string>& names);

/// The side of each link (SideOfName of its ends: a link is on a side when both ends are).
std::vector<BodySide> KeypointLinkSides(const std::vector<std::string>& names,
                                        const std::vector<std::pair<int, int>>& links);

}  // namespace acro::analysis
