#include "acro/ui/chart.h"

#include <gtest/gtest.h>
#include <vtkImageData.h>
#include <vtkNew.h>
#include <vtkPNGReader.h>

#include <unistd.h>
#include <cmath>

#include <algorithm>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <limits>
#include <optional>
#include <string>
#include <vector>

#include "acro/base/input_error.h"
#include "acro/ui/offscreen.h"

namespace acro::ui {
namespace {

namespace fs = std::filesystem;

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
constexpr Rgb kRed{1.0, 0.0, 0.0};
constexpr Rgb kBlue{0.0, 0.0, 1.0};
constexpr Rgb kGreen{0.0, 0.8, 0.0};

// Skips the calling test when this process cannot render, with the reason.
#define ACRO_SKIP_WITHOUT_DISPLAY()                                                 \
  do {                                                                              \
    const RenderingStatus status = OffscreenRenderingStatus();                      \
    if (!status.available) GTEST_SKIP() << "cannot render here: " << status.reason; \
  } while (0)

// A fresh empty directory under the system temporary directory.
fs::path MakeTempDir(const std::string& name) {
  const fs::path dir =
      fs::temp_directory_path() / ("acro_ui_" + name + "_" + std::to_string(getpid()));
  fs::remove_all(dir);
  fs::create_directories(dir);
  return dir;
}

// Sets an environment variable for the lifetime of the object, then restores it.
class ScopedEnv {
 public:
  ScopedEnv(const char* name, const char* value) : name_(name) {
    if (const char* old = std::getenv(name)) old_ = old;
    if (value) {
      setenv(name, value, 1);
    } else {
      unsetenv(name);
    }
  }
  ~ScopedEnv() {
    if (old_) {
      setenv(name_, old_->c_str(), 1);
    } else {
      unsetenv(name_);
    }
  }

