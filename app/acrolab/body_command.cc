#include <cstdio>
#include <memory>
#include <optional>

#include "acro/athlete/athlete_profile.h"
#include "acro/athlete/body_mesh.h"
#include "acro/base/text.h"
#include "acro/report/body_report.h"
#include "commands.h"

namespace acro::app {

namespace {

struct BodyArguments {
  std::string measurements, profile_path, sex, density, pose_spec, mesh_path;
  std::optional<double> height, mass;
  bool json = false;
  bool yeadon_package = false;
};

int RunBody(const BodyArguments& args) {
  const int sources =
      !args.measurements.empty() + !args.profile_path.empty() + (args.height || !args.sex.empty());
  if (sources != 1)
    throw UsageError{"give one of --measurements FILE, --profile FILE, or --height/--mass/--sex"};

  // The athlete's body in the reference pose: Yeadon's model or de Leva's regression.
  std::unique_ptr<analysis::YeadonHuman> human;
  analysis::AthleteBody rest;
  analysis::YeadonOptions yeadon_options;
  if (!args.density.empty()) analysis::ParseDensitySet(args.density, &yeadon_options.density);
  yeadon_options.package_compatible = args.yeadon_package;
  if (!args.measurements.empty()) {
    analysis::YeadonMeasurements meas = analysis::ReadYeadonMeasurements(args.measurements);
    if (args.mass) meas.total_mass_kg = *args.mass;
    human =
        std::make_unique<analysis::YeadonHuman>(analysis::YeadonHuman::Make(meas, yeadon_options));
  } else if (!args.profile_path.empty()) {
    analysis::AthleteProfile profile = analysis::ReadAthleteProfile(args.profile_path);
    if (profile.yeadon_measurements) {
      if (!args.density.empty()) profile.yeadon_options.density = yeadon_options.density;
      profile.yeadon_options.package_compatible = args.yeadon_package;
      analysis::YeadonMeasurements meas = *profile.yeadon_measurements;
      meas.total_mass_kg = profile.mass_kg;
      human = std::make_unique<analysis::YeadonHuman>(
          analysis::YeadonHuman::Make(meas, profile.yeadon_options));
    } else {
      rest = analysis::MakeAthleteBody(profile);
    }
  } else {
    if (!args.height || !args.mass || args.sex.empty())
      throw UsageError{"--height, --mass and --sex go together"};
    if (!args.density.empty() || args.yeadon_package)
      throw UsageError{"--density and --yeadon-package apply to Yeadon measurements only"};
    rest = analysis::MakeDeLevaBody(
        *args.height, *args.mass, args.sex == "f" ? analysis::Sex::kFemale : analysis::Sex::kMale);
  }
  if (human) rest = analysis::MakeAthleteBodyFromYeadon(*human);

  // Pose, shapes, report.
  const analysis::AthleteBody posed = analysis::PoseAthleteBody(
      rest, analysis::ParseBodyPose(args.pose_spec.empty() ? "straight" : args.pose_spec));
  const analysis::ShapeInertias shapes = analysis::CalcShapeInertias(rest, posed);
  const std::string report = args.json ? ui::FormatBodyReportJson(posed, shapes, args.pose_spec)
                                       : ui::FormatBodyReportText(posed, shapes, args.pose_spec);
  std::fputs(report.c_str(), stdout);

  // Mesh: Yeadon's solids, or inertia-equivalent ellipsoids for de Leva; skinned to the pose.
  if (!args.mesh_path.empty()) {
    analysis::BodyMeshOptions display;  // ellipsoids are for display: a lighter tessellation
    display.points_per_semicircle = 16;
    display.ellipsoid_bands = 8;
    analysis::BodyMesh mesh = human ? analysis::MakeBodyMesh(*human, rest)
                                    : analysis::MakeEllipsoidBodyMesh(rest, display);
    mesh.vertices_H = analysis::CalcSkinnedVertices(mesh, rest, posed);
    analysis::WriteBodyMesh(mesh, args.mesh_path);
    std::fprintf(stderr,
                 "acrolab body: wrote %s (%d vertices, %d triangles)\n",
                 EscapeForTerminal(args.mesh_path).c_str(),
                 mesh.num_vertices(),
                 mesh.num_triangles());
  }
  return 0;
}

}  // namespace

void AddBodyCommand(CLI::App& app, CommandRunner* run) {
  auto args = std::make_shared<BodyArguments>();
  CLI::App* command = app.add_subcommand(
      "body",
      "The athlete's 15 segments and whole body: mass, centre of mass and inertia about the centre "
      "of mass, and the somersault-axis inertia of the straight, piked and tucked shapes. Give "
      "one of --measurements, --profile, or --height/--mass/--sex.");
  command->add_option("--measurements",
                      args->measurements,
                      "Yeadon (1990) geometric model from a yeadon measurement file (--mass, if "
                      "given, scales its densities to that mass)");
  command->add_option(
      "--profile", args->profile_path, "an athlete profile (docs/formats/athlete.md)");
  command->add_option("--height", args->height, "de Leva (1996) regression: stature (m)")
      ->check(CLI::Range(0.5, 2.6));
  command->add_option("--mass", args->mass, "body mass (kg)")->check(CLI::Range(10.0, 300.0));
  command->add_option("--sex", args->sex, "f or m (de Leva's tables)")
      ->check(CLI::IsMember({"f", "m"}));
  command->add_option("--density", args->density, "Yeadon's density set")
      ->check(CLI::IsMember({"dempster", "chandler", "clauser"}));
  command->add_option("--pose",
                      args->pose_spec,
                      "straight | pike | tuck and/or NAME=DEG, comma-separated, e.g. "
                      "'tuck,knee_flexion=120' (names: docs/athlete-model.md)");
  command->add_flag("--json", args->json, "print one JSON object (docs/cli.md)");
  command->add_option("--mesh", args->mesh_path, "write the (posed) body mesh as OBJ or PLY");
  command->add_flag("--yeadon-package",
                    args->yeadon_package,
                    "reproduce the yeadon package's numbers (its cone centroids and long-axis "
                    "stadium inertia; docs/athlete-model.md)");
  command->callback([args, run] { *run = [args] { return RunBody(*args); }; });
}

}  // namespace acro::app
