// Argument helpers shared by the commands.
#include <unistd.h>

#include <cstdio>

#include "acro/athlete/athlete_profile.h"
#include "acro/athlete/de_leva.h"
#include "acro/athlete/yaml.h"
#include "commands.h"

namespace acro::app {

const std::string& OptionValue(const std::vector<std::string>& args, std::size_t* i) {
  if (*i + 1 >= args.size()) throw UsageError{args[*i] + " needs a value"};
  return args[++*i];
}

double OptionNumber(const std::string& option, const std::string& text) {
  double value = 0.0;
  if (!analysis::ParseYamlNumber(text, &value))
    throw UsageError{option + " needs a number, got '" + text + "'"};
  return value;
}

bool TrialArguments::Take(const std::vector<std::string>& args,
                          std::size_t* i,
                          analysis::ReconstructionOptions* options) {
  const std::string& arg = args[*i];
  auto value = [&]() -> const std::string& { return OptionValue(args, i); };
  if (arg == "--static") {
    static_path = value();
  } else if (arg == "--athlete") {
    athlete_path = value();
  } else if (arg == "--markerset") {
    markerset = value();
    options->markerset = markerset;
  } else if (arg == "-o" || arg == "--output") {
    out_dir = value();
  } else if (arg == "--height" || arg == "--mass") {
    (arg == "--height" ? height_m : mass_kg) = OptionNumber(arg, value());
    have_body_numbers = true;
  } else if (arg == "--sex") {
    sex = value();
    have_body_numbers = true;
  } else if (arg == "--cutoff") {
    options->cutoff_hz = OptionNumber(arg, value());
    if (options->cutoff_hz < 0) throw UsageError{"--cutoff must be >= 0"};
    options->filter = options->cutoff_hz > 0;
  } else if (arg == "--no-scale") {
    options->scale = false;
  } else if (arg == "--threads") {
    options->num_threads = static_cast<int>(OptionNumber(arg, value()));
  } else if (arg == "--quiet") {
    quiet = true;
  } else if (!arg.empty() && arg[0] == '-') {
    return false;
  } else if (trial_path.empty()) {
    trial_path = arg;
  } else {
    throw UsageError{"one TRIAL only, got '" + trial_path + "' and '" + arg + "'"};
  }
  return true;
}

void TrialArguments::Check() const {
  if (trial_path.empty()) throw UsageError{"missing TRIAL"};
  if (out_dir.empty()) throw UsageError{"missing -o DIR"};
  if (sex != "f" && sex != "m") throw UsageError{"--sex must be f or m, got '" + sex + "'"};
  if (!athlete_path.empty() && have_body_numbers)
    throw UsageError{"--athlete and --height/--mass/--sex exclude each other"};
}

analysis::AthleteBody TrialArguments::MakeBody(const std::string& command,
                                               std::string* athlete_name) const {
  if (!athlete_path.empty()) {
    const analysis::AthleteProfile profile = analysis::ReadAthleteProfile(athlete_path);
    analysis::AthleteBody body = analysis::MakeAthleteBody(profile);
    if (athlete_name) *athlete_name = profile.name + ", " + body.model;
    return body;
  }
  if (athlete_name) *athlete_name = "default de Leva athlete (no --athlete file)";
  std::fprintf(stderr,
               "acrolab %s: warning: no --athlete file; using a de Leva athlete of %.2f m, %.1f "
               "kg, sex %s (segment masses and inertias will be generic)\n",
               command.c_str(),
               height_m,
               mass_kg,
               sex.c_str());
  return analysis::MakeDeLevaBody(
      height_m, mass_kg, sex == "f" ? analysis::Sex::kFemale : analysis::Sex::kMale);
}

std::function<void(int, int)> MakeFrameProgress() {
  const bool tty = isatty(fileno(stderr)) != 0;
  return [tty](int done, int total) {
    if (!tty && done < total) return;
    const int width = 40;
    const int filled = total > 0 ? done * width / total : width;
    std::fprintf(stderr,
                 "\rinverse kinematics [%s%s] %3d%% (%d/%d frames)",
                 std::string(size_t(filled), '#').c_str(),
                 std::string(size_t(width - filled), ' ').c_str(),
                 total > 0 ? done * 100 / total : 100,
                 done,
                 total);
    if (done >= total) std::fputc('\n', stderr);
    std::fflush(stderr);
  };
}

}  // namespace acro::app
