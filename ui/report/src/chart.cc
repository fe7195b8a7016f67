#include "acro/report/chart.h"

#include <cairo-svg.h>
#include <cairo.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <memory>
#include <set>
#include <stdexcept>
#include <string_view>

#include <fmt/format.h>

#include "acro/base/file_io.h"
#include "acro/base/input_error.h"
#include "rgb_surface.h"

namespace acro::ui {
namespace {

constexpr int kMaxSidePx = 8192;

// Type sizes (px) and spacing of the layout.
constexpr double kTitleSize = 15.0;
constexpr double kLabelSize = 13.0;
constexpr double kTickSize = 11.5;
constexpr double kLegendSize = 12.0;
constexpr double kPad = 10.0;        // outer margin
constexpr double kGap = 6.0;         // between a text and what it labels
constexpr double kTickLen = 5.0;     // tick marks outside the plot area
constexpr double kSwatchLen = 24.0;  // legend line sample
constexpr double kLegendRow = 17.0;
constexpr const char* kFontFamily = "DejaVu Sans";

// --- Validation -----------------------------------------------------------------------------

// "series 2 'COM height'" for error messages.
std::string Describe(std::string_view kind, std::size_t index, const std::string& name) {
  std::string out = fmt::format("{} {}", kind, index);
  if (!name.empty()) out += fmt::format(" '{}'", name);
  return out;
}

bool Fail(std::string* why, const std::string& message) {
  if (why) *why = message;
  return false;
}

bool ColorIsValid(const Rgb& c) {
  const auto ok = [](double v) { return v >= 0.0 && v <= 1.0; };
  return ok(c.r) && ok(c.g) && ok(c.b);
}

bool RangeIsValid(const ValueRange& range) {
  return std::isfinite(range.min) && std::isfinite(range.max) && range.min < range.max;
}

std::string ChartName(const Chart& chart) {
  return chart.title.empty() ? "chart" : "chart '" + chart.title + "'";
}

// Throws InputError for an invalid chart.
void DemandValid(const Chart& chart) {
  std::string why;
  if (!chart.IsValid(&why)) throw InputError(ChartName(chart), "", why);
}

// --- Axes -----------------------------------------------------------------------------------

// The x and y extents of everything drawn, before padding. Empty extents stay at ±infinity.
struct Extent {
  double min = std::numeric_limits<double>::infinity();
  double max = -std::numeric_limits<double>::infinity();
  void Add(double v) {
    if (!std::isfinite(v)) return;
    min = std::min(min, v);
    max = std::max(max, v);
  }
  bool empty() const { return !(min <= max); }
};

// The axis range for an extent: a fixed range when given, else the extent widened by `pad` of its
// span on each side (a flat extent gets a span of its own size, or 1).
ValueRange AxisRange(const std::optional<ValueRange>& fixed, Extent extent, double pad) {
  if (fixed) return *fixed;
  if (extent.empty()) return {0.0, 1.0};
  double span = extent.max - extent.min;
  if (span <= 0.0) {
    span = std::abs(extent.min) > 0.0 ? std::abs(extent.min) : 1.0;
    return {extent.min - 0.5 * span, extent.max + 0.5 * span};
  }
  return {extent.min - pad * span, extent.max + pad * span};
}

// Round tick values over a range: a step of 1, 2 or 5 × 10^k giving about `target` intervals, and
// the number of decimals that writes every tick exactly.
struct Ticks {
  std::vector<double> values;
  int decimals = 0;
};

Ticks MakeTicks(const ValueRange& range, double target) {
  Ticks ticks;
  const double raw = (range.max - range.min) / std::max(target, 1.0);
  const double magnitude = std::pow(10.0, std::floor(std::log10(raw)));
  double step = 10.0 * magnitude;
  for (double m : {1.0, 2.0, 5.0, 10.0}) {
    if (m * magnitude >= raw) {
      step = m * magnitude;
      break;
    }
  }
  ticks.decimals = std::max(0, -static_cast<int>(std::floor(std::log10(step) + 1e-9)));
  const double first = std::ceil(range.min / step - 1e-9);
  for (double k = first;; k += 1.0) {
    const double v = k * step;
    if (v > range.max + 1e-9 * step) break;
    ticks.values.push_back(std::abs(v) < 1e-12 * step ? 0.0 : v);
    if (ticks.values.size() > 100) break;  // cannot happen with a finite range; a guard
  }
  return ticks;
}

// "−1.5": tick text with a true minus sign.
std::string TickText(double v, int decimals) {
  std::string s = fmt::format("{:.{}f}", v, decimals);
  if (!s.empty() && s[0] == '-') s = "\u2212" + s.substr(1);
  return s;
}

// --- Text -----------------------------------------------------------------------------------

void SetFont(cairo_t* cr, double size, bool bold = false) {
  cairo_select_font_face(cr,
                         kFontFamily,
                         CAIRO_FONT_SLANT_NORMAL,
                         bold ? CAIRO_FONT_WEIGHT_BOLD : CAIRO_FONT_WEIGHT_NORMAL);
  cairo_set_font_size(cr, size);
}

double TextWidth(cairo_t* cr, const std::string& text) {
  cairo_text_extents_t extents;
  cairo_text_extents(cr, text.c_str(), &extents);
  return extents.x_advance;
}

// Draws `text` with its baseline at y and its anchor (0 left, 0.5 centre, 1 right) at x.
void DrawText(cairo_t* cr, const std::string& text, double x, double y, double anchor) {
  cairo_move_to(cr, x - anchor * TextWidth(cr, text), y);
  cairo_show_text(cr, text.c_str());
}

// --- Legend ---------------------------------------------------------------------------------

struct LegendEntry {
  enum class Kind { kLine, kBand } kind = Kind::kLine;
  std::string label;
  Rgb color;
  double alpha = 1.0;
  double width_px = 2.0;
  bool dashed = false;
  bool markers = false;
  bool line = true;
};

std::vector<LegendEntry> LegendEntries(const Chart& chart) {
  std::vector<LegendEntry> entries;
  if (!chart.show_legend) return entries;
  for (const LineSeries& s : chart.series) {
    if (s.name.empty()) continue;
    entries.push_back(
        {LegendEntry::Kind::kLine, s.name, s.color, 1.0, s.width_px, s.dashed, s.markers, s.line});
  }
  for (const ReferenceLine& r : chart.reference_lines) {
    if (r.label.empty()) continue;
    entries.push_back(
        {LegendEntry::Kind::kLine, r.label, r.color, 1.0, 1.5, r.dashed, false, true});
  }
  std::set<std::string> seen;
  for (const ShadedInterval& b : chart.bands) {
    if (b.label.empty() || !seen.insert(b.label).second) continue;
    entries.push_back({LegendEntry::Kind::kBand,
                       b.label,
                       b.color,
                       std::max(b.alpha, 0.25),
                       0.0,
                       false,
                       false,
                       false});
  }
  return entries;
}

// True when the segment (x0, y0)–(x1, y1) meets the rectangle (Liang–Barsky clipping).
bool SegmentMeetsRect(double x0,
                      double y0,
                      double x1,
                      double y1,
                      double left,
                      double top,
                      double right,
                      double bottom) {
  double t0 = 0.0, t1 = 1.0;
  const double dx = x1 - x0, dy = y1 - y0;
  const std::array<double, 4> p = {-dx, dx, -dy, dy};
  const std::array<double, 4> q = {x0 - left, right - x0, y0 - top, bottom - y0};
  for (int i = 0; i < 4; ++i) {
    if (p[i] == 0.0) {
      if (q[i] < 0.0) return false;
      continue;
    }
    const double t = q[i] / p[i];
    if (p[i] < 0.0) {
      t0 = std::max(t0, t);
    } else {
      t1 = std::min(t1, t);
    }
    if (t0 > t1) return false;
  }
  return true;
}

// --- Layout ---------------------------------------------------------------------------------

struct Mapping {
  ChartLayout layout;
  double X(double x) const {
    const ChartLayout& l = layout;
    return l.plot_left +
           (x - l.x_range.min) / (l.x_range.max - l.x_range.min) * (l.plot_right - l.plot_left);
  }
  double Y(double y) const {
    const ChartLayout& l = layout;
    return l.plot_bottom -
           (y - l.y_range.min) / (l.y_range.max - l.y_range.min) * (l.plot_bottom - l.plot_top);
  }
};

// True when anything drawn as data (series, reference lines) passes through the rectangle.
bool DataMeetsRect(const Chart& chart, const Mapping& m, double l, double t, double r, double b) {
  for (const LineSeries& s : chart.series) {
    bool have_previous = false;
    double px = 0.0, py = 0.0;
    for (std::size_t i = 0; i < s.x.size(); ++i) {
      if (!(std::isfinite(s.x[i]) && std::isfinite(s.y[i]))) {
        have_previous = false;
        continue;
      }
      const double x = m.X(s.x[i]), y = m.Y(s.y[i]);
      const double r_mark = s.markers ? 4.0 : 0.0;
      if (x + r_mark >= l && x - r_mark <= r && y + r_mark >= t && y - r_mark <= b) return true;
      if (s.line && have_previous && SegmentMeetsRect(px, py, x, y, l, t, r, b)) return true;
      px = x;
      py = y;
      have_previous = true;
    }
  }
  for (const ReferenceLine& ref : chart.reference_lines) {
    const double y = m.Y(ref.y);
    if (y >= t && y <= b) return true;
  }
  return false;
}

// Lays the chart out on a scratch Cairo context (for text measurement): margins from the text
// sizes, then the legend in the first plot corner that holds no data, else outside on the right.
ChartLayout Layout(cairo_t* cr, const Chart& chart) {
  // Axis ranges: fixed where asked, else the data's extent (y padded by 5 %).
  Extent x_extent, y_extent;
  for (const LineSeries& line : chart.series) {
    for (std::size_t i = 0; i < line.x.size(); ++i) {
      if (!std::isfinite(line.x[i]) || !std::isfinite(line.y[i])) continue;
      x_extent.Add(line.x[i]);
      y_extent.Add(line.y[i]);
    }
  }
  for (const ShadedInterval& band : chart.bands) {
    x_extent.Add(band.x0);
    x_extent.Add(band.x1);
  }
  for (const ReferenceLine& ref : chart.reference_lines) y_extent.Add(ref.y);
  Mapping m;
  ChartLayout& l = m.layout;
  l.x_range = AxisRange(chart.x_range, x_extent, 0.0);
  l.y_range = AxisRange(chart.y_range, y_extent, 0.05);

  // Margins around the plot area from the sizes of the texts around it.
  const double w = chart.width_px, h = chart.height_px;
  const Ticks y_ticks = MakeTicks(l.y_range, std::max(2.0, h / 70.0));
  SetFont(cr, kTickSize);
  double y_tick_width = 0.0;
  for (double v : y_ticks.values)
    y_tick_width = std::max(y_tick_width, TextWidth(cr, TickText(v, y_ticks.decimals)));
  l.plot_left =
      kPad + (chart.y_label.empty() ? 0.0 : kLabelSize + kGap) + y_tick_width + kGap + kTickLen;
  l.plot_top = kPad + (chart.title.empty() ? kTickSize / 2 : kTitleSize + 2 * kGap);
  l.plot_bottom =
      h - kPad - (chart.x_label.empty() ? 0.0 : kLabelSize + kGap) - kTickSize - kGap - kTickLen;
  l.plot_right = w - kPad - TextWidth(cr, "0") / 2;

  // The legend's size.
  const std::vector<LegendEntry> entries = LegendEntries(chart);
  if (entries.empty()) return l;
  SetFont(cr, kLegendSize);
  double text_width = 0.0;
  for (const LegendEntry& e : entries) text_width = std::max(text_width, TextWidth(cr, e.label));
  const double legend_w = 8.0 + kSwatchLen + 6.0 + text_width + 8.0;
  const double legend_h = 6.0 + kLegendRow * static_cast<double>(entries.size()) + 2.0;
  l.legend_drawn = true;

  // Inside: the first corner (top right, top left, bottom right, bottom left) free of data.
  const double inset = 6.0;
  const std::array<std::pair<bool, bool>, 4> corners = {
      {{true, true}, {false, true}, {true, false}, {false, false}}};
  if (legend_w + 2 * inset < l.plot_right - l.plot_left &&
      legend_h + 2 * inset < l.plot_bottom - l.plot_top) {
    for (const auto& [right, top] : corners) {
      const double left_px = right ? l.plot_right - inset - legend_w : l.plot_left + inset;
      const double top_px = top ? l.plot_top + inset : l.plot_bottom - inset - legend_h;
      if (!DataMeetsRect(chart, m, left_px, top_px, left_px + legend_w, top_px + legend_h)) {
        l.legend_inside = true;
        l.legend_left = left_px;
        l.legend_top = top_px;
        l.legend_right = left_px + legend_w;
        l.legend_bottom = top_px + legend_h;
        return l;
      }
    }
  }
  // Outside on the right, when that leaves the plot at least half the width.
  if (l.plot_right - legend_w - kGap - l.plot_left > 0.5 * w) {
    l.plot_right -= legend_w + kGap;
    l.legend_left = l.plot_right + kGap;
    l.legend_top = l.plot_top;
  } else {
    // Below the plot, when the chart is too narrow for a legend beside it.
    l.plot_bottom -= legend_h + kGap;
    l.legend_left = l.plot_left;
    l.legend_top = h - kPad - legend_h;
  }
  l.legend_right = l.legend_left + legend_w;
  l.legend_bottom = l.legend_top + legend_h;
  return l;
}

// --- Drawing --------------------------------------------------------------------------------

void SetColor(cairo_t* cr, const Rgb& c, double alpha = 1.0) {
  cairo_set_source_rgba(cr, c.r, c.g, c.b, alpha);
}

void SetDash(cairo_t* cr, bool dashed, double width) {
  if (dashed) {
    const double pattern[2] = {std::max(6.0, 3.0 * width), std::max(4.0, 2.0 * width)};
    cairo_set_dash(cr, pattern, 2, 0.0);
  } else {
    cairo_set_dash(cr, nullptr, 0, 0.0);
  }
}

void DrawSeries(cairo_t* cr, const LineSeries& s, const Mapping& m) {
  SetColor(cr, s.color);
  cairo_set_line_width(cr, s.width_px);
  cairo_set_line_join(cr, CAIRO_LINE_JOIN_ROUND);
  SetDash(cr, s.dashed, s.width_px);
  // Each run of finite points is its own path: a NaN breaks the line.
  if (s.line) {
    bool open = false;
    for (std::size_t i = 0; i < s.x.size(); ++i) {
      const bool finite = std::isfinite(s.x[i]) && std::isfinite(s.y[i]);
      if (!finite) {
        open = false;
        continue;
      }
      if (open) {
        cairo_line_to(cr, m.X(s.x[i]), m.Y(s.y[i]));
      } else {
        cairo_move_to(cr, m.X(s.x[i]), m.Y(s.y[i]));
        open = true;
      }
    }
    cairo_stroke(cr);
  }
  if (s.markers) {
    for (std::size_t i = 0; i < s.x.size(); ++i) {
      if (!(std::isfinite(s.x[i]) && std::isfinite(s.y[i]))) continue;
      cairo_new_sub_path(cr);
      cairo_arc(cr, m.X(s.x[i]), m.Y(s.y[i]), std::max(3.0, 1.6 * s.width_px), 0.0, 2 * M_PI);
    }
    cairo_fill(cr);
  }
}

void DrawLegend(cairo_t* cr, const Chart& chart, const ChartLayout& l) {
  const std::vector<LegendEntry> entries = LegendEntries(chart);
  cairo_set_dash(cr, nullptr, 0, 0.0);
  cairo_rectangle(cr,
                  l.legend_left,
                  l.legend_top,
                  l.legend_right - l.legend_left,
                  l.legend_bottom - l.legend_top);
  cairo_set_source_rgba(cr, 1.0, 1.0, 1.0, 0.9);
  cairo_fill_preserve(cr);
  cairo_set_source_rgb(cr, 0.75, 0.75, 0.75);
  cairo_set_line_width(cr, 1.0);
  cairo_stroke(cr);
  SetFont(cr, kLegendSize);
  for (std::size_t k = 0; k < entries.size(); ++k) {
    const LegendEntry& e = entries[k];
    const double row_mid = l.legend_top + 6.0 + kLegendRow * (static_cast<double>(k) + 0.5);
    const double x0 = l.legend_left + 8.0;
    if (e.kind == LegendEntry::Kind::kBand) {
      SetColor(cr, e.color, e.alpha);
      cairo_rectangle(cr, x0, row_mid - 5.0, kSwatchLen, 10.0);
      cairo_fill(cr);
    } else {
      SetColor(cr, e.color);
      if (e.line) {
        cairo_set_line_width(cr, e.width_px);
        SetDash(cr, e.dashed, e.width_px);
        cairo_move_to(cr, x0, row_mid);
        cairo_line_to(cr, x0 + kSwatchLen, row_mid);
        cairo_stroke(cr);
        cairo_set_dash(cr, nullptr, 0, 0.0);
      }
      if (e.markers) {
        cairo_arc(cr, x0 + kSwatchLen / 2, row_mid, 3.5, 0.0, 2 * M_PI);
        cairo_fill(cr);
      }
    }
    cairo_set_source_rgb(cr, 0.1, 0.1, 0.1);
    DrawText(cr, e.label, x0 + kSwatchLen + 6.0, row_mid + 0.35 * kLegendSize, 0.0);
  }
}

// The whole chart on `cr`, whatever surface it draws on.
void Draw(cairo_t* cr, const Chart& chart, const ChartLayout& layout) {
  const Mapping m{layout};
  const ChartLayout& l = layout;
  const double w = chart.width_px, h = chart.height_px;
  cairo_set_source_rgb(cr, 1.0, 1.0, 1.0);
  cairo_paint(cr);

  // Inside the plot area: bands, grid, reference lines, series, clipped to it.
  cairo_save(cr);
  cairo_rectangle(
      cr, l.plot_left, l.plot_top, l.plot_right - l.plot_left, l.plot_bottom - l.plot_top);
  cairo_clip(cr);
  for (const ShadedInterval& band : chart.bands) {
    SetColor(cr, band.color, band.alpha);
    cairo_rectangle(
        cr, m.X(band.x0), l.plot_top, m.X(band.x1) - m.X(band.x0), l.plot_bottom - l.plot_top);
    cairo_fill(cr);
  }
  const Ticks x_ticks = MakeTicks(l.x_range, std::max(2.0, (l.plot_right - l.plot_left) / 90.0));
  const Ticks y_ticks = MakeTicks(l.y_range, std::max(2.0, h / 70.0));
  cairo_set_source_rgb(cr, 0.88, 0.88, 0.88);
  cairo_set_line_width(cr, 1.0);
  for (double v : y_ticks.values) {
    const double y = std::round(m.Y(v)) + 0.5;
    cairo_move_to(cr, l.plot_left, y);
    cairo_line_to(cr, l.plot_right, y);
  }
  cairo_stroke(cr);
  for (const ReferenceLine& ref : chart.reference_lines) {
    SetColor(cr, ref.color);
    cairo_set_line_width(cr, 1.5);
    SetDash(cr, ref.dashed, 1.5);
    cairo_move_to(cr, l.plot_left, m.Y(ref.y));
    cairo_line_to(cr, l.plot_right, m.Y(ref.y));
    cairo_stroke(cr);
  }
  for (const LineSeries& s : chart.series) DrawSeries(cr, s, m);
  cairo_restore(cr);

  // Frame, ticks and their labels.
  cairo_set_dash(cr, nullptr, 0, 0.0);
  cairo_set_source_rgb(cr, 0.2, 0.2, 0.2);
  cairo_set_line_width(cr, 1.0);
  cairo_rectangle(cr,
                  std::round(l.plot_left) + 0.5,
                  std::round(l.plot_top) + 0.5,
                  std::round(l.plot_right) - std::round(l.plot_left),
                  std::round(l.plot_bottom) - std::round(l.plot_top));
  cairo_stroke(cr);
  SetFont(cr, kTickSize);
  for (double v : x_ticks.values) {
    const double x = std::round(m.X(v)) + 0.5;
    cairo_move_to(cr, x, l.plot_bottom);
    cairo_line_to(cr, x, l.plot_bottom + kTickLen);
    cairo_stroke(cr);
    DrawText(
        cr, TickText(v, x_ticks.decimals), x, l.plot_bottom + kTickLen + kGap / 2 + kTickSize, 0.5);
  }
  for (double v : y_ticks.values) {
    const double y = std::round(m.Y(v)) + 0.5;
    cairo_move_to(cr, l.plot_left - kTickLen, y);
    cairo_line_to(cr, l.plot_left, y);
    cairo_stroke(cr);
    DrawText(cr,
             TickText(v, y_ticks.decimals),
             l.plot_left - kTickLen - kGap / 2,
             y + 0.35 * kTickSize,
             1.0);
  }

  // Axis labels and the title.
  cairo_set_source_rgb(cr, 0.1, 0.1, 0.1);
  SetFont(cr, kLabelSize);
  if (!chart.x_label.empty()) {
    const double baseline = l.plot_bottom + kTickLen + kGap + kTickSize + kGap + kLabelSize;
    DrawText(cr, chart.x_label, 0.5 * (l.plot_left + l.plot_right), baseline, 0.5);
  }
  if (!chart.y_label.empty()) {
    cairo_save(cr);
    cairo_translate(cr, kPad + kLabelSize - 2.0, 0.5 * (l.plot_top + l.plot_bottom));
    cairo_rotate(cr, -M_PI / 2);
    DrawText(cr, chart.y_label, 0.0, 0.0, 0.5);
    cairo_restore(cr);
  }
  if (!chart.title.empty()) {
    SetFont(cr, kTitleSize, true);
    DrawText(cr, chart.title, 0.5 * w, kPad + kTitleSize, 0.5);
  }
  if (l.legend_drawn) DrawLegend(cr, chart, l);
}

// Owners for Cairo objects.
struct SurfaceDeleter {
  void operator()(cairo_surface_t* s) const { cairo_surface_destroy(s); }
};
struct ContextDeleter {
  void operator()(cairo_t* c) const { cairo_destroy(c); }
};
using Surface = std::unique_ptr<cairo_surface_t, SurfaceDeleter>;
using Context = std::unique_ptr<cairo_t, ContextDeleter>;

void DemandOk(cairo_status_t status, const Chart& chart, const char* what) {
  if (status != CAIRO_STATUS_SUCCESS) {
    throw std::runtime_error(
        fmt::format("{}: {} failed: {}", ChartName(chart), what, cairo_status_to_string(status)));
  }
}

// Cairo's stream writers append to a byte string.
cairo_status_t AppendBytes(void* closure, const unsigned char* data, unsigned int length) {
  static_cast<std::string*>(closure)->append(reinterpret_cast<const char*>(data), length);
  return CAIRO_STATUS_SUCCESS;
}

// A context on a 1×1 image surface, for measuring text.
Context MakeScratchContext() {
  Surface scratch(cairo_image_surface_create(CAIRO_FORMAT_RGB24, 1, 1));
  return Context(cairo_create(scratch.get()));  // the context keeps its own reference
}

// The chart drawn on an RGB24 image surface of its size.
Surface DrawImage(const Chart& chart) {
  DemandValid(chart);
  const ChartLayout layout = Layout(MakeScratchContext().get(), chart);
  Surface surface(cairo_image_surface_create(CAIRO_FORMAT_RGB24, chart.width_px, chart.height_px));
  DemandOk(cairo_surface_status(surface.get()), chart, "creating the image");
  {
    Context cr(cairo_create(surface.get()));
    Draw(cr.get(), chart, layout);
    DemandOk(cairo_status(cr.get()), chart, "drawing");
  }
  return surface;
}

std::string RenderPngString(const Chart& chart) {
  const Surface surface = DrawImage(chart);
  std::string png;
  DemandOk(
      cairo_surface_write_to_png_stream(surface.get(), AppendBytes, &png), chart, "PNG encoding");
  return png;
}

}  // namespace

bool Chart::IsValid(std::string* why) const {
  // Sizes.
  if (width_px < 16 || height_px < 16 || width_px > kMaxSidePx || height_px > kMaxSidePx) {
    return Fail(why,
                fmt::format("size {}x{} px is outside 16..{}", width_px, height_px, kMaxSidePx));
  }
  // Series: equal lengths, sane styles, and something to draw.
  if (series.empty()) return Fail(why, "no series: nothing to draw");
  bool any_point = false;
  for (std::size_t s = 0; s < series.size(); ++s) {
    const LineSeries& line = series[s];
    const std::string where = Describe("series", s, line.name);
    if (line.x.size() != line.y.size()) {
      return Fail(
          why,
          fmt::format("{}: x has {} values but y has {}", where, line.x.size(), line.y.size()));
    }
    if (!ColorIsValid(line.color))
      return Fail(why, where + ": colour components must be in [0, 1]");
    if (!(line.width_px > 0.0 && line.width_px <= 100.0))
      return Fail(why, fmt::format("{}: width {} px not in (0, 100]", where, line.width_px));
    if (!line.line && !line.markers)
      return Fail(why, where + ": neither line nor markers: nothing to draw");
    for (std::size_t i = 0; i < line.x.size(); ++i) {
      if (std::isfinite(line.x[i]) && std::isfinite(line.y[i])) any_point = true;
    }
  }
  if (!any_point) return Fail(why, "no series has a finite point: nothing to draw");
  // Bands and reference lines.
  for (std::size_t b = 0; b < bands.size(); ++b) {
    const ShadedInterval& band = bands[b];
    const std::string where = Describe("band", b, band.label);
    if (!(std::isfinite(band.x0) && std::isfinite(band.x1) && band.x0 <= band.x1)) {
      return Fail(
          why,
          fmt::format("{}: x0 {} and x1 {} must be finite with x0 <= x1", where, band.x0, band.x1));
    }
    if (!ColorIsValid(band.color))
      return Fail(why, where + ": colour components must be in [0, 1]");
    if (!(band.alpha >= 0.0 && band.alpha <= 1.0))
      return Fail(why, fmt::format("{}: alpha {} not in [0, 1]", where, band.alpha));
  }
  for (std::size_t r = 0; r < reference_lines.size(); ++r) {
    const ReferenceLine& ref = reference_lines[r];
    const std::string where = Describe("reference line", r, ref.label);
    if (!std::isfinite(ref.y)) return Fail(why, where + ": y is not finite");
    if (!ColorIsValid(ref.color)) return Fail(why, where + ": colour components must be in [0, 1]");
  }
  // Fixed ranges.
  if (y_range && !RangeIsValid(*y_range)) return Fail(why, "y_range must be finite with min < max");
  if (x_range && !RangeIsValid(*x_range)) return Fail(why, "x_range must be finite with min < max");
  return true;
}

ChartLayout MakeChartLayout(const Chart& chart) {
  DemandValid(chart);
  return Layout(MakeScratchContext().get(), chart);
}

std::vector<std::uint8_t> RenderChartPng(const Chart& chart) {
  const std::string png = RenderPngString(chart);
  return std::vector<std::uint8_t>(png.begin(), png.end());
}

std::vector<std::uint8_t> RenderChartRgb(const Chart& chart) {
  const Surface surface = DrawImage(chart);
  std::vector<std::uint8_t> rgb;
  internal::RgbFromSurface(surface.get(), &rgb);
  return rgb;
}

std::string RenderChartSvg(const Chart& chart) {
  DemandValid(chart);
  const ChartLayout layout = Layout(MakeScratchContext().get(), chart);
  std::string svg;
  {
    Surface surface(
        cairo_svg_surface_create_for_stream(AppendBytes, &svg, chart.width_px, chart.height_px));
    DemandOk(cairo_surface_status(surface.get()), chart, "creating the SVG");
    // Pixel units, so that the SVG opens at the size of the PNG.
    cairo_svg_surface_set_document_unit(surface.get(), CAIRO_SVG_UNIT_PX);
    {
      Context cr(cairo_create(surface.get()));
      Draw(cr.get(), chart, layout);
      DemandOk(cairo_status(cr.get()), chart, "drawing");
    }
    cairo_surface_finish(surface.get());
    DemandOk(cairo_surface_status(surface.get()), chart, "SVG writing");
  }
  return svg;
}

std::string FormatChartCsv(const Chart& chart) {
  std::string out = "series,x,y\n";
  for (const LineSeries& s : chart.series) {
    std::string name = s.name;
    if (name.find_first_of(",\"\n") != std::string::npos) {
      std::string quoted = "\"";
      for (const char c : name) quoted += c == '"' ? std::string("\"\"") : std::string(1, c);
      name = quoted + "\"";
    }
    for (size_t k = 0; k < s.x.size() && k < s.y.size(); ++k) {
      if (!std::isfinite(s.y[k])) continue;  // gaps (NaN) are left out
      out += name + "," + fmt::format("{:.9g},{:.9g}", s.x[k], s.y[k]) + "\n";
    }
  }
  return out;
}

void WriteChart(const Chart& chart, const std::filesystem::path& path) {
  const std::string ext = LowerExtension(path);
  if (ext == "png") {
    WriteFileAtomically(path, RenderPngString(chart));
  } else if (ext == "svg") {
    WriteFileAtomically(path, RenderChartSvg(chart));
  } else if (ext == "csv") {
    WriteFileAtomically(path, FormatChartCsv(chart));
  } else {
    throw InputError(
        path.string(), "", "a chart is written as .png, .svg or .csv, not '." + ext + "'");
  }
}

}  // namespace acro::ui
