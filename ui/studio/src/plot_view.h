#pragma once

// A chart of the trial linked to the cursor (the studio's plots): drawn by the reports' chart
// renderer (ui/report, Cairo) at the widget's size, the cursor a red line at its time; a click
// asks for the cursor at the time under it. Exports what it shows as PNG, SVG or CSV.

#include <QImage>
#include <QWidget>

#include <optional>
#include <string>

#include "acro/report/chart.h"

namespace acro::studio {

class PlotView : public QWidget {
  Q_OBJECT

 public:
  explicit PlotView(QWidget* parent = nullptr);

  void SetChart(const ui::Chart& chart);
  const ui::Chart& chart() const { return chart_; }
  /// The cursor's time (s), drawn as a red line.
  void SetCursorTime(double t_s);
  /// The time (s) under pixel column x of the widget (the chart's x axis as drawn), if x is over
  /// the plot.
  std::optional<double> TimeAt(int x) const;
  /// The pixel column of time t (s), −1 before any drawing.
  int XOf(double t_s) const;
  /// Writes the chart as shown: .png, .svg or .csv by the extension. Throws acro::InputError.
  void Export(const std::string& path) const;

  QSize sizeHint() const override { return {640, 260}; }

 Q_SIGNALS:
  void timeRequested(double t_s);

 protected:
  void paintEvent(QPaintEvent* event) override;
  void resizeEvent(QResizeEvent* event) override;
  void mousePressEvent(QMouseEvent* event) override;

 private:
  void Draw();

  ui::Chart chart_;
  bool has_chart_ = false;
  QImage image_;
  ui::ChartLayout layout_;
  double cursor_s_ = 0.0;
};

}  // namespace acro::studio
