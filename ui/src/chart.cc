#include "acro/ui/chart.h"

#include <vtkAutoInit.h>
#include <vtkAxis.h>
#include <vtkBrush.h>
#include <vtkCallbackCommand.h>
#include <vtkChartLegend.h>
#include <vtkChartXY.h>
#include <vtkContextScene.h>
#include <vtkContextView.h>
#include <vtkDoubleArray.h>
#include <vtkImageData.h>
#include <vtkNew.h>
#include <vtkPNGWriter.h>
#include <vtkPen.h>
#include <vtkPlotArea.h>
#include <vtkPlotLine.h>
#include <vtkRenderWindow.h>
#include <vtkRenderer.h>
#include <vtkSmartPointer.h>
#include <vtkTable.h>
#include <vtkTextProperty.h>
#include <vtkUnsignedCharArray.h>
#include <vtkWindowToImageFilter.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <set>
#include <stdexcept>
#include <string_view>

#include "acro/base/input_error.h"
#include "acro/capture/file_io.h"

// The object factories that give vtkRenderWindow and the 2D context their OpenGL implementations,
// and text rendering. Registered here because the library is not built with vtk_module_autoinit.
VTK_MODULE_INIT(vtkRenderingOpenGL2);
VTK_MODULE_INIT(vtkRenderingContextOpenGL2);
VTK_MODULE_INIT(vtkRenderingFreeType);
VTK_MODULE_INIT(vtkInteractionStyle);

