// The report of `acrolab analyze`: what its figures show is checked as data (no display needed),
// the page says what a coach must read, and with a display the PNGs are written and linked.
#include "acro/report/analysis_report.h"

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>

#include <cstdlib>
#include "acro/athlete/athlete_profile.h"
#include "acro/athlete/de_leva.h"
#include "acro/base/input_error.h"
#include "acro/base/text_format.h"
#include "acro/capture/c3d.h"
#include "acro/capture/trial_io.h"
#include "refdata.h"

namespace acro::ui {
namespace {

namespace fs = std::filesystem;

const analysis::TrialAnalysis& Sample() {
  static const analysis::TrialAnalysis a = [] {
    const fs::path root = acro::testing::SourceDir();
    const capture::Trial trial =
        capture::ReadC3d(root / "samples/trials/trampoline_routine/trampoline_routine.c3d");
    const analysis::AthleteBody body = analysis::MakeAthleteBody(
        analysis::ReadAthleteProfile(root / "samples/athletes/sample_athlete.yaml"));
    return analysis::AnalyzeTrial(trial, nullptr, body);
  }();
  return a;
}

int FiniteCount(const std::vector<double>& y) {
  return static_cast<int>(
      std::count_if(y.begin(), y.end(), [](double v) { return std::isfinite(v); }));
}

TEST(AnalysisReport, FiguresShowThePhasesTheJudgedResidualsAndTheChosenJoint) {
  const analysis::TrialAnalysis& a = Sample();
  AnalysisReportOptions options;
  options.joint = "l_knee_flexion";
  const std::vector<ReportFigure> figures = MakeAnalysisFigures(a, options);
  ASSERT_EQ(figures.size(), 8u);
  const int frames = a.reconstruction.motion.num_frames();
  int judged = 0;
  for (const analysis::FlightCheck& f : a.check.flights) judged += f.last_frame - f.first_frame + 1;
  // The execution chart (the last): per element, each fault's worst value over its first
  // threshold; the clean sample's are all below 1 (no fault), one point per element and fault.
  const ReportFigure& execution = figures.back();
  EXPECT_EQ(execution.file, "execution.png");
  ASSERT_FALSE(execution.chart.series.empty());
  size_t points = 0;
  for (const LineSeries& s : execution.chart.series) {
    EXPECT_FALSE(s.name.empty());
    for (size_t i = 0; i < s.y.size(); ++i) {
      EXPECT_LT(s.y[i], 1.0) << s.name << " at element " << s.x[i];
      EXPECT_GT(s.x[i], 0.5);
      EXPECT_LT(s.x[i], double(a.score.elements.size()) + 0.5);
    }
    points += s.y.size();
  }
  size_t measured = 0;
  for (const auto& e : a.score.elements)
    for (const auto& f : e.faults)
      measured += std::isfinite(f.threshold) && f.threshold > 0 ? 1 : 0;
  EXPECT_EQ(points, measured);
  for (size_t k = 0; k + 1 < figures.size(); ++k) {
    const ReportFigure& f = figures[k];
    SCOPED_TRACE(f.file);
    std::string why;
    EXPECT_TRUE(f.chart.IsValid(&why)) << why;
    // Every chart shades the six flights and spans the whole trial.
    EXPECT_EQ(f.chart.bands.size(), a.phases.flights.size());
    for (const LineSeries& s : f.chart.series) EXPECT_EQ(static_cast<int>(s.x.size()), frames);
    EXPECT_FALSE(f.caption.empty());
  }
  // COM height: the COM and the lowest sole, and the bed line at the bed's height.
  EXPECT_EQ(figures[0].file, "com_height.png");
  ASSERT_EQ(figures[0].chart.reference_lines.size(), 1u);
  EXPECT_DOUBLE_EQ(figures[0].chart.reference_lines[0].y, a.bed->centre_W.z());
  // Residual force: per frame over the judged frames only, the judged mean, the limit.
  EXPECT_EQ(figures[1].file, "residual_force.png");
  ASSERT_EQ(figures[1].chart.series.size(), 2u);
  EXPECT_EQ(FiniteCount(figures[1].chart.series[0].y), judged);
  EXPECT_GT(FiniteCount(figures[1].chart.series[1].y), judged / 2);
  EXPECT_DOUBLE_EQ(figures[1].chart.reference_lines[0].y, a.check_options.max_force_bw);
  // The clean sample passes: its judged mean stays below the limit everywhere.
  for (double v : figures[1].chart.series[1].y) {
    if (std::isfinite(v)) {
      EXPECT_LE(v, a.check_options.max_force_bw);
    }
  }
  // The joint: its angle in degrees and its torque.
  EXPECT_NE(figures[4].chart.title.find("l_knee_flexion"), std::string::npos);
  EXPECT_NE(figures[5].chart.title.find("l_knee_flexion"), std::string::npos);
  double max_knee_deg = 0;
  for (double v : figures[4].chart.series[0].y) max_knee_deg = std::max(max_knee_deg, v);
  EXPECT_GT(max_knee_deg, 90.0);  // the tucks bend the knees well past a right angle
  // Somersault and twist from each take-off, in contact nothing: at its last flight frame each
  // jump has turned what its code says (the double back two backward turns, the full one twist);
  // the routine's generator made them 10–20 % short of whole turns in the air (a somersault is
  // completed on the bed).
  EXPECT_EQ(figures[6].file, "rotation.png");
  const std::vector<double>& somersault = figures[6].chart.series[0].y;
  const std::vector<double>& twist = figures[6].chart.series[1].y;
  const auto at_landing = [&](const std::vector<double>& y, int jump) {
    return y[size_t(a.jumps.at(size_t(jump - 1)).flight.landing_frame)];
  };
  EXPECT_LT(at_landing(somersault, 6), -540.0);  // 800o
  EXPECT_GT(at_landing(somersault, 6), -760.0);
  EXPECT_LT(at_landing(somersault, 2), -250.0);  // 40o
  EXPECT_GT(at_landing(twist, 5), 270.0);        // 42/: a full twist
  EXPECT_LT(std::abs(at_landing(twist, 6)), 20.0);
  EXPECT_FALSE(std::isfinite(somersault[size_t(a.jumps.at(0).flight.landing_frame + 5)]));
}

TEST(AnalysisReport, AnUnknownJointIsAnInputError) {
  AnalysisReportOptions options;
  options.joint = "r_tail_wag";
  EXPECT_THROW(MakeAnalysisFigures(Sample(), options), acro::InputError);
}

TEST(AnalysisReport, ThePageCarriesTheRoutineTheVerdictAndEveryJump) {
  const analysis::TrialAnalysis& a = Sample();
  const AnalysisReportOptions options;
  const std::vector<ReportFigure> figures = MakeAnalysisFigures(a, options);
  AnalysisReportOutcome none;
  none.reason = "no display: test";
  const std::string html = FormatAnalysisReportHtml(a, figures, options, none);
  EXPECT_NE(html.find("6 skills"), std::string::npos);
  EXPECT_NE(html.find("<b>3.5</b>"), std::string::npos);  // the routine's DD
  EXPECT_NE(html.find("class=\"pass\"><b>pass</b>"), std::string::npos);
  for (const analysis::JumpMetrics& j : a.jumps)
    EXPECT_NE(html.find("<b>" + acro::HtmlEscape(j.fig_code) + "</b>"), std::string::npos)
        << j.fig_code;
  EXPECT_NE(html.find("No plots in this report: no display: test"), std::string::npos);
  EXPECT_EQ(html.find("<img"), std::string::npos);
  AnalysisReportOutcome rendered;
  rendered.images_rendered = true;
  const std::string with = FormatAnalysisReportHtml(a, figures, options, rendered);
  for (const ReportFigure& f : figures)
    EXPECT_NE(with.find("<img src=\"" + f.file + "\""), std::string::npos) << f.file;
}

TEST(AnalysisReport, PngAndSvgAreWrittenAndLinkedWithNoDisplay) {
  // Charts are drawn by Cairo in memory: DISPLAY plays no part.
  const char* display = std::getenv("DISPLAY");
  const std::string saved = display ? display : "";
  unsetenv("DISPLAY");
  const fs::path dir = acro::testing::TempDir() / "analysis_report";
  fs::remove_all(dir);
  fs::create_directories(dir);
  const AnalysisReportOutcome outcome = WriteAnalysisReport(Sample(), dir, {});
  if (display) setenv("DISPLAY", saved.c_str(), 1);
  ASSERT_TRUE(outcome.images_rendered) << outcome.reason;
  ASSERT_EQ(outcome.images.size(), 16u);  // eight figures, PNG and SVG each
  for (const fs::path& p : outcome.images) {
    std::ifstream in(p, std::ios::binary);
    std::string head(5, '\0');
    in.read(head.data(), 5);
    if (p.extension() == ".png") {
      EXPECT_EQ(head.substr(1, 3), "PNG") << p;
    } else {
      EXPECT_EQ(head, "<?xml") << p;
    }
  }
  std::ifstream page(dir / "report.html");
  const std::string html(std::istreambuf_iterator<char>(page), {});
  EXPECT_NE(html.find("<img src=\"com_height.png\""), std::string::npos);
  EXPECT_NE(html.find("<a href=\"com_height.svg\">SVG</a>"), std::string::npos);
}

// A trial with no flight (the Pose2Sim balancing trial: a person standing on one leg, BODY_25B
// keypoints) still gets its plots — the centre of mass and the joint — and the page says why the
// flight charts are absent; it once lost every plot to the empty residual chart.
TEST(AnalysisReport, ATrialWithoutAFlightStillHasItsPlots) {
  const fs::path file = acro::testing::RefdataFile(
      "pose2sim-demo/balancing-trial/pose-3d/S00_P00_T01_BalancingTrial_0-100.trc");
  ACRO_REQUIRE_REFDATA_FILE(file);
  const capture::Trial trial = capture::ReadTrial(file);
  const analysis::TrialAnalysis a = analysis::AnalyzeTrial(
      trial, nullptr, analysis::MakeDeLevaBody(1.75, 65.0, analysis::Sex::kFemale));
  ASSERT_TRUE(a.phases.flights.empty());
  const std::vector<ReportFigure> figures = MakeAnalysisFigures(a, {});
  std::vector<std::string> files;
  for (const ReportFigure& f : figures) files.push_back(f.file);
  EXPECT_EQ(files,
            (std::vector<std::string>{"com_height.png", "joint_angle.png", "joint_torque.png"}));
  const fs::path dir = acro::testing::TempDir() / "analysis_report_no_flight";
  fs::remove_all(dir);
  fs::create_directories(dir);
  const AnalysisReportOutcome outcome = WriteAnalysisReport(a, dir, {});
  ASSERT_TRUE(outcome.images_rendered) << outcome.reason;
  EXPECT_EQ(outcome.images.size(), 6u);
  std::ifstream page(dir / "report.html");
  const std::string html(std::istreambuf_iterator<char>(page), {});
  EXPECT_NE(html.find("No flight in this trial"), std::string::npos);
}

}  // namespace
}  // namespace acro::ui
