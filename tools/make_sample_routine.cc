// Makes samples/trials/trampoline_routine/: trampoline_routine.c3d, a routine of six skills
// simulated by the project's own dynamics engine for the sample athlete, and truth.json, its
// ground truth (tools/sample_routine.h says how it is made).
//
// usage: make_sample_routine ATHLETE.yaml OUT_DIR
// (from the repository root: build/bin/make_sample_routine samples/athletes/sample_athlete.yaml
//  samples/trials/trampoline_routine)
#include <cstdio>
#include <filesystem>
#include <string>

#include "acro/base/file_io.h"
#include "acro/base/input_error.h"
#include "acro/capture/c3d.h"
#include "sample_routine.h"

int main(int argc, char** argv) {
  if (argc != 3) {
    std::fprintf(stderr, "usage: make_sample_routine ATHLETE.yaml OUT_DIR\n");
    return 2;
  }
  const std::filesystem::path athlete = argv[1];
  const std::filesystem::path dir = argv[2];
  try {
    // The athlete as truth.json names it: relative to the repository (samples/athletes/…).
    const std::string label = "samples/athletes/" + athlete.filename().string();
    const acro::samples::SampleRoutine routine = acro::samples::MakeSampleRoutine(athlete, label);
    std::filesystem::create_directories(dir);
    const std::vector<std::uint8_t> c3d = acro::capture::WriteC3dToMemory(routine.trial);
    acro::WriteFileAtomically(
        dir / "trampoline_routine.c3d",
        std::string_view(reinterpret_cast<const char*>(c3d.data()), c3d.size()));
    acro::WriteFileAtomically(dir / "truth.json", routine.TruthJson());
    std::printf("wrote %s: %d frames at %g Hz, %d points, %zu bytes\n",
                (dir / "trampoline_routine.c3d").string().c_str(),
                routine.trial.num_frames,
                routine.trial.point_rate_hz,
                routine.trial.num_points(),
                c3d.size());
    for (size_t i = 0; i < routine.flights.size(); ++i) {
      const auto& f = routine.flights[i];
      const auto check = acro::samples::CheckSampleFlight(routine, static_cast<int>(i));
      std::printf(
          "  %-5s %-28s take-off %7.4f s  landing %7.4f s  ToF %.4f s  apex %.3f m  "
          "air somersault %7.1f deg  twist %6.1f deg  |H| %6.2f N m s  drift %.1e  g_fit %.9f\n",
          f.fig_code.c_str(),
          f.name.c_str(),
          f.takeoff_s,
          f.landing_s,
          f.landing_s - f.takeoff_s,
          f.apex_com_z_m,
          f.air_somersault_rad * 180 / 3.14159265358979323846,
          f.air_twist_rad * 180 / 3.14159265358979323846,
          check.momentum_norm_N_m_s,
          check.max_relative_momentum_drift,
          -check.fitted_vertical_acceleration_m_per_s2);
    }
    for (const auto& c : routine.contacts)
      std::printf("  contact %7.4f–%7.4f s (%.3f s): peak %.2f body weights, depression %.3f m\n",
                  c.start_s,
                  c.end_s,
                  c.end_s - c.start_s,
                  c.peak_force_body_weights,
                  c.max_depression_m);
    std::printf(
        "  C1 at take-offs and landings: COM %.1e m, %.1e m/s; orientation %.1e rad, %.1e rad/s; "
        "joints %.1e rad, %.1e rad/s\n",
        routine.max_boundary_position_jump_m,
        routine.max_boundary_velocity_jump_m_per_s,
        routine.max_boundary_orientation_jump_rad,
        routine.max_boundary_angular_velocity_jump_rad_per_s,
        routine.max_boundary_joint_jump_rad,
        routine.max_boundary_joint_rate_jump_rad_per_s);
  } catch (const acro::InputError& e) {
    std::fprintf(stderr, "make_sample_routine: %s\n", e.what());
    return 1;
  }
  return 0;
}
