// Makes samples/trials/straight_jump/straight_jump.c3d: a synthetic trampoline jump written with
// Acrolab's own C3D writer, so that a fresh clone can run `acrolab info` (and later the main job)
// with no outside data.
//
// The athlete is a rigid straight body (16 markers of a 1.75 m, 65 kg figure) that sinks into the
// bed, takes off with vertical velocity v0, performs a back somersault at constant rate in flight
// (a rigid body in free flight: COM on the parabola, constant angular velocity about a principal
// axis) and lands. In contact the bed acts as a linear spring of stiffness k, so the COM follows
// a harmonic arc about its static equilibrium (ω² = k / m). A load-cell channel records the bed
// force m (g + z̈), zero in flight. Markers carry 0.5 mm Gaussian noise (fixed seed) and one marker
// has a 12-frame occlusion, so gap reporting has something to show.
//
// usage: make_sample_trial OUT.c3d
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <random>
#include <string>
#include <vector>

#include <Eigen/Geometry>

#include "acro/base/input_error.h"
#include "acro/capture/c3d.h"

namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr double kG = 9.81;

struct Marker {
  const char* label;
  const char* description;
  Eigen::Vector3d
      p_BcmM_B;  // marker position from the body's COM, in body frame B (x forward, z head)
};

// A straight body 1.75 m tall, COM 0.97 m above the soles (de Leva-like proportions).
const std::vector<Marker>& Markers() {
  static const std::vector<Marker> markers = {
      {"HEAD", "top of head", {0.00, 0.00, 0.78}},
      {"C7", "7th cervical vertebra", {-0.06, 0.00, 0.49}},
      {"STRN", "sternum", {0.10, 0.00, 0.35}},
      {"LSHO", "left acromion", {0.00, 0.19, 0.46}},
      {"RSHO", "right acromion", {0.00, -0.19, 0.46}},
      {"LWRI", "left wrist", {0.00, 0.23, 0.02}},
      {"RWRI", "right wrist", {0.00, -0.23, 0.02}},
      {"LASI", "left anterior superior iliac spine", {0.09, 0.12, 0.06}},
      {"RASI", "right anterior superior iliac spine", {0.09, -0.12, 0.06}},
      {"SACR", "sacrum", {-0.10, 0.00, 0.04}},
      {"LKNE", "left lateral knee", {0.00, 0.11, -0.46}},
      {"RKNE", "right lateral knee", {0.00, -0.11, -0.46}},
      {"LANK", "left lateral malleolus", {-0.02, 0.10, -0.90}},
      {"RANK", "right lateral malleolus", {-0.02, -0.10, -0.90}},
      {"LTOE", "left second metatarsal head", {0.14, 0.06, -0.95}},
      {"RTOE", "right second metatarsal head", {0.14, -0.06, -0.95}},
  };
  return markers;
}

}  // namespace

namespace {

// The athlete's bounce: on the bed a spring (z(t) = z_eq + B cos θ, θ = θ0 + ω t, about the static
// equilibrium z_eq = z_rest − m g / k; touch-down at z = z_rest, ż = −v0, at θ0 = atan2(v0 / ω,
// m g / k), take-off at 2π − θ0), in the air a parabola, turning a back somersault.
struct Bounce {
  double mass_kg = 65.0;
  double bed_stiffness_N_per_m = 5000.0;  // effective vertical stiffness of a competition bed
  double v0_m_per_s = 7.0;                // take-off vertical velocity: flight 2 v0 / g ≈ 1.43 s
  double z_com_rest_m = 0.97;             // COM height standing on the unloaded bed (bed at z = 0)
  double horizontal_m_per_s = 0.15;       // drift towards +x
  double omega = std::sqrt(bed_stiffness_N_per_m / mass_kg);
  double sag_m = mass_kg * kG / bed_stiffness_N_per_m;
  double amplitude_m = std::hypot(sag_m, v0_m_per_s / omega);
  double theta0 = std::atan2(v0_m_per_s / omega, sag_m);
  double contact_s = (2 * kPi - 2 * theta0) / omega;
  double flight_s = 2 * v0_m_per_s / kG;
  // A back somersault (negative rotation about +y): 0.92 of a turn in the air, the rest happens
  // on the bed.
  double somersault_rad_per_s = -2 * kPi * 0.92 / flight_s;

