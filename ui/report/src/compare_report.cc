#include "acro/report/compare_report.h"

#include <cstring>

#include "acro/report/chart.h"

namespace acro::ui {

namespace {

constexpr Rgb kColourA{0.85, 0.45, 0.2};  // the first jump: warm, as its athlete is drawn
constexpr Rgb kColourB{0.15, 0.45, 0.9};  // the second: the blue of the ghost

LineSeries Line(std::string name,
                const std::vector<double>& x,
                const std::vector<double>& y,
                Rgb colour,
                bool dashed) {
  LineSeries s;
  s.name = std::move(name);
  s.x = x;
  s.y = y;
  s.color = colour;
  s.dashed = dashed;
  return s;
}

}  // namespace

analysis::TimedPanel MakeCompareCharts(const analysis::JumpCurves& a,
                                       const analysis::JumpCurves& b,
                                       const std::string& label_a,
                                       const std::string& label_b,
                                       double start_s,
                                       double end_s,
                                       int width,
                                       int height) {
  Chart com;
  com.title = "Centre of mass height";
  com.x_label = "time from take-off (s)";
  com.y_label = "height (m)";
  com.series.push_back(Line(label_a, a.tau_s, a.com_height_m, kColourA, false));
  com.series.push_back(Line(label_b, b.tau_s, b.com_height_m, kColourB, false));
  Chart angles;
  angles.title = "Somersault (solid) and twist (dashed)";
  angles.x_label = "time from take-off (s)";
  angles.y_label = "degrees";
  angles.series.push_back(Line(label_a, a.tau_s, a.somersault_deg, kColourA, false));
  angles.series.push_back(Line(label_b, b.tau_s, b.somersault_deg, kColourB, false));
  angles.series.push_back(Line("", a.tau_s, a.twist_deg, kColourA, true));
  angles.series.push_back(Line("", b.tau_s, b.twist_deg, kColourB, true));
  analysis::TimedPanel out;
  out.width = width - width % 2;
  out.height = height;
  out.start_s = start_s;
  out.end_s = end_s;
  out.rgb.assign(size_t(out.width) * size_t(height) * 3, 255);
  int x0 = 0;
  for (Chart* c : {&com, &angles}) {
    c->width_px = out.width / 2;
    c->height_px = height;
    c->x_range = ValueRange{start_s, end_s};
    const ChartLayout layout = MakeChartLayout(*c);
    const std::vector<std::uint8_t> rgb = RenderChartRgb(*c);
    for (int y = 0; y < height; ++y)
      std::memcpy(out.rgb.data() + (size_t(y) * size_t(out.width) + size_t(x0)) * 3,
                  rgb.data() + size_t(y) * size_t(c->width_px) * 3,
                  size_t(c->width_px) * 3);
    out.cursor_spans_px.push_back(
        {x0 + layout.plot_left, x0 + layout.plot_right, layout.plot_top, layout.plot_bottom});
    x0 += c->width_px;
  }
  return out;
}

}  // namespace acro::ui