 private:
  const char* name_;
  std::optional<std::string> old_;
};

// A decoded RGB image, row 0 at the top.
struct Image {
  int width = 0;
  int height = 0;
  std::vector<unsigned char> rgb;
  const unsigned char* At(int x, int y) const {
    return &rgb[3 * (static_cast<std::size_t>(y) * width + x)];
  }
};

// Decodes a PNG file with VTK's reader (an implementation independent of the writer's options).
Image ReadPng(const fs::path& path) {
  vtkNew<vtkPNGReader> reader;
  reader->SetFileName(path.c_str());
  reader->Update();
  vtkImageData* data = reader->GetOutput();
  int dims[3];
  data->GetDimensions(dims);
  Image image;
  image.width = dims[0];
  image.height = dims[1];
  const int channels = data->GetNumberOfScalarComponents();
  image.rgb.resize(3 * static_cast<std::size_t>(dims[0]) * dims[1]);
  // VTK's image rows run bottom-up.
  for (int y = 0; y < dims[1]; ++y) {
    for (int x = 0; x < dims[0]; ++x) {
      const auto* p =
          static_cast<const unsigned char*>(data->GetScalarPointer(x, dims[1] - 1 - y, 0));
      for (int c = 0; c < 3; ++c)
        image.rgb[3 * (static_cast<std::size_t>(y) * dims[0] + x) + c] =
            p[std::min(c, channels - 1)];
    }
  }
  return image;
}

bool IsRed(const unsigned char* p) {
  return p[0] > 180 && p[1] < 90 && p[2] < 90;
}
bool IsBlue(const unsigned char* p) {
  return p[2] > 180 && p[0] < 90 && p[1] < 90;
}
// The green band at alpha 0.3 over white: about (178, 240, 178); well away from white and grey.
bool IsBandTint(const unsigned char* p) {
  return p[1] > 200 && p[0] > 140 && p[0] < 215 && p[2] > 140 && p[2] < 215 && p[1] > p[0] + 20;
}

// Counts pixels matching `pred` in the box [x0, x1) × [y0, y1) (fractions of the image, y from
// top).
template <typename Pred>
int CountIn(const Image& image, double x0, double x1, double y0, double y1, Pred pred) {
  int count = 0;
  for (int y = static_cast<int>(y0 * image.height); y < static_cast<int>(y1 * image.height); ++y) {
    for (int x = static_cast<int>(x0 * image.width); x < static_cast<int>(x1 * image.width); ++x) {
      if (pred(image.At(x, y))) ++count;
    }
  }
  return count;
}

// For each column, whether any pixel in it matches `pred`.
template <typename Pred>
std::vector<bool> ColumnsWith(const Image& image, Pred pred) {
  std::vector<bool> columns(image.width, false);
  for (int y = 0; y < image.height; ++y) {
    for (int x = 0; x < image.width; ++x) {
      if (pred(image.At(x, y))) columns[x] = true;
    }
  }
  return columns;
}

// The longest run of columns without a match between the first and last matching column.
int LongestGap(const std::vector<bool>& columns) {
  int first = -1, last = -1;
  for (int x = 0; x < static_cast<int>(columns.size()); ++x) {
    if (columns[x]) {
      if (first < 0) first = x;
      last = x;
    }
  }
  int longest = 0, run = 0;
  for (int x = first; x >= 0 && x <= last; ++x) {
    run = columns[x] ? 0 : run + 1;
    longest = std::max(longest, run);
  }
  return longest;
}

// y = x rising in red, y = 10 − x falling in blue, x in [0, 10] at 101 points.
LineSeries Ramp(const std::string& name, bool rising, Rgb color) {
  LineSeries series;
  series.name = name;
  series.color = color;
  series.width_px = 3.0;
  for (int i = 0; i <= 100; ++i) {
    const double x = 0.1 * i;
    series.x.push_back(x);
    series.y.push_back(rising ? x : 10.0 - x);
  }
  return series;
}

Chart TwoSeriesChart() {
  Chart chart;
  chart.title = "Test chart";
  chart.x_label = "time (s)";
  chart.y_label = "value";
  chart.series = {Ramp("rising", true, kRed), Ramp("falling", false, kBlue)};
  chart.bands = {{2.0, 4.0, kGreen, 0.3, "flight"}};
  chart.show_legend = false;
  return chart;
}

TEST(ChartTest, IsValidNamesTheFault) {
  std::string why;
  Chart empty;
  EXPECT_FALSE(empty.IsValid(&why));
  EXPECT_NE(why.find("no series"), std::string::npos) << why;

  Chart mismatch = TwoSeriesChart();
  mismatch.series[1].y.pop_back();
  EXPECT_FALSE(mismatch.IsValid(&why));
  EXPECT_NE(why.find("series 1 'falling': x has 101 values but y has 100"), std::string::npos)
      << why;

  Chart all_nan = TwoSeriesChart();
  for (LineSeries& s : all_nan.series) s.y.assign(s.y.size(), kNaN);
  EXPECT_FALSE(all_nan.IsValid(&why));
  EXPECT_NE(why.find("finite point"), std::string::npos) << why;

  Chart bad_band = TwoSeriesChart();
  bad_band.bands[0].x1 = 1.0;  // before x0
  EXPECT_FALSE(bad_band.IsValid(&why));
  EXPECT_NE(why.find("band 0 'flight'"), std::string::npos) << why;

  Chart bad_range = TwoSeriesChart();
  bad_range.y_range = ValueRange{1.0, 1.0};
  EXPECT_FALSE(bad_range.IsValid(&why));
  EXPECT_NE(why.find("y_range"), std::string::npos) << why;

  EXPECT_TRUE(TwoSeriesChart().IsValid(&why)) << why;
  EXPECT_TRUE(TwoSeriesChart().IsValid(nullptr));
}

TEST(ChartTest, BadInputThrowsBeforeRenderingAndWritesNothing) {
  // Validation comes first, so these errors hold with or without a display.
  const fs::path dir = MakeTempDir("bad");
  Chart mismatch = TwoSeriesChart();
  mismatch.series[0].x.push_back(11.0);
  try {
    RenderChartPng(mismatch, dir / "bad.png");
    FAIL() << "no exception";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("chart 'Test chart'"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("series 0 'rising': x has 102 values but y has 101"),
              std::string::npos)
        << e.what();
  }
  EXPECT_THROW(RenderChartPng(Chart{}, dir / "empty.png"), InputError);
  const std::vector<Chart> charts = {TwoSeriesChart()};
  const std::vector<fs::path> paths = {dir / "a.png", dir / "b.png"};
  EXPECT_THROW(RenderChartsPng(charts, paths), std::invalid_argument);
  EXPECT_TRUE(fs::is_empty(dir));
  fs::remove_all(dir);
}

TEST(ChartTest, NoDisplayIsReportedNotFatal) {
  // Without DISPLAY, VTK 9.1 (X only) would abort on creating a window: the status must say so
  // and the renderer must throw instead.
  const ScopedEnv no_display("DISPLAY", nullptr);
  const RenderingStatus status = OffscreenRenderingStatus();
  EXPECT_FALSE(status.available);
  EXPECT_NE(status.reason.find("no display"), std::string::npos) << status.reason;
  EXPECT_NE(status.reason.find("xvfb-run"), std::string::npos) << status.reason;
  EXPECT_THROW(ChartRenderer(), RenderingUnavailable);

  // A display that does not exist is reported, not fatal, too.
  const ScopedEnv bad_display("DISPLAY", ":9731");
  const RenderingStatus bad = OffscreenRenderingStatus();
  EXPECT_FALSE(bad.available);
  EXPECT_NE(bad.reason.find("cannot open display ':9731'"), std::string::npos) << bad.reason;
}

TEST(ChartTest, RendersSeriesAndBandWhereExpected) {
  ACRO_SKIP_WITHOUT_DISPLAY();
  const fs::path dir = MakeTempDir("render");
  const fs::path path = dir / "chart.png";
  RenderChartPng(TwoSeriesChart(), path);

  // Written atomically: the file and nothing else.
  std::vector<fs::path> entries;
  for (const auto& entry : fs::directory_iterator(dir)) entries.push_back(entry.path());
  ASSERT_EQ(entries.size(), 1u);
  EXPECT_EQ(entries[0].filename(), "chart.png");

  const Image image = ReadPng(path);
  ASSERT_EQ(image.width, 900);
  ASSERT_EQ(image.height, 360);

  // Red rises: it ends in the upper right, never in the lower right; blue falls: the reverse.
  // The margins (0.65 rather than 0.5) keep clear of where the lines cross the centre.
  EXPECT_GT(CountIn(image, 0.65, 1.0, 0.0, 0.35, IsRed), 50);
  EXPECT_EQ(CountIn(image, 0.65, 1.0, 0.65, 1.0, IsRed), 0);
  EXPECT_GT(CountIn(image, 0.65, 1.0, 0.65, 1.0, IsBlue), 50);
  EXPECT_EQ(CountIn(image, 0.65, 1.0, 0.0, 0.35, IsBlue), 0);

  // The band [2, 4] of x in [0, 10]: tinted columns form one run about a fifth of the plot width
  // wide, in the left half.
  const std::vector<bool> band = ColumnsWith(image, IsBandTint);
  int first = -1, last = -1, count = 0;
  for (int x = 0; x < image.width; ++x) {
    if (!band[x]) continue;
    if (first < 0) first = x;
    last = x;
    ++count;
  }
  ASSERT_GE(first, 0) << "no band tint found";
  const int span = last - first + 1;
  EXPECT_EQ(count, span) << "band columns are not contiguous";
  EXPECT_GT(span, 0.15 * image.width);
  EXPECT_LT(span, 0.23 * image.width);
  EXPECT_GT(first, 0.15 * image.width);
  EXPECT_LT(last, 0.5 * image.width);
  fs::remove_all(dir);
}

TEST(ChartTest, NanBreaksTheLine) {
  ACRO_SKIP_WITHOUT_DISPLAY();
  const fs::path dir = MakeTempDir("gap");
  Chart chart;
  chart.series = {Ramp("rising", true, kRed)};
  chart.show_legend = false;
  Chart gapped = chart;
  // x in (4, 6) missing: a gap of a fifth of the x range.
  for (std::size_t i = 0; i < gapped.series[0].x.size(); ++i) {
    if (gapped.series[0].x[i] > 4.05 && gapped.series[0].x[i] < 5.95) gapped.series[0].y[i] = kNaN;
  }
  const std::vector<Chart> charts = {chart, gapped};
  const std::vector<fs::path> paths = {dir / "whole.png", dir / "gapped.png"};
  RenderChartsPng(charts, paths);

  const Image whole = ReadPng(paths[0]);
  const Image broken = ReadPng(paths[1]);
  EXPECT_LE(LongestGap(ColumnsWith(whole, IsRed)), 2);
  const int gap = LongestGap(ColumnsWith(broken, IsRed));
  EXPECT_GT(gap, 0.15 * broken.width) << "the NaN run was joined across";
  EXPECT_LT(gap, 0.22 * broken.width);
  fs::remove_all(dir);
}

TEST(ChartTest, RendererIsReusableAcrossSizesAndOverwrites) {
  ACRO_SKIP_WITHOUT_DISPLAY();
  const fs::path dir = MakeTempDir("reuse");
  ChartRenderer renderer;
  Chart chart = TwoSeriesChart();
  chart.show_legend = true;
  chart.reference_lines = {{5.0, "threshold", {0.5, 0.5, 0.5}, true}};
  chart.y_range = ValueRange{-1.0, 11.0};
  chart.series[0].dashed = true;
  chart.series[1].y[50] = kNaN;
  chart.bands.push_back({6.0, 7.0, kGreen, 0.3, "flight"});
  renderer.RenderPng(chart, dir / "out.png");
  chart.width_px = 400;
  chart.height_px = 300;
  renderer.RenderPng(chart, dir / "out.png");
  const Image image = ReadPng(dir / "out.png");
  EXPECT_EQ(image.width, 400);
  EXPECT_EQ(image.height, 300);
  const std::vector<std::uint8_t> bytes = renderer.RenderPngBytes(chart);
  ASSERT_GT(bytes.size(), 8u);
  EXPECT_EQ(bytes[1], 'P');
  EXPECT_EQ(bytes[2], 'N');
  EXPECT_EQ(bytes[3], 'G');
  fs::remove_all(dir);
}

// --- Relaunch under Xvfb ---

class XvfbRelaunchTest : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = MakeTempDir("xvfb");
    fake_ = dir_ / "xvfb-run";
    std::ofstream(fake_) << "#!/bin/sh\n";
    fs::permissions(fake_, fs::perms::owner_all);
  }
  void TearDown() override { fs::remove_all(dir_); }
  fs::path dir_;
  fs::path fake_;
};