  // COM height, vertical acceleration, horizontal position and somersault angle at time t: contact,
  // flight, contact (landing).
  void State(double t, double* z, double* zdd, double* x, double* angle) const {
    const double z_eq = z_com_rest_m - sag_m;
    const double t_landing = contact_s + flight_s;
    if (t < contact_s || t >= t_landing) {  // on the bed: push-off, then the landing
      const double tau = t < contact_s ? t : t - t_landing;
      const double theta = theta0 + omega * tau;
      *z = z_eq + amplitude_m * std::cos(theta);
      *zdd = -amplitude_m * omega * omega * std::cos(theta);
      *x = t < contact_s ? 0.0 : horizontal_m_per_s * flight_s;
      *angle = t < contact_s ? 0.0 : somersault_rad_per_s * flight_s;
    } else {  // flight
      const double tau = t - contact_s;
      *z = z_com_rest_m + v0_m_per_s * tau - 0.5 * kG * tau * tau;
      *zdd = -kG;
      *x = horizontal_m_per_s * tau;
      *angle = somersault_rad_per_s * tau;
    }
  }
};

// The trial's header: the markers, a 2 kHz bed load cell, `frames` frames at `rate_hz`.
acro::capture::Trial EmptyTrial(int frames, double rate_hz, int analog_per_frame) {
  acro::capture::Trial trial;
  trial.source.point_units = "mm";
  trial.point_rate_hz = rate_hz;
  trial.first_frame = 1;
  trial.num_frames = frames;
  trial.subject_name = "Sample Athlete";
  for (const Marker& m : Markers()) {
    trial.points.push_back({m.label, m.description, acro::capture::PointType::kMarker, "m"});
  }
  const int num_markers = trial.num_points();
  trial.positions.resize(3, std::int64_t(frames) * num_markers);
  trial.residuals.setConstant(num_markers, frames, 0.5f);
  trial.camera_masks.setConstant(num_markers, frames, 0x0F);
  trial.analog_rate_hz = rate_hz * analog_per_frame;
  trial.analog_channels.push_back({"BedFz", "trampoline bed vertical load", "N", 1.0, 0.0, 0.0});
  trial.analog.resize(1, std::int64_t(frames) * analog_per_frame);
  return trial;
}

// Every frame's markers (the rigid body at the COM, turned by the somersault, 0.5 mm of noise)
// and the bed's load (m (g + z̈) while compressed, zero in flight).
void FillFrames(const Bounce& b, int analog_per_frame, acro::capture::Trial* trial) {
  std::mt19937 rng(20261122);
  std::normal_distribution<double> noise(0.0, 0.0005);
  const int num_markers = trial->num_points();
  for (int f = 0; f < trial->num_frames; ++f) {
    const double t = f / trial->point_rate_hz;
    double z, zdd, x, angle;
    b.State(t, &z, &zdd, &x, &angle);
    const Eigen::Matrix3d R_WB =
        Eigen::AngleAxisd(angle, Eigen::Vector3d::UnitY()).toRotationMatrix();
    const Eigen::Vector3d p_WoBcm_W(x, 0.0, z);
    for (int m = 0; m < num_markers; ++m) {
      Eigen::Vector3d p = p_WoBcm_W + R_WB * Markers()[m].p_BcmM_B;
      p += Eigen::Vector3d(noise(rng), noise(rng), noise(rng));
      trial->position(f, m) = p;
    }
    for (int s = 0; s < analog_per_frame; ++s) {
      double zs, zdds, xs, as;
      b.State(t + s / trial->analog_rate_hz, &zs, &zdds, &xs, &as);
      trial->analog(0, std::int64_t(f) * analog_per_frame + s) =
          std::max(0.0, b.mass_kg * (kG + zdds));
    }
  }
}

}  // namespace

int main(int argc, char** argv) {
  if (argc != 2) {
    std::fprintf(stderr, "usage: make_sample_trial OUT.c3d\n");
    return 2;
  }
  const Bounce b;
  // Time line: contact, flight, contact (landing), at 200 Hz.
  const double rate_hz = 200.0;
  const double total_s = b.contact_s + b.flight_s + b.contact_s;
  const int frames = static_cast<int>(std::floor(total_s * rate_hz)) + 1;
  const int analog_per_frame = 10;  // 2 kHz load cell
  acro::capture::Trial trial = EmptyTrial(frames, rate_hz, analog_per_frame);
  FillFrames(b, analog_per_frame, &trial);
  // One occlusion: the right wrist is hidden for 12 frames at the top of the flight.
  const int right_wrist = 6;
  const int apex = static_cast<int>((b.contact_s + b.flight_s / 2) * rate_hz);
  for (int f = apex; f < apex + 12; ++f) {
    trial.position(f, right_wrist).setConstant(std::nan(""));
    trial.residuals(right_wrist, f) = -1.0f;
  }
  // Events where the athlete leaves and touches the bed.
  trial.events.push_back(
      {"Take-off", "General", "athlete leaves the bed", "Sample Athlete", b.contact_s, true, 0, 0});
  trial.events.push_back({"Landing",
                          "General",
                          "athlete touches the bed",
                          "Sample Athlete",
                          b.contact_s + b.flight_s,
                          true,
                          0,
                          0});

  try {
    acro::capture::WriteC3d(trial, argv[1]);
  } catch (const acro::InputError& e) {
    std::fprintf(stderr, "make_sample_trial: %s\n", e.what());
    return 1;
  }
  std::printf("wrote %s: %d frames at %g Hz, %d markers, flight %.3f s, contact %.3f s\n",
              argv[1],
              frames,
              rate_hz,
              trial.num_points(),
              b.flight_s,
              b.contact_s);
  return 0;
}
