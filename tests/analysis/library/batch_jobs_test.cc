// acrolab batch's job lists (acro/library/batch_jobs.h): the shell-like words, paths relative to
// the list, the batch's defaults, and one line naming what is wrong.

#include "acro/library/batch_jobs.h"

#include <filesystem>
#include <fstream>
#include <string>

#include <gtest/gtest.h>

#include "acro/base/input_error.h"
#include "refdata.h"

namespace acro::library {
namespace {

namespace fs = std::filesystem;

fs::path WriteList(const fs::path& dir, const std::string& text) {
  const fs::path list = dir / "jobs.txt";
  std::ofstream(list) << text;
  return list;
}

TEST(BatchJobs, WordsAreSplitAsAShellWould) {
  EXPECT_EQ(SplitJobWords(R"(a 'b c' "d \"e\"" f\ g  # comment)", "x"),
            (std::vector<std::string>{"a", "b c", "d \"e\"", "f g"}));
  EXPECT_TRUE(SplitJobWords("   # only a comment", "x").empty());
  try {
    SplitJobWords("trial.c3d --notes 'open", "jobs.txt: line 3");
    ADD_FAILURE() << "an open quote was accepted";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("jobs.txt: line 3"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("quote is not closed"), std::string::npos) << e.what();
  }
  for (const std::string w : {"plain-word_1.c3d", "two words", "it's", ""})
    EXPECT_EQ(SplitJobWords(ShellQuote(w), "x"), w.empty() ? std::vector<std::string>{""} : std::vector<std::string>{w})
        << w;
}

TEST(BatchJobs, AListGivesEachTrialItsOptionsAndTheDefaults) {
  const fs::path dir = acro::testing::ScratchDir("batch_jobs");
  const fs::path list = WriteList(dir,
                                  "# the season\n"
                                  "day1/jump.c3d --session 2026-09-01 --video day1/side.mp4\n"
                                  "\n"
                                  "'day 2/jump.trc' --athlete other.yaml --notes 'windy day'\n");
  BatchDefaults defaults;
  defaults.athlete = "/profiles/anna.yaml";
  defaults.session = "2026-09-02";
  defaults.analyses = "/done";
  const std::vector<BatchJob> jobs = ReadBatchJobs(list, defaults);
  ASSERT_EQ(jobs.size(), 2u);
  EXPECT_EQ(jobs[0].number, 1);
  EXPECT_EQ(jobs[0].where, list.string() + ": line 2");
  EXPECT_EQ(jobs[0].request.trial, fs::absolute(dir / "day1/jump.c3d").lexically_normal());
  EXPECT_EQ(OptionValue(jobs[0].words, "--video"), (dir / "day1/side.mp4").lexically_normal().string());
  EXPECT_EQ(OptionValue(jobs[0].words, "--session"), "2026-09-01");  // its own, not the default
  EXPECT_EQ(jobs[0].request.athlete_profile, "/profiles/anna.yaml");
  EXPECT_EQ(jobs[0].request.analysis_dir, fs::path("/done/job-1"));
  EXPECT_EQ(jobs[1].request.trial, fs::absolute(dir / "day 2/jump.trc").lexically_normal());
  EXPECT_EQ(jobs[1].request.athlete_profile, (dir / "other.yaml").lexically_normal());
  EXPECT_EQ(OptionValue(jobs[1].words, "--notes"), "windy day");
  EXPECT_EQ(OptionValue(jobs[1].words, "--session"), "2026-09-02");
}

// A list saved on Windows: the \r of each line end is no part of the last value.
TEST(BatchJobs, ACrlfListReadsAsItsLfTwin) {
  const fs::path dir = acro::testing::ScratchDir("batch_jobs_crlf");
  const fs::path list =
      WriteList(dir, "day1/jump.c3d --session 2026-09-01 --notes 'windy day'\r\n# end\r\n");
  BatchDefaults defaults;
  defaults.athlete = "a.yaml";
  const std::vector<BatchJob> jobs = ReadBatchJobs(list, defaults);
  ASSERT_EQ(jobs.size(), 1u);
  EXPECT_EQ(OptionValue(jobs[0].words, "--notes"), "windy day");
  EXPECT_EQ(OptionValue(jobs[0].words, "--session"), "2026-09-01");
}

TEST(BatchJobs, MistakesNameTheLine) {
  const fs::path dir = acro::testing::ScratchDir("batch_jobs_bad");
  const auto error = [&](const std::string& text, const BatchDefaults& defaults) {
    try {
      ReadBatchJobs(WriteList(dir, text), defaults);
    } catch (const InputError& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  BatchDefaults with_athlete;
  with_athlete.athlete = "a.yaml";
  EXPECT_NE(error("a.c3d\nb.c3d --speed 3\n", with_athlete).find("line 2"), std::string::npos);
  EXPECT_NE(error("a.c3d --notes\n", with_athlete).find("with its value"), std::string::npos);
  EXPECT_NE(error("a.c3d\n", {}).find("no --athlete for this trial"), std::string::npos);
  EXPECT_EQ(error("", with_athlete), "no error");  // an empty list is no mistake: no jobs
}

}  // namespace
}  // namespace acro::library
