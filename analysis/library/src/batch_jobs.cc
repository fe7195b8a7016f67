#include "acro/library/batch_jobs.h"

#include <algorithm>
#include <fstream>
#include <sstream>

#include <fmt/format.h>

#include "acro/base/file_io.h"
#include "acro/base/input_error.h"
#include "acro/library/library.h"

namespace acro::library {

std::vector<std::string> SplitJobWords(const std::string& line, const std::string& where) {
  std::vector<std::string> words;
  std::string word;
  bool in_word = false;
  char quote = 0;
  for (size_t i = 0; i < line.size(); ++i) {
    const char c = line[i];
    if (quote) {
      if (c == quote) {
        quote = 0;
      } else if (c == '\\' && quote == '"' && i + 1 < line.size()) {
        word += line[++i];
      } else {
        word += c;
      }
    } else if (c == '\'' || c == '"') {
      quote = c;
      in_word = true;
    } else if (c == '\\' && i + 1 < line.size()) {
      word += line[++i];
      in_word = true;
    } else if (c == ' ' || c == '\t') {
      if (in_word) words.push_back(word);
      word.clear();
      in_word = false;
    } else if (c == '#' && !in_word) {
      break;
    } else {
      word += c;
      in_word = true;
    }
  }
  if (quote) throw InputError(where, "", "a quote is not closed");
  if (in_word) words.push_back(word);
  return words;
}

std::string ShellQuote(const std::string& word) {
  if (!word.empty() && word.find_first_not_of("abcdefghijklmnopqrstuvwxyzABCDEFGHIJKLMNOPQRSTUVWXYZ"
                                              "0123456789-_./=:,+@%") == std::string::npos)
    return word;
  std::string q = "'";
  for (char c : word) q += c == '\'' ? std::string("'\\''") : std::string(1, c);
  return q + "'";
}

std::string OptionValue(const std::vector<std::string>& words, const std::string& option) {
  for (size_t i = 1; i + 1 < words.size(); ++i)
    if (words[i] == option) return words[i + 1];
  return {};
}

std::vector<BatchJob> ReadBatchJobs(const std::filesystem::path& source,
                                    const BatchDefaults& defaults) {
  std::vector<BatchJob> jobs;
  std::error_code ec;
  if (std::filesystem::is_directory(source, ec)) {
    // Every C3D and TRC under DIR, in name order.
    std::vector<std::filesystem::path> files;
    for (const auto& entry : std::filesystem::recursive_directory_iterator(source)) {
      const std::string ext = LowerExtension(entry.path());
      if (entry.is_regular_file() && (ext == "c3d" || ext == "trc")) files.push_back(entry.path());
    }
    std::sort(files.begin(), files.end());
    for (const auto& f : files) {
      BatchJob j;
      j.where = f.string();
      j.words = {std::filesystem::absolute(f).lexically_normal().string()};
      jobs.push_back(j);
    }
  } else {
    // Through the one file reader: a pipe or a device is refused before it can block, and a job
    // list is text of at most 16 MB (a season's 100 000 trials at 160 bytes a line).
    if (!std::filesystem::exists(source, ec) && !ec)
      throw InputError(source.string(), "", "neither a directory nor a readable job list");
    const std::vector<std::uint8_t> bytes = ReadFileBytes(source, std::int64_t(16) << 20);
    std::istringstream in(std::string(bytes.begin(), bytes.end()));
    std::string line;
    int number = 0;
    while (std::getline(in, line)) {
      ++number;
      if (!line.empty() && line.back() == '\r') line.pop_back();  // a list written on Windows
      const std::string where = fmt::format("{}: line {}", source.string(), number);
      std::vector<std::string> words = SplitJobWords(line, where);
      if (words.empty()) continue;
      // A relative trial path is relative to the list's folder.
      std::filesystem::path trial = words[0];
      if (trial.is_relative()) trial = source.parent_path() / trial;
      words[0] = std::filesystem::absolute(trial).lexically_normal().string();
      for (size_t i = 1; i < words.size(); ++i) {
        static const std::vector<std::string> kTakes = {
            "--athlete", "--session", "--place", "--notes", "--video", "--calib"};
        if (std::find(kTakes.begin(), kTakes.end(), words[i]) == kTakes.end() ||
            i + 1 == words.size())
          throw InputError(where,
                           "",
                           "'" + words[i] +
                               "' is not one of --athlete, --session, --place, --notes, "
                               "--video, --calib with its value");
        if (words[i] == "--session" && !IsSessionDate(words[i + 1]))
          throw InputError(where, "", "--session '" + words[i + 1] + "' is not YYYY-MM-DD");
        if (words[i] != "--session" && words[i] != "--place" && words[i] != "--notes") {
          std::filesystem::path file = words[i + 1];
          if (file.is_relative())
            words[i + 1] = (source.parent_path() / file).lexically_normal().string();
        }
        ++i;
      }
      BatchJob j;
      j.where = where;
      j.words = words;
      jobs.push_back(j);
    }
  }
  for (size_t k = 0; k < jobs.size(); ++k) {
    BatchJob& j = jobs[k];
    j.number = int(k + 1);
    if (OptionValue(j.words, "--athlete").empty()) {
      if (defaults.athlete.empty())
        throw InputError(
            j.where, "", "no --athlete for this trial (give one to batch, or on the line)");
      j.words.insert(j.words.end(), {"--athlete", defaults.athlete});
    }
    if (OptionValue(j.words, "--session").empty() && !defaults.session.empty())
      j.words.insert(j.words.end(), {"--session", defaults.session});
    j.request.trial = j.words[0];
    j.request.athlete_profile = OptionValue(j.words, "--athlete");
    if (!defaults.analyses.empty())
      j.request.analysis_dir =
          std::filesystem::path(defaults.analyses) / fmt::format("job-{}", j.number);
  }
  return jobs;
}

}  // namespace acro::library
