#include <cstdio>
#include <memory>
#include <optional>

#include "acro/athlete/athlete_profile.h"
#include "acro/athlete/body_mesh.h"
#include "acro/report/body_report.h"
#include "acro/athlete/yaml.h"
#include "commands.h"

namespace acro::app {

namespace {

constexpr const char* kBodyHelp =
    "usage: acrolab body (--measurements FILE | --profile FILE | --height M --mass KG --sex f|m)\n"
    "                    [--density dempster|chandler|clauser] [--pose SPEC] [--json] [--mesh "
    "OUT.obj|OUT.ply]\n"
    "\n"
    "Prints the athlete's 15 segments and whole body: mass, centre of mass and inertia about the\n"
    "centre of mass, and the somersault-axis inertia of the straight, piked and tucked shapes.\n"
    "  --measurements FILE  Yeadon (1990) geometric model from a yeadon measurement file\n"
    "                       (--mass, if given, scales its densities to that mass)\n"
    "  --profile FILE       an athlete profile (docs/formats/athlete.md)\n"
    "  --height/--mass/--sex  de Leva (1996) regression\n"
    "  --pose SPEC          straight | pike | tuck and/or NAME=DEG, comma-separated, e.g.\n"
    "                       'tuck,knee_flexion=120' (names: docs/athlete-model.md)\n"
    "  --mesh OUT           writes the (posed) body mesh as OBJ or PLY\n"
    "  --yeadon-package     reproduce the yeadon package's numbers (its cone centroids and\n"
    "                       long-axis stadium inertia; see docs/athlete-model.md)\n";

}  // namespace

int RunBody(const std::vector<std::string>& args) {
  // Arguments.
  std::string measurements, profile_path, sex, density, pose_spec, mesh_path;
  std::optional<double> height, mass;
  bool json = false;
  bool yeadon_package = false;
  for (size_t i = 0; i < args.size(); ++i) {
    const std::string& arg = args[i];
    auto value = [&]() -> const std::string& { return OptionValue(args, &i); };
    if (arg == "--help" || arg == "-h") {
      std::fputs(kBodyHelp, stdout);
      return 0;
    } else if (arg == "--json") {
      json = true;
    } else if (arg == "--yeadon-package") {
      yeadon_package = true;
    } else if (arg == "--measurements") {
      measurements = value();
    } else if (arg == "--profile") {
      profile_path = value();
    } else if (arg == "--height") {
      height = OptionNumber(arg, value());
    } else if (arg == "--mass") {
      mass = OptionNumber(arg, value());
    } else if (arg == "--sex") {
      sex = value();
    } else if (arg == "--density") {
      density = value();
    } else if (arg == "--pose") {
      pose_spec = value();
    } else if (arg == "--mesh") {
      mesh_path = value();
    } else {
      throw UsageError{"unknown argument '" + arg + "'"};
    }
  }
  const int sources = !measurements.empty() + !profile_path.empty() + (height || !sex.empty());
  if (sources != 1)
    throw UsageError{"give one of --measurements FILE, --profile FILE, or --height/--mass/--sex"};

  // The athlete's body in the reference pose: Yeadon's model or de Leva's regression.
  std::unique_ptr<analysis::YeadonHuman> human;
  analysis::AthleteBody rest;
  analysis::YeadonOptions yeadon_options;
  if (!density.empty() && !analysis::ParseDensitySet(density, &yeadon_options.density))
    throw UsageError{"--density must be dempster, chandler or clauser, got '" + density + "'"};
  yeadon_options.package_compatible = yeadon_package;
  if (!measurements.empty()) {
    analysis::YeadonMeasurements meas = analysis::ReadYeadonMeasurements(measurements);
    if (mass) meas.total_mass_kg = *mass;
    human =
        std::make_unique<analysis::YeadonHuman>(analysis::YeadonHuman::Make(meas, yeadon_options));
  } else if (!profile_path.empty()) {
    analysis::AthleteProfile profile = analysis::ReadAthleteProfile(profile_path);
    if (profile.yeadon_measurements) {
      if (!density.empty()) profile.yeadon_options.density = yeadon_options.density;
      profile.yeadon_options.package_compatible = yeadon_package;
      analysis::YeadonMeasurements meas = *profile.yeadon_measurements;
      meas.total_mass_kg = profile.mass_kg;
      human = std::make_unique<analysis::YeadonHuman>(
          analysis::YeadonHuman::Make(meas, profile.yeadon_options));
    } else {
      rest = analysis::MakeAthleteBody(profile);
    }
  } else {
    if (!height || !mass || sex.empty()) throw UsageError{"--height, --mass and --sex go together"};
    if (sex != "f" && sex != "m") throw UsageError{"--sex must be f or m, got '" + sex + "'"};
    if (!density.empty() || yeadon_package)
      throw UsageError{"--density and --yeadon-package apply to Yeadon measurements only"};
    rest = analysis::MakeDeLevaBody(
        *height, *mass, sex == "f" ? analysis::Sex::kFemale : analysis::Sex::kMale);
  }
  if (human) rest = analysis::MakeAthleteBodyFromYeadon(*human);

  // Pose, shapes, report.
  const analysis::AthleteBody posed = analysis::PoseAthleteBody(
      rest, analysis::ParseBodyPose(pose_spec.empty() ? "straight" : pose_spec));
  const analysis::ShapeInertias shapes = analysis::CalcShapeInertias(rest, posed);
  const std::string report = json ? ui::FormatBodyReportJson(posed, shapes, pose_spec)
                                  : ui::FormatBodyReportText(posed, shapes, pose_spec);
  std::fputs(report.c_str(), stdout);

  // Mesh: Yeadon's solids, or inertia-equivalent ellipsoids for de Leva; skinned to the pose.
  if (!mesh_path.empty()) {
    analysis::BodyMeshOptions display;  // ellipsoids are for display: a lighter tessellation
    display.points_per_semicircle = 16;
    display.ellipsoid_bands = 8;
    analysis::BodyMesh mesh = human ? analysis::MakeBodyMesh(*human, rest)
                                    : analysis::MakeEllipsoidBodyMesh(rest, display);
    mesh.vertices_H = analysis::CalcSkinnedVertices(mesh, rest, posed);
    analysis::WriteBodyMesh(mesh, mesh_path);
    std::fprintf(stderr,
                 "acrolab body: wrote %s (%d vertices, %d triangles)\n",
                 mesh_path.c_str(),
                 mesh.num_vertices(),
                 mesh.num_triangles());
  }
  return 0;
}

}  // namespace acro::app