TEST_F(XvfbRelaunchTest, RelaunchesOnlyWithoutDisplayOnceAndWhenInstalled) {
  const std::vector<std::string> args = {"/opt/acrolab", "analyze", "trial.c3d", "-o", "out dir"};
  const std::string path = "/nonexistent:" + dir_.string();

  const auto command = XvfbRelaunchCommand(args, DisplayEnvironment{"", "", path});
  ASSERT_TRUE(command.has_value());
  const std::vector<std::string> expected = {fake_.string(),
                                             "-a",
                                             "-s",
                                             "-screen 0 1280x1024x24 -noreset",
                                             "env",
                                             "ACRO_UNDER_XVFB=1",
                                             "/opt/acrolab",
                                             "analyze",
                                             "trial.c3d",
                                             "-o",
                                             "out dir"};
  EXPECT_EQ(*command, expected);

  EXPECT_FALSE(XvfbRelaunchCommand(args, DisplayEnvironment{":0", "", path}));
  EXPECT_FALSE(XvfbRelaunchCommand(args, DisplayEnvironment{"", "1", path}));
  EXPECT_FALSE(XvfbRelaunchCommand(args, DisplayEnvironment{"", "", "/nonexistent"}));
  EXPECT_FALSE(XvfbRelaunchCommand(std::vector<std::string>{}, DisplayEnvironment{"", "", path}));
}

TEST_F(XvfbRelaunchTest, FindOnPathNeedsAnExecutableFile) {
  EXPECT_EQ(FindOnPath("xvfb-run", dir_.string()), fake_);
  fs::permissions(fake_, fs::perms::owner_read | fs::perms::owner_write);
  EXPECT_FALSE(FindOnPath("xvfb-run", dir_.string()));
  EXPECT_FALSE(FindOnPath("xvfb-run", ""));
}

TEST_F(XvfbRelaunchTest, MainArgumentsUseThisExecutable) {
  const ScopedEnv no_display("DISPLAY", nullptr);
  const ScopedEnv no_guard(kUnderXvfbEnv, nullptr);
  const ScopedEnv path("PATH", dir_.c_str());
  const char* argv[] = {"relative/name", "--flag"};
  const auto command = XvfbRelaunchCommand(2, argv);
  ASSERT_TRUE(command.has_value());
  ASSERT_EQ(command->size(), 8u);
  EXPECT_EQ((*command)[6], fs::read_symlink("/proc/self/exe").string());
  EXPECT_EQ((*command)[7], "--flag");
}

}  // namespace
}  // namespace acro::ui
