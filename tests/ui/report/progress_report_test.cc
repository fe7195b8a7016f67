// The season's progress page (ui/report/progress_report.h): its figures as data — every jump and
// every session median plotted where the series says, the trend line the least-squares line, the
// bed and zone A at their FIG sizes, the landings split into the season's parts — then the page
// and its files written and the PNGs decoded at their size.
#include <cairo.h>
#include <unistd.h>

#include <cmath>
#include <filesystem>
#include <fstream>

#include <gtest/gtest.h>

#include "acro/report/progress_report.h"

namespace {

namespace fs = std::filesystem;

acro::library::Progress MakeSeason() {
  std::vector<acro::library::JumpRow> rows;
  for (int s = 0; s < 9; ++s)
    for (int k = 0; k < 4; ++k) {
      acro::library::JumpRow r;
      r.athlete = "Ann";
      r.session_date = "2026-09-1" + std::to_string(s);
      r.jump.index = k + 1;
      r.jump.fig_code = "40o";
      r.jump.time_of_flight_s = 1.3 + 0.01 * s + 0.01 * k;
      r.jump.verdict_class = "pass";
      r.jump.landing_x_m = -0.15 * s;
      r.jump.landing_y_m = 0.05 * k;
      r.jump.landing_in_zone_a = std::abs(-0.15 * s) <= 1.075;
      rows.push_back(r);
    }
  return acro::library::CalcProgress(
      rows, acro::library::ProgressMetric::kTimeOfFlight, "Ann", "40o");
}

TEST(ProgressReport, FiguresHoldTheSeason) {
  const acro::library::Progress p = MakeSeason();
  const std::vector<acro::ui::ProgressFigure> figures = acro::ui::MakeProgressFigures(p);
  ASSERT_EQ(figures.size(), 3u);
  for (const auto& f : figures) {
    std::string why;
    EXPECT_TRUE(f.chart.IsValid(&why)) << f.file << ": " << why;
  }
  // The metric: 36 jumps, 9 session medians, the trend through both ends of the season.
  const acro::ui::Chart& metric = figures[0].chart;
  ASSERT_EQ(metric.series.size(), 3u);
  EXPECT_EQ(metric.series[0].x.size(), 36u);
  EXPECT_EQ(metric.series[1].y.size(), 9u);
  EXPECT_NEAR(
      metric.series[1].y[4], 1.3 + 0.04 + 0.015, 1e-12);  // median of 4: mean of the middle two
  const acro::ui::LineSeries& trend = metric.series[2];
  EXPECT_NEAR(trend.y[1] - trend.y[0], p.trend_slope_per_day * trend.x[1], 1e-12);
  EXPECT_NEAR(p.trend_slope_per_day, 0.01, 1e-12);  // one day per session, 0.01 s per session
  // Landings: the bed (4.28 m × 2.14 m), zone A (2.15 m × 1.08 m), then three parts of 3 sessions.
  const acro::ui::Chart& landings = figures[1].chart;
  ASSERT_EQ(landings.series.size(), 5u);
  EXPECT_NEAR(landings.series[0].x[1] - landings.series[0].x[0], 4.28, 1e-12);
  EXPECT_NEAR(landings.series[0].y[2] - landings.series[0].y[1], 2.14, 1e-12);
  EXPECT_NEAR(landings.series[1].x[1] - landings.series[1].x[0], 2.15, 1e-12);
  EXPECT_NEAR(landings.series[1].y[2] - landings.series[1].y[1], 1.08, 1e-12);
  for (size_t part = 2; part < 5; ++part) EXPECT_EQ(landings.series[part].x.size(), 12u);
  EXPECT_EQ(landings.series[4].name, "2026-09-16 – 2026-09-18");
  // Zone A share: 1 until the landings pass 1.075 m (session 8: 1.2 m).
  const acro::ui::Chart& zone = figures[2].chart;
  EXPECT_EQ(zone.series[0].y[7], 1.0);
  EXPECT_EQ(zone.series[0].y[8], 0.0);
  // One small chart per session: zone A, then its landings inside (and outside) it.
  const std::vector<acro::ui::ProgressFigure> sessions = acro::ui::MakeSessionLandingFigures(p);
  ASSERT_EQ(sessions.size(), 9u);
  EXPECT_EQ(sessions[0].file, "landings_2026-09-10.png");
  EXPECT_EQ(sessions[0].caption, "4 of 4 in zone A");
  EXPECT_EQ(sessions[0].chart.series.size(), 2u);  // zone A, the landings inside
  EXPECT_EQ(sessions[8].caption, "0 of 4 in zone A");
  ASSERT_EQ(sessions[8].chart.series.size(), 2u);  // zone A, the landings outside
  EXPECT_EQ(sessions[8].chart.series[1].x.size(), 4u);
  for (const auto& f : sessions) {
    std::string why;
    EXPECT_TRUE(f.chart.IsValid(&why)) << f.file << ": " << why;
  }
}

TEST(ProgressReport, WritesThePageAndItsFiles) {
  const fs::path dir = fs::temp_directory_path() / ("acro_progress_" + std::to_string(getpid()));
  fs::create_directories(dir);
  acro::ui::WriteProgressReport(MakeSeason(), dir);
  std::ifstream page(dir / "progress.html");
  const std::string html(std::istreambuf_iterator<char>(page), {});
  for (const char* f :
       {"progress_metric.png", "progress_landings.svg", "progress_zone_a.png", "progress.csv"}) {
    EXPECT_NE(html.find(f), std::string::npos) << f;
    EXPECT_TRUE(fs::exists(dir / f)) << f;
  }
  cairo_surface_t* png =
      cairo_image_surface_create_from_png((dir / "progress_landings.png").c_str());
  EXPECT_EQ(cairo_surface_status(png), CAIRO_STATUS_SUCCESS);
  EXPECT_EQ(cairo_image_surface_get_width(png), 900);
  EXPECT_EQ(cairo_image_surface_get_height(png), 520);
  cairo_surface_destroy(png);
  std::ifstream csv(dir / "progress.csv");
  std::string line;
  int lines = 0;
  while (std::getline(csv, line)) ++lines;
  EXPECT_EQ(lines, 10);  // header and 9 sessions
  fs::remove_all(dir);
}

}  // namespace
