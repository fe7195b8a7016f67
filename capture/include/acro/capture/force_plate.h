#pragma once

#include <string>
#include <vector>

#include "acro/capture/trial.h"

namespace acro::capture {

/// Smallest vertical force (N) for which a centre of pressure is computed; below it the COP and
/// the free moment are NaN (the COP of a nearly unloaded plate is noise divided by noise).
inline constexpr double kMinCopForce_N = 10.0;

/// Computes `plate->force_W_N`, `cop_W_m`, `free_moment_W_Nm` and `moment_at_origin_W_Nm` per
/// analog sample from the trial's analog channels, for FORCE_PLATFORM TYPE 1–4 (C3D manual, "Force
/// platforms"). Channel baselines are first removed over the frames given by ZERO (when ZERO names
/// a valid range); TYPE 4 applies CAL_MATRIX; TYPE 3 combines the eight Kistler channels with the
/// sensor offsets in ORIGIN.
///
/// Sign convention: the outputs are the ground *reaction* — the force and moment that the plate
/// exerts on the body — expressed in W, so a person standing still gives force_W_N ≈ (0, 0, +m g)
/// in a Z-up lab. The analog channels are taken to give that same reaction in the plate frame F;
/// as F's z axis points into the ground, FZ is negative under load (as in the well-formed TYPE 2–4
/// files of the c3d.org and BTK suites: AMTI, Kistler, Motion Analysis). The plate frame F is built
/// from CORNERS: x along corner 2 → corner 1, y completed from corner 4 → corner 1, z = x × y
/// (pointing into the plate); its origin is the centre of the top surface (the mean of the
/// corners). ORIGIN is the position of that surface centre relative to the transducer origin, in F
/// (z ≤ 0 by the manual); a file with ORIGIN z > 0 has it with the opposite sign (c3d.org samples 2
/// and 10) and the vector is negated, with a warning.
///
/// Moments are converted to N·m using the unit of the moment channels (ANALOG:UNITS "Nmm" or "Nm";
/// when empty, the point unit). Plates whose channels are missing or out of range, or whose type is
/// not 1–4, get empty outputs and a warning.
void CalcForcePlateOutputs(const Trial& trial,
                           ForcePlate* plate,
                           std::vector<std::string>* warnings);

}  // namespace acro::capture
