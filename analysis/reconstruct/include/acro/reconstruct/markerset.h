#pragma once

// Marker sets: which segment of the standard human each marker (or video keypoint) belongs to,
// where it sits, how much it weighs in the fit, and which marker is its left/right mirror. Sets are
// data files (docs/formats/markerset.md); the shipped ones (analysis/markersets/*.yaml) are
// compiled into the library. DetectMarkerSet picks the set that matches a trial's labels best.

#include <filesystem>
#include <string>
#include <string_view>
#include <vector>

#include <Eigen/Core>

#include "acro/base/yaml.h"
#include "acro/capture/trial.h"
#include "acro/dynamics/model.h"

namespace acro::analysis {

struct MarkerDefinition {
  std::string name;
  std::vector<std::string> aliases;  ///< other spellings accepted in trials ("L Hip")
  std::string segment;               ///< standard segment name ("l_thigh")
  std::string at;                    ///< named model point the offset starts from ("" = origin)
  /// Offset from `at` in the body frame H of the reference pose, for an athlete of the set's
  /// reference height (m).
  Eigen::Vector3d offset_m = Eigen::Vector3d::Zero();
  double weight = 1.0;
  std::string mirror;  ///< the marker on the other side ("" on the midline)
};

struct MarkerSet {
  std::string name;   ///< "plug_in_gait"
  std::string title;  ///< one line for reports
  double reference_height_m = 1.75;
  /// Video keypoints rather than skin markers: no static trial, scaling to a window of the motion.
  bool keypoints = false;
  std::vector<MarkerDefinition> markers;
  std::string source;  ///< file name (or "builtin:<name>")

  /// Index of the marker whose name or an alias equals `label` (after stripping a "Subject:"
  /// prefix; case-insensitive), or −1.
  int Find(std::string_view label) const;
};

/// Parses a marker-set document; `model`, when given, is used to check segment and point names.
/// Throws acro::InputError naming the file, line and key.
MarkerSet MarkerSetFromYaml(const YamlNode& root, const dynamics::Model<double>* model = nullptr);
/// Reads a marker-set file.
MarkerSet ReadMarkerSet(const std::filesystem::path& path,
                        const dynamics::Model<double>* model = nullptr);
/// Names of the shipped sets: "plug_in_gait", "helen_hayes", "trampoline" (markers); "coco17",
/// "body25", "body25b", "halpe26", "blazepose33" (video keypoints).
std::vector<std::string> BuiltinMarkerSetNames();
/// A shipped set by name; throws acro::InputError (where "markerset") for an unknown name.
MarkerSet BuiltinMarkerSet(std::string_view name);
/// A shipped set by name, or a file when `name_or_path` names one (ends in .yaml/.yml).
MarkerSet LoadMarkerSet(std::string_view name_or_path);

/// A trial label without a "Subject:" prefix.
std::string StripSubjectPrefix(std::string_view label);

/// How a marker set maps onto a trial's points.
struct MarkerSetMatch {
  std::string set_name;
  /// Per marker of the set: the trial point index, or −1 when the trial lacks it.
  std::vector<int> trial_point;
  int num_matched = 0;
  /// Trial labels of markers (PointType::kMarker) that no marker of the set claims.
  std::vector<std::string> unmatched_labels;
  /// Set markers absent from the trial.
  std::vector<std::string> missing_markers;
  /// One line: "plug_in_gait: 39 of 39 markers matched; 2 trial labels unmatched: …".
  std::string Report() const;
};

/// Matches one set against a trial's labels (the first trial point wins when a label repeats).
MarkerSetMatch MatchMarkerSet(const MarkerSet& set, const capture::Trial& trial);

/// Tries every shipped set and returns the one matching most markers (ties: the larger fraction
/// of the set). `match` receives its match. Throws acro::InputError when no set matches at least
/// four markers.
MarkerSet DetectMarkerSet(const capture::Trial& trial, MarkerSetMatch* match);

/// Marker positions in their segment frames for `model` (a standard human, reference pose):
/// p_BoM_B = p_BoAt_B + offset_m · height_m / reference_height_m. Throws acro::InputError for a
/// segment or point the model lacks.
struct ModelMarker {
  std::string name;
  int segment = 0;
  Eigen::Vector3d p_BoM_B = Eigen::Vector3d::Zero();
  double weight = 1.0;
  int mirror = -1;  ///< index of the mirror marker in the same list, or −1
};
std::vector<ModelMarker> PlaceMarkers(const MarkerSet& set,
                                      const dynamics::Model<double>& model,
                                      double height_m);

}  // namespace acro::analysis
