#pragma once

// What a trial's measurement noise alone does to the physical check (docs/physical-check.md,
// "Judged against the noise"). Video keypoints carry centimetres of noise; filtered, fitted and
// differentiated twice, noise alone gives flight residuals that the thresholds made for optical
// markers call failures. The noise floor measures that on the trial itself: each judged flight's
// motion, as its model markers, is given white noise of the trial's measured RMS, filtered with
// the trial's filter, fitted by the same inverse kinematics (same model, markers, limits and
// priors; each frame warm-started at the motion's own pose) and run through the same inverse
// dynamics; what changes in the judged measures against the same markers fitted without noise
// and without filter is what the noise alone gives — through the filter its level made necessary,
// whose smoothing of a fast motion is part of it. The check is then judged against it
// (JudgeAgainstNoise).

#include <functional>
#include <string>
#include <vector>

#include "acro/assess/physical_check.h"
#include "acro/reconstruct/reconstruction.h"

namespace acro::analysis {

struct NoiseFloorOptions {
  /// Noisy copies per flight; the floor is the largest of their measures. Copies after the
  /// first only for flights whose first copy reaches half a threshold (divided by the factor).
  int repetitions = 5;
  unsigned seed = 20261202;
  /// Frames fitted on each side of the judged frames, for the filter and the differences (s).
  double padding_s = 0.3;
  /// Worker threads over the flights and copies (0: the hardware's concurrency).
  int num_threads = 0;
  /// Asked between the copies: true stops, and every floor is returned as zero.
  std::function<bool()> cancelled;

  bool IsValid(std::string* why) const;
};

/// One floor per judged flight of `check` (check.flights order), for white noise of `noise_rms_m`
/// per coordinate on the markers of `rec` (recorded samples only, as the fit uses them). The
/// physical check options give the residual window and the momentum floor.
std::vector<FlightNoiseFloor> CalcNoiseFloor(const ReconstructionResult& rec,
                                             const PhysicalCheck& check,
                                             double noise_rms_m,
                                             const PhysicalCheckOptions& check_options,
                                             const NoiseFloorOptions& options = {});

}  // namespace acro::analysis
