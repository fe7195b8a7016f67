#include "acro/library/designs.h"

#include <nlohmann/json.hpp>

#include "acro/base/file_io.h"
#include "acro/base/input_error.h"
#include "acro/fig/skill.h"
#include "json_text.h"

namespace acro::library {

namespace {

std::string ReadSmallText(const std::filesystem::path& path) {
  const std::vector<std::uint8_t> bytes = ReadFileBytes(path, std::int64_t(64) << 20);
  return std::string(bytes.begin(), bytes.end());
}

}  // namespace

std::int64_t StoreSkillDesign(Library& library,
                              const std::filesystem::path& skill_file,
                              const analysis::Skill& skill,
                              const std::filesystem::path& output_dir) {
  double difficulty = 0.0;
  if (!skill.fig_code.empty())
    difficulty = fig::CalcFigDifficulty(fig::ParseFigCode(skill.fig_code)).total();
  const std::filesystem::path result = output_dir / "result.json";
  nlohmann::json content;
  content["skill_file"] = std::filesystem::absolute(skill_file).lexically_normal().string();
  content["skill_yaml"] = ReadSmallText(skill_file);
  content["output_dir"] = std::filesystem::absolute(output_dir).lexically_normal().string();
  content["result"] = internal::ParseJsonText(ReadSmallText(result), result.string());
  return library.StoreDesign(
      skill.athlete.name, "skill", skill.name, skill.fig_code, difficulty, content.dump(1));
}

}  // namespace acro::library
