#include "acro/report/chart.h"

#include <cairo.h>
#include <gtest/gtest.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <limits>
#include <optional>
#include <sstream>
#include <string>
#include <vector>

#include "acro/base/input_error.h"

namespace acro::ui {
namespace {

namespace fs = std::filesystem;

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
constexpr Rgb kRed{1.0, 0.0, 0.0};
constexpr Rgb kBlue{0.0, 0.0, 1.0};
constexpr Rgb kGreen{0.0, 0.8, 0.0};

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

// Decodes PNG bytes with libpng through Cairo's reader (RGB24 pixels, row 0 at the top).
Image DecodePng(const std::string& png) {
  struct Cursor {
    const std::string* bytes;
    std::size_t pos = 0;
  } cursor{&png};
  cairo_surface_t* surface = cairo_image_surface_create_from_png_stream(
      [](void* closure, unsigned char* data, unsigned int length) {
        auto* c = static_cast<Cursor*>(closure);
        if (c->pos + length > c->bytes->size()) return CAIRO_STATUS_READ_ERROR;
        std::copy_n(c->bytes->data() + c->pos, length, data);
        c->pos += length;
        return CAIRO_STATUS_SUCCESS;
      },
      &cursor);
  Image image;
  if (cairo_surface_status(surface) == CAIRO_STATUS_SUCCESS) {
    image.width = cairo_image_surface_get_width(surface);
    image.height = cairo_image_surface_get_height(surface);
    const int stride = cairo_image_surface_get_stride(surface);
    const unsigned char* data = cairo_image_surface_get_data(surface);
    image.rgb.resize(3 * static_cast<std::size_t>(image.width) * image.height);
    for (int y = 0; y < image.height; ++y) {
      for (int x = 0; x < image.width; ++x) {
        std::uint32_t pixel = 0;
        std::copy_n(data + y * stride + 4 * x, 4, reinterpret_cast<unsigned char*>(&pixel));
        unsigned char* out = &image.rgb[3 * (static_cast<std::size_t>(y) * image.width + x)];
        out[0] = static_cast<unsigned char>(pixel >> 16);
        out[1] = static_cast<unsigned char>(pixel >> 8);
        out[2] = static_cast<unsigned char>(pixel);
      }
    }
  }
  cairo_surface_destroy(surface);
  return image;
}

std::string ReadFile(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(in), {});
}

Image ReadPng(const fs::path& path) {
  return DecodePng(ReadFile(path));
}

Image Render(const Chart& chart) {
  const std::vector<std::uint8_t> png = RenderChartPng(chart);
  return DecodePng(std::string(png.begin(), png.end()));
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

TEST(ChartTest, BadInputThrowsAndWritesNothing) {
  const fs::path dir = MakeTempDir("bad");
  Chart mismatch = TwoSeriesChart();
  mismatch.series[0].x.push_back(11.0);
  try {
    WriteChart(mismatch, dir / "bad.png");
    FAIL() << "no exception";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("chart 'Test chart'"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("series 0 'rising': x has 102 values but y has 101"),
              std::string::npos)
        << e.what();
  }
  EXPECT_THROW(WriteChart(Chart{}, dir / "empty.svg"), InputError);
  try {
    WriteChart(TwoSeriesChart(), dir / "chart.jpg");
    FAIL() << "no exception";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("'.jpg'"), std::string::npos) << e.what();
  }
  EXPECT_TRUE(fs::is_empty(dir));
  fs::remove_all(dir);
}

// A chart's data as CSV (the studio's "export what is shown"): every point of every series, read
// back to the same numbers; a name with a comma quoted; NaN gaps left out.
TEST(ChartTest, CsvHoldsEveryPointOfEverySeries) {
  Chart chart = TwoSeriesChart();
  chart.series[1].name = "falling, fast";
  chart.series[1].y[50] = std::numeric_limits<double>::quiet_NaN();
  const std::string csv = FormatChartCsv(chart);
  std::istringstream in(csv);
  std::string line;
  std::getline(in, line);
  EXPECT_EQ(line, "series,x,y");
  int rising = 0, falling = 0;
  while (std::getline(in, line)) {
    if (line.rfind("rising,", 0) == 0) {
      const double x = std::stod(line.substr(7));
      const double y = std::stod(line.substr(line.rfind(',') + 1));
      EXPECT_DOUBLE_EQ(x, chart.series[0].x[size_t(rising)]);
      EXPECT_DOUBLE_EQ(y, chart.series[0].y[size_t(rising)]);
      ++rising;
    } else {
      EXPECT_EQ(line.rfind("\"falling, fast\",", 0), 0u) << line;
      ++falling;
    }
  }
  EXPECT_EQ(rising, 101);
  EXPECT_EQ(falling, 100);  // the NaN left out
}

// The RGB pixels a video frame takes (compare's charts) are the PNG's, decoded by libpng.
TEST(ChartTest, RgbPixelsAreThePngsPixels) {
  const Chart chart = TwoSeriesChart();
  const std::vector<std::uint8_t> rgb = RenderChartRgb(chart);
  const Image png = Render(chart);
  ASSERT_EQ(png.width, chart.width_px);
  ASSERT_EQ(rgb.size(), png.rgb.size());
  EXPECT_TRUE(std::equal(rgb.begin(), rgb.end(), png.rgb.begin()));
}

TEST(ChartTest, RendersSeriesAndBandWhereExpectedWithNoDisplay) {
  // Cairo draws into memory: no X server is involved, whatever DISPLAY says.
  const ScopedEnv no_display("DISPLAY", nullptr);
  const fs::path dir = MakeTempDir("render");
  const fs::path path = dir / "chart.png";
  WriteChart(TwoSeriesChart(), path);

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

  // The band [2, 4] of x in [0, 10]: tinted columns form one run a fifth of the plot width wide,
  // where the layout puts x = 2 and x = 4 (to a pixel of anti-aliasing).
  const ChartLayout layout = MakeChartLayout(TwoSeriesChart());
  const std::vector<bool> band = ColumnsWith(image, IsBandTint);
  int first = -1, last = -1, count = 0;
  for (int x = 0; x < image.width; ++x) {
    if (!band[x]) continue;
    if (first < 0) first = x;
    last = x;
    ++count;
  }
  ASSERT_GE(first, 0) << "no band tint found";
  EXPECT_EQ(count, last - first + 1) << "band columns are not contiguous";
  const double px_per_x = (layout.plot_right - layout.plot_left) / 10.0;
  EXPECT_NEAR(first, layout.plot_left + 2.0 * px_per_x, 1.5);
  EXPECT_NEAR(last + 1, layout.plot_left + 4.0 * px_per_x, 1.5);
  fs::remove_all(dir);
}

TEST(ChartTest, NanBreaksTheLine) {
  Chart chart;
  chart.series = {Ramp("rising", true, kRed)};
  chart.show_legend = false;
  Chart gapped = chart;
  // x in (4, 6) missing: a gap of a fifth of the x range.
  for (std::size_t i = 0; i < gapped.series[0].x.size(); ++i) {
    if (gapped.series[0].x[i] > 4.05 && gapped.series[0].x[i] < 5.95) gapped.series[0].y[i] = kNaN;
  }
  const Image whole = Render(chart);
  const Image broken = Render(gapped);
  EXPECT_LE(LongestGap(ColumnsWith(whole, IsRed)), 2);
  const int gap = LongestGap(ColumnsWith(broken, IsRed));
  EXPECT_GT(gap, 0.15 * broken.width) << "the NaN run was joined across";
  EXPECT_LT(gap, 0.22 * broken.width);
}

TEST(ChartTest, SizesAreHonouredAndPngAndSvgComeFromOneLayout) {
  Chart chart = TwoSeriesChart();
  chart.show_legend = true;
  chart.reference_lines = {{5.0, "threshold", {0.5, 0.5, 0.5}, true}};
  chart.y_range = ValueRange{-1.0, 11.0};
  chart.series[0].dashed = true;
  chart.series[1].y[50] = kNaN;
  chart.bands.push_back({6.0, 7.0, kGreen, 0.3, "flight"});
  chart.width_px = 400;
  chart.height_px = 300;
  const Image image = Render(chart);
  EXPECT_EQ(image.width, 400);
  EXPECT_EQ(image.height, 300);

  const std::string svg = RenderChartSvg(chart);
  EXPECT_EQ(svg.rfind("<?xml", 0), 0u) << svg.substr(0, 60);
  EXPECT_NE(svg.find("width=\"400px\""), std::string::npos) << svg.substr(0, 300);
  EXPECT_NE(svg.find("height=\"300px\""), std::string::npos) << svg.substr(0, 300);
  EXPECT_NE(svg.find("</svg>"), std::string::npos);
  // The series are vector paths in the SVG, in their colours (red is rgb(100%,0%,0%)).
  EXPECT_NE(svg.find("rgb(100%,0%,0%)"), std::string::npos);
  EXPECT_NE(svg.find("rgb(0%,0%,100%)"), std::string::npos);
}

// The legend box of a drawn chart, in the layout.
bool LegendMeetsData(const Chart& chart, const ChartLayout& l) {
  for (const LineSeries& s : chart.series) {
    for (std::size_t i = 0; i < s.x.size(); ++i) {
      const double x = l.plot_left + (s.x[i] - l.x_range.min) / (l.x_range.max - l.x_range.min) *
                                         (l.plot_right - l.plot_left);
      const double y = l.plot_bottom - (s.y[i] - l.y_range.min) / (l.y_range.max - l.y_range.min) *
                                           (l.plot_bottom - l.plot_top);
      if (x >= l.legend_left && x <= l.legend_right && y >= l.legend_top && y <= l.legend_bottom)
        return true;
    }
  }
  return false;
}

TEST(ChartTest, LegendCoversNoData) {
  // One ramp from the bottom left to the top right leaves two corners free.
  Chart chart = TwoSeriesChart();
  chart.series = {Ramp("rising", true, kRed)};
  chart.show_legend = true;
  ChartLayout layout = MakeChartLayout(chart);
  ASSERT_TRUE(layout.legend_drawn);
  EXPECT_TRUE(layout.legend_inside);
  EXPECT_FALSE(LegendMeetsData(chart, layout));
  // The rising ramp occupies the top right: the legend goes to the top left.
  EXPECT_LT(layout.legend_left, 0.5 * (layout.plot_left + layout.plot_right));

  // Data in every corner (two crossing ramps and a flat line at each end): outside, on the right.
  chart = TwoSeriesChart();
  chart.show_legend = true;
  layout = MakeChartLayout(chart);
  ASSERT_TRUE(layout.legend_drawn);
  EXPECT_FALSE(layout.legend_inside);
  EXPECT_GE(layout.legend_left, layout.plot_right);
  EXPECT_FALSE(LegendMeetsData(chart, layout));

  // Series without names are left out of the legend; with none named, there is no legend.
  for (LineSeries& s : chart.series) s.name.clear();
  chart.bands.front().label.clear();
  ASSERT_TRUE(chart.show_legend);
  EXPECT_FALSE(MakeChartLayout(chart).legend_drawn);
}

// Dark (text) pixels in the rows of the title.
int TitleInk(const std::string& title) {
  Chart chart = TwoSeriesChart();
  chart.title = title;
  const Image image = Render(chart);
  const ChartLayout layout = MakeChartLayout(chart);
  return CountIn(image, 0.0, 1.0, 0.0, (layout.plot_top - 1.0) / image.height, [](const auto* p) {
    return p[0] < 128 && p[1] < 128 && p[2] < 128;
  });
}

TEST(ChartTest, UnicodeTextIsDrawn) {
  // "²" and "·" are glyphs of their own, not dropped (OpenCV's Hershey fonts dropped them).
  const int plain = TitleInk("kg m/s");
  EXPECT_GT(plain, 50);
  EXPECT_GT(TitleInk("kg·m²/s"), plain + 5);
}

}  // namespace
}  // namespace acro::ui
