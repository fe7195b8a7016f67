#pragma once

// Writing a reconstructed Motion: OpenSim .mot (joint angles in degrees), CSV (every coordinate
// with its unit in the column name, and the fit quality), and C3D with the processed markers plus
// the joint angles stored as points the way Vicon Nexus stores model outputs (POINT:ANGLES,
// "LHipAngles" with X = sagittal, Y = frontal, Z = transverse component, degrees). Column and
// point names: docs/reconstruction.md. All writes are atomic.

#include <filesystem>
#include <string>

#include "acro/athlete/motion.h"
#include "acro/capture/storage.h"
#include "acro/capture/trial.h"
#include "acro/reconstruct/reconstruction.h"

namespace acro::analysis {

/// The motion as an OpenSim table: root position (m), root quaternion (unitless), joint angles
/// (degrees; inDegrees=yes), named by MakeCoordinateNames.
capture::Storage MakeMotionStorage(const Motion& motion);
void WriteMotionMot(const Motion& motion, const std::filesystem::path& path);

/// CSV: time_s, pelvis_tx_m … pelvis_qz, <angle>_deg …, rms_m, max_m, num_markers.
std::string FormatMotionCsv(const Motion& motion);
void WriteMotionCsv(const Motion& motion, const std::filesystem::path& path);

/// A trial holding the processed markers (set order, metres) and one angle point per joint
/// (PointType::kAngle, unit "deg"), at the source trial's rate and first frame.
capture::Trial MakeModelOutputTrial(const ReconstructionResult& result,
                                    const capture::Trial& source);
void WriteMotionC3d(const ReconstructionResult& result,
                    const capture::Trial& source,
                    const std::filesystem::path& path);

/// Per-marker residuals as CSV: marker, frames present, mean, RMS and max distance (m).
std::string FormatMarkerResidualsCsv(const Motion& motion);

}  // namespace acro::analysis
