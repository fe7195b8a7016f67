// Argument helpers shared by the commands.
#include "acro/analysis/yaml.h"
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

}  // namespace acro::app
