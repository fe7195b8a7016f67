#pragma once

// The sample trampoline routine (samples/trials/trampoline_routine/): a routine of six skills
// made by the project's own tools for one athlete. Flights are simulated by the dynamics engine
// (dynamics::SimulateFlight: prescribed joint angles, free root under gravity, so the COM follows
// the ballistic parabola and the angular momentum about it is conserved); the take-off angular
// momentum of each skill is found by shooting so that it lands with its nominal rotation. Contacts
// are on a spring-damper bed: m z̈ = −m g + max(0, k d + c ḋ), d the bed depression under the
// feet, with orientation and joint angles blended (cubic Hermite) from the landing state to the
// next take-off state and a knee-and-hip "push" that gives the athlete the energy of the next
// flight. Markers of the "trampoline" marker set by forward kinematics, 1 mm Gaussian noise (a
// fixed seed and our own Box–Muller, so the file is the same on every run) and a few gaps; four
// static markers at the corners of the woven bed.

#include <filesystem>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "acro/capture/trial.h"
#include "acro/design/routine_simulation.h"
#include "acro/dynamics/model.h"

namespace acro::samples {

/// A fault put into one skill of the routine, as an athlete would make it (the execution
/// assistant's tests, tests/analysis/assess/execution_faults_test.cc). "The shape" is every posture
/// of the skill's plan between its take-off and its landing posture.
struct SampleFault {
  enum class Kind {
    kKneesBent,  ///< `value` degrees of knee flexion added over the shape
    kLegsApart,  ///< each hip abducted by `value` degrees over the shape
    kArmsOut,    ///< each arm abducted to `value` degrees over the shape (sideways, in place of
                 ///< the held position)
    kTuckAngle,  ///< the closed postures' trunk–thigh angle set to `value` degrees (the tuck's
                 ///< own: 48°)
    kOpening,    ///< the closed shape held, then opened straight into the landing posture with
                 ///< the trunk–thigh angle passing 135° `value` seconds before landing
    kLanding,    ///< the landing target moved by `offset_m` (along, across the bed)
  };
  int skill = 0;  ///< 0-based, in the routine's order
  Kind kind = Kind::kKneesBent;
  double value = 0;
  Eigen::Vector2d offset_m = Eigen::Vector2d::Zero();
};

/// The routine's rate, integration grid and bed (acro/design/routine_simulation.h; the sample
/// keeps the reverse squat it was first made with, absorb_by_late_squat = false), the markers'
/// noise, and the variations of a season.
struct SampleRoutineOptions : analysis::RoutineSimulationOptions {
  SampleRoutineOptions() { absorb_by_late_squat = false; }
  double noise_sd_m = 0.001;
  unsigned noise_seed = 20261122;
  /// Variations of the routine (a season of them, tests/library): every flight time scaled (a
  /// higher or lower routine; 0.9–1.1 keeps every skill within reach), every landing target moved
  /// on the bed (m, along and across it), and only the first `num_skills` skills (1–6).
  double flight_time_scale = 1.0;
  Eigen::Vector2d landing_offset_m = Eigen::Vector2d::Zero();
  int num_skills = 6;
  /// The routine's skills as indices into the six (0 the straight jump … 5 the double back; empty:
  /// all six in order, before `num_skills`): {0, 1, 2, 3, 2, 5} performs the back pike where the
  /// full was, as a synchro partner who changed element 4 would.
  std::vector<int> skill_order;
  /// Faults put into given skills (none: the clean routine).
  std::vector<SampleFault> faults;
};

/// One flight and one bed contact as simulated (acro/design/routine_simulation.h).
using SampleFlightTruth = analysis::RoutineFlightTruth;
using SampleContactTruth = analysis::RoutineContactTruth;

/// The simulated routine (its model, flights, contacts, noise-free q and v per frame, C¹ check)
/// and its trial: the markers placed from q, with noise and a few gaps.
struct SampleRoutine : analysis::SimulatedRoutine {
  std::string athlete_file;
  capture::Trial trial;

  /// truth.json: the flights, contacts, bed and athlete.
  std::string TruthJson() const;
};

/// Simulates the routine for the athlete profile at `athlete_path` (docs/formats/athlete.md).
/// `athlete_label` is the path written into truth.json. Throws acro::InputError for a bad profile.
SampleRoutine MakeSampleRoutine(const std::filesystem::path& athlete_path,
                                const std::string& athlete_label,
                                const SampleRoutineOptions& options = {});

/// Physics of one flight on the noise-free frames strictly between take-off and landing.
using SampleFlightPhysics = analysis::RoutineFlightPhysics;

SampleFlightPhysics CheckSampleFlight(const SampleRoutine& routine, int flight);

}  // namespace acro::samples
