#pragma once

#include <cstddef>
#include <functional>
#include <string>
#include <vector>

#include "acro/athlete/athlete_body.h"
#include "acro/reconstruct/reconstruction.h"

namespace acro::app {

/// Each command parses its own arguments, calls library functions and prints. It returns the exit
/// status; bad input surfaces as acro::InputError, which main() prints as one line.
int RunInfo(const std::vector<std::string>& args);
int RunConvert(const std::vector<std::string>& args);
int RunBody(const std::vector<std::string>& args);
int RunReconstruct(const std::vector<std::string>& args);
int RunOptimize(const std::vector<std::string>& args);
int RunAnalyze(const std::vector<std::string>& args);

/// Thrown for a bad command line: main() prints it with the usage hint and exits with status 2.
struct UsageError {
  std::string message;
};

/// The value that follows option args[*i] (advancing *i), or UsageError "<option> needs a value".
const std::string& OptionValue(const std::vector<std::string>& args, std::size_t* i);

/// `text` as a number, or UsageError "<option> needs a number, got '<text>'".
double OptionNumber(const std::string& option, const std::string& text);

/// What every command that reconstructs a trial takes: TRIAL, --static, --athlete or
/// --height/--mass/--sex, --markerset, -o, --cutoff, --no-scale, --threads, --quiet.
struct TrialArguments {
  std::string trial_path, static_path, athlete_path, markerset, out_dir, sex = "f";
  double height_m = 1.75, mass_kg = 65.0;
  bool have_body_numbers = false, quiet = false;
  /// Takes args[*i] (and its value, advancing *i) when it is one of these options or the TRIAL;
  /// true when taken. Options of the reconstruction go into `options`.
  bool Take(const std::vector<std::string>& args,
            std::size_t* i,
            analysis::ReconstructionOptions* options);
  /// UsageError for a missing TRIAL or -o, or contradictory athlete options.
  void Check() const;
  /// The athlete profile's body, or a de Leva body of the given numbers with a warning on stderr
  /// naming `command`; `athlete_name` (when given) gets the profile's name or a description.
  analysis::AthleteBody MakeBody(const std::string& command,
                                 std::string* athlete_name = nullptr) const;
};

/// Inverse-kinematics progress on stderr: a bar redrawn in place on a terminal, one line at the end
/// otherwise (logs, pipes).
std::function<void(int, int)> MakeFrameProgress();

}  // namespace acro::app