namespace acro::ui {
namespace {

constexpr int kMaxSidePx = 8192;
// zlib level for the PNGs: charts are mostly flat colour, so a fast level loses little size.
constexpr int kPngCompressionLevel = 1;

// "series 2 'COM height'" for error messages.
std::string Describe(std::string_view kind, std::size_t index, const std::string& name) {
  std::string out = std::string(kind) + " " + std::to_string(index);
  if (!name.empty()) out += " '" + name + "'";
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

// A two-column-or-more table of doubles named `names`, one row per entry of the columns.
vtkSmartPointer<vtkTable> MakeTable(const std::vector<std::string>& names,
                                    const std::vector<std::vector<double>>& columns) {
  auto table = vtkSmartPointer<vtkTable>::New();
  for (std::size_t c = 0; c < names.size(); ++c) {
    vtkNew<vtkDoubleArray> array;
    array->SetName(names[c].c_str());
    array->SetNumberOfValues(static_cast<vtkIdType>(columns[c].size()));
    for (std::size_t i = 0; i < columns[c].size(); ++i) {
      array->SetValue(static_cast<vtkIdType>(i), columns[c][i]);
    }
    table->AddColumn(array);
  }
  return table;
}

// Adds one line plot of (x, y) to `chart`; `label` empty hides it from the legend.
void AddLine(vtkChartXY& chart,
             std::vector<double> x,
             std::vector<double> y,
             const Rgb& color,
             double width_px,
             bool dashed,
             const std::string& label) {
  vtkSmartPointer<vtkTable> table = MakeTable({"x", "y"}, {std::move(x), std::move(y)});
  vtkNew<vtkPlotLine> line;
  line->SetInputData(table, 0, 1);
  line->SetColor(color.r, color.g, color.b);
  line->SetWidth(static_cast<float>(width_px));
  line->GetPen()->SetLineType(dashed ? vtkPen::DASH_LINE : vtkPen::SOLID_LINE);
  line->SetPolyLine(true);
  line->SetLabel(label);
  line->SetLegendVisibility(!label.empty());
  chart.AddPlot(line);
}

// Splits a series at its non-finite points into runs of at least one finite point each, so that a
// NaN breaks the line rather than being joined across.
std::vector<std::pair<std::size_t, std::size_t>> FiniteRuns(const LineSeries& series) {
  std::vector<std::pair<std::size_t, std::size_t>> runs;
  std::size_t i = 0;
  const std::size_t n = series.x.size();
  while (i < n) {
    while (i < n && !(std::isfinite(series.x[i]) && std::isfinite(series.y[i]))) ++i;
    const std::size_t begin = i;
    while (i < n && std::isfinite(series.x[i]) && std::isfinite(series.y[i])) ++i;
    if (i > begin) runs.emplace_back(begin, i);
  }
  return runs;
}

// Collects VTK error events of the objects it observes, instead of letting VTK print them.
class ErrorCollector {
 public:
  ErrorCollector() {
    callback_->SetClientData(this);
    callback_->SetCallback([](vtkObject*, unsigned long, void* client, void* call) {
      auto* self = static_cast<ErrorCollector*>(client);
      if (self->message_.empty()) {
        self->message_ = call ? static_cast<const char*>(call) : "unknown VTK error";
      }
    });
  }
  void Observe(vtkObject* object) { object->AddObserver(vtkCommand::ErrorEvent, callback_); }
  // Throws with the first collected error, prefixed by `what`, and clears it.
  void ThrowIfAny(const std::string& what) {
    if (message_.empty()) return;
    std::string message = std::move(message_);
    message_.clear();
    while (!message.empty() && (message.back() == '\n' || message.back() == ' ')) {
      message.pop_back();
    }
    throw std::runtime_error(what + ": " + message);
  }

 private:
  vtkNew<vtkCallbackCommand> callback_;
  std::string message_;
};

}  // namespace

bool Chart::IsValid(std::string* why) const {
  // Sizes.
  if (width_px < 16 || height_px < 16 || width_px > kMaxSidePx || height_px > kMaxSidePx) {
    return Fail(why,
                "size " + std::to_string(width_px) + "x" + std::to_string(height_px) +
                    " px is outside 16.." + std::to_string(kMaxSidePx));
  }
  // Series: equal lengths, sane styles, and something to draw.
  if (series.empty()) return Fail(why, "no series: nothing to draw");
  bool any_point = false;
  for (std::size_t s = 0; s < series.size(); ++s) {
    const LineSeries& line = series[s];
    const std::string where = Describe("series", s, line.name);
    if (line.x.size() != line.y.size()) {
      return Fail(why,
                  where + ": x has " + std::to_string(line.x.size()) + " values but y has " +
                      std::to_string(line.y.size()));
    }
    if (!ColorIsValid(line.color))
      return Fail(why, where + ": colour components must be in [0, 1]");
    if (!(line.width_px > 0.0 && line.width_px <= 100.0)) {
      return Fail(why, where + ": width " + std::to_string(line.width_px) + " px not in (0, 100]");
    }
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
      return Fail(why,
                  where + ": x0 " + std::to_string(band.x0) + " and x1 " + std::to_string(band.x1) +
                      " must be finite with x0 <= x1");
    }
    if (!ColorIsValid(band.color))
      return Fail(why, where + ": colour components must be in [0, 1]");
    if (!(band.alpha >= 0.0 && band.alpha <= 1.0)) {
      return Fail(why, where + ": alpha " + std::to_string(band.alpha) + " not in [0, 1]");
    }
  }
  for (std::size_t r = 0; r < reference_lines.size(); ++r) {
    const ReferenceLine& ref = reference_lines[r];
    const std::string where = Describe("reference line", r, ref.label);
    if (!std::isfinite(ref.y)) return Fail(why, where + ": y is not finite");
    if (!ColorIsValid(ref.color)) return Fail(why, where + ": colour components must be in [0, 1]");
  }
  // Fixed ranges.
  if (y_range && !RangeIsValid(*y_range)) {
    return Fail(why, "y_range must be finite with min < max");
  }
  if (x_range && !RangeIsValid(*x_range)) {
    return Fail(why, "x_range must be finite with min < max");
  }
  return true;
}

namespace {

// Throws InputError for the first invalid chart, before any window is made.
void DemandValid(const Chart& chart) {
  std::string why;
  if (!chart.IsValid(&why)) {
    throw InputError(chart.title.empty() ? "chart" : "chart '" + chart.title + "'", "", why);
  }
}

}  // namespace

struct ChartRenderer::Impl {
  vtkNew<vtkContextView> view;
  ErrorCollector errors;
};

ChartRenderer::ChartRenderer() {
  // Never create a VTK window where it would abort the process.
  const RenderingStatus status = OffscreenRenderingStatus();
  if (!status.available) throw RenderingUnavailable("cannot render charts: " + status.reason);
  impl_ = std::make_unique<Impl>();
  vtkRenderWindow* window = impl_->view->GetRenderWindow();
  // No interactor: nothing is interactive offscreen, and VTK's X interactor would open and sync a
  // display connection of its own on the first Render().
  window->SetInteractor(nullptr);
  window->SetOffScreenRendering(1);
  window->SetMultiSamples(0);
  impl_->view->GetRenderer()->SetBackground(1.0, 1.0, 1.0);
  impl_->errors.Observe(window);
}

ChartRenderer::~ChartRenderer() = default;

std::vector<std::uint8_t> ChartRenderer::RenderPngBytes(const Chart& chart) {
  DemandValid(chart);
  const std::string chart_name = chart.title.empty() ? "chart" : "chart '" + chart.title + "'";

  // Axis ranges: fixed where asked, else the data's extent (y padded by 5 %). Bands and reference
  // lines are drawn across exactly these ranges, so the axes are always fixed.
  Extent x_extent;
  Extent y_extent;
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
  const ValueRange x_range = AxisRange(chart.x_range, x_extent, 0.0);
  const ValueRange y_range = AxisRange(chart.y_range, y_extent, 0.05);

  // A fresh chart item in the reused view (the window and its OpenGL context are the costly part).
  vtkNew<vtkChartXY> xy;
  xy->SetTitle(chart.title);
  xy->GetTitleProperties()->SetFontSize(14);
  xy->SetShowLegend(chart.show_legend);
  xy->SetAutoSize(true);
  vtkAxis* bottom = xy->GetAxis(vtkAxis::BOTTOM);
  vtkAxis* left = xy->GetAxis(vtkAxis::LEFT);
  bottom->SetTitle(chart.x_label);
  left->SetTitle(chart.y_label);
  bottom->SetBehavior(vtkAxis::FIXED);
  left->SetBehavior(vtkAxis::FIXED);
  bottom->SetRange(x_range.min, x_range.max);
  left->SetRange(y_range.min, y_range.max);
  bottom->SetGridVisible(false);

  // Bands first (drawn behind), as filled areas between the y axis limits; one legend entry per
  // distinct label.
  std::set<std::string> labelled;
  for (const ShadedInterval& band : chart.bands) {
    // Three samples, not two: vtkPlotArea 9.1 paints its quad strip only when it has more than four
    // points (two per sample), so a two-sample band would silently not be drawn.
    const double mid = 0.5 * (band.x0 + band.x1);
    vtkSmartPointer<vtkTable> table = MakeTable({"x", "low", "high"},
                                                {{band.x0, mid, band.x1},
                                                 {y_range.min, y_range.min, y_range.min},
                                                 {y_range.max, y_range.max, y_range.max}});
    vtkNew<vtkPlotArea> area;
    area->SetInputData(table);
    area->SetInputArray(0, "x");
    area->SetInputArray(1, "low");
    area->SetInputArray(2, "high");
    area->GetBrush()->SetColorF(band.color.r, band.color.g, band.color.b, band.alpha);
    area->GetPen()->SetLineType(vtkPen::NO_PEN);
    const bool show = !band.label.empty() && labelled.insert(band.label).second;
    area->SetLabel(band.label);
    area->SetLegendVisibility(show);
    xy->AddPlot(area);
  }

  // Reference lines across the x range, then the series, each finite run its own line.
  for (const ReferenceLine& ref : chart.reference_lines) {
    AddLine(*xy, {x_range.min, x_range.max}, {ref.y, ref.y}, ref.color, 1.5, ref.dashed, ref.label);
  }
  for (const LineSeries& line : chart.series) {
    bool first = true;
    for (const auto& [begin, end] : FiniteRuns(line)) {
      std::vector<double> x(line.x.begin() + begin, line.x.begin() + end);
      std::vector<double> y(line.y.begin() + begin, line.y.begin() + end);
      AddLine(*xy,
              std::move(x),
              std::move(y),
              line.color,
              line.width_px,
              line.dashed,
              first ? line.name : std::string());
      first = false;
    }
  }

  // Render offscreen at the requested size.
  vtkRenderWindow* window = impl_->view->GetRenderWindow();
  impl_->view->GetScene()->ClearItems();
  impl_->view->GetScene()->AddItem(xy);
  window->SetSize(chart.width_px, chart.height_px);
  impl_->view->Render();
  impl_->errors.ThrowIfAny(chart_name + ": rendering failed");

  // Read the back buffer and encode it as PNG in memory.
  vtkNew<vtkWindowToImageFilter> grab;
  impl_->errors.Observe(grab);
  grab->SetInput(window);
  grab->SetInputBufferTypeToRGB();
  grab->ReadFrontBufferOff();
  grab->Update();
  impl_->errors.ThrowIfAny(chart_name + ": reading the rendered image failed");
  int dims[3] = {0, 0, 0};
  grab->GetOutput()->GetDimensions(dims);
  if (dims[0] != chart.width_px || dims[1] != chart.height_px) {
    throw std::runtime_error(chart_name + ": rendered image is " + std::to_string(dims[0]) + "x" +
                             std::to_string(dims[1]) + " px, expected " +
                             std::to_string(chart.width_px) + "x" +
                             std::to_string(chart.height_px));
  }
  vtkNew<vtkPNGWriter> writer;
  impl_->errors.Observe(writer);
  writer->SetCompressionLevel(kPngCompressionLevel);
  writer->WriteToMemoryOn();
  writer->SetInputConnection(grab->GetOutputPort());
  writer->Write();
  impl_->errors.ThrowIfAny(chart_name + ": PNG encoding failed");
  vtkUnsignedCharArray* png = writer->GetResult();
  if (!png || png->GetNumberOfValues() == 0) {
    throw std::runtime_error(chart_name + ": PNG encoding produced no data");
  }
  const unsigned char* data = png->GetPointer(0);
  return std::vector<std::uint8_t>(data, data + png->GetNumberOfValues());
}

void ChartRenderer::RenderPng(const Chart& chart, const std::filesystem::path& path) {
  const std::vector<std::uint8_t> png = RenderPngBytes(chart);
  capture::WriteFileAtomically(
      path, std::string_view(reinterpret_cast<const char*>(png.data()), png.size()));
}

void RenderChartPng(const Chart& chart, const std::filesystem::path& path) {
  DemandValid(chart);
  ChartRenderer renderer;
  renderer.RenderPng(chart, path);
}

void RenderChartsPng(std::span<const Chart> charts, std::span<const std::filesystem::path> paths) {
  if (charts.size() != paths.size()) {
    throw std::invalid_argument("RenderChartsPng: " + std::to_string(charts.size()) +
                                " charts but " + std::to_string(paths.size()) + " paths");
  }
  for (const Chart& chart : charts) DemandValid(chart);
  if (charts.empty()) return;
  ChartRenderer renderer;
  for (std::size_t i = 0; i < charts.size(); ++i) renderer.RenderPng(charts[i], paths[i]);
}

}  // namespace acro::ui
