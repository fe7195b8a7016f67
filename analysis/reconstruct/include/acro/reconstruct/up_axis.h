#pragma once

// Which way is up in a trial's file. Acrolab's lab frame has Z up (DESIGN.md); OpenSim and
// Pose2Sim write Y up (the floor is the X–Z plane), some video pipelines other axes. A standing,
// walking or jumping body has its head above its feet over most of a trial — even a trampoline
// routine, upside down only for moments of each somersault — so the axis the body is most often
// upright along names the file's up axis. (Issue "real-data fidelity", item 3.)

#include <string>

#include <Eigen/Core>

#include "acro/capture/trial.h"

namespace acro::analysis {

struct UpAxis {
  int axis = 2;  ///< the file's axis that points up: 0 x, 1 y, 2 z
  int sign = 1;  ///< +1: that axis; −1: its opposite
  /// The fraction of the frames used in which feet→head lies within 45° of that axis.
  double agreement = 0.0;
  int frames = 0;      ///< frames with head and foot markers more than 0.3 m apart
  bool found = false;  ///< false: too few such frames, or no direction clearly up (Z kept)
  /// "+Y", "−Z", …
  std::string Name() const;
};

/// The up axis from the marker set the trial's labels match (DetectMarkerSet): its head markers
/// against its foot markers (ankles, heels, toes), frame by frame — the axis (±x, ±y, ±z) the body
/// is upright along (feet→head within 45° of it) in the most frames. `found` is false when the
/// trial has no such markers, fewer than 10 frames with both, or no axis upright in a quarter of
/// the frames and twice as often as any other.
UpAxis DetectUpAxis(const capture::Trial& trial);

/// The rotation that turns the file's up onto +Z, a quarter or half turn: Y up becomes Z up by a
/// quarter turn about X ((x, y, z) → (x, −z, y)), X up by a quarter turn about Y.
Eigen::Matrix3d RotationToZUp(const UpAxis& up);

/// Orients a trial for analysis: `up` is "auto" (detected; a file whose up is already +Z, or whose
/// up cannot be told, is left alone) or "x", "y", "z", "-x", "-y", "-z" (the file's up, forced).
/// Rotates the trial (capture::RotateTrial) and returns the line to warn with — "<file>: Y up
/// (detected: feet→head along +Y in 97 % …), turned to Z up" — or "" when nothing was turned.
/// Throws acro::InputError (where "--up") for another value.
std::string OrientTrialUp(capture::Trial* trial, const std::string& up, UpAxis* found = nullptr);

}  // namespace acro::analysis
