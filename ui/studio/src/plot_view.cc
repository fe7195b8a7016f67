#include "plot_view.h"

#include <QMouseEvent>
#include <QPainter>

#include <algorithm>
#include <cmath>

namespace acro::studio {

PlotView::PlotView(QWidget* parent) : QWidget(parent) {
  setMinimumSize(320, 160);
}

void PlotView::SetChart(const ui::Chart& chart) {
  chart_ = chart;
  has_chart_ = true;
  Draw();
  update();
}

void PlotView::SetCursorTime(double t_s) {
  cursor_s_ = t_s;
  update();
}

void PlotView::Draw() {
  if (!has_chart_ || width() < 50 || height() < 50) return;
  chart_.width_px = width();
  chart_.height_px = height();
  try {
    layout_ = ui::MakeChartLayout(chart_);
    const std::vector<std::uint8_t> rgb = ui::RenderChartRgb(chart_);
    image_ = QImage(rgb.data(),
                    chart_.width_px,
                    chart_.height_px,
                    3 * chart_.width_px,
                    QImage::Format_RGB888)
                 .copy();
  } catch (const std::exception&) {
    image_ = QImage();  // a chart without data: nothing to draw
  }
}

int PlotView::XOf(double t_s) const {
  if (image_.isNull()) return -1;
  const double u = (t_s - layout_.x_range.min) / (layout_.x_range.max - layout_.x_range.min);
  return int(std::lround(layout_.plot_left + u * (layout_.plot_right - layout_.plot_left)));
}

std::optional<double> PlotView::TimeAt(int x) const {
  if (image_.isNull() || x < layout_.plot_left || x > layout_.plot_right) return std::nullopt;
  const double u = (x - layout_.plot_left) / (layout_.plot_right - layout_.plot_left);
  return layout_.x_range.min + u * (layout_.x_range.max - layout_.x_range.min);
}

void PlotView::Export(const std::string& path) const {
  ui::Chart c = chart_;
  c.width_px = 900;  // the reports' size, whatever the window's
  c.height_px = 360;
  ui::WriteChart(c, path);
}

void PlotView::paintEvent(QPaintEvent*) {
  QPainter p(this);
  p.fillRect(rect(), Qt::white);
  if (image_.isNull()) return;
  p.drawImage(0, 0, image_);
  const int x = XOf(cursor_s_);
  if (x >= layout_.plot_left && x <= layout_.plot_right) {
    p.setPen(QPen(QColor(200, 20, 20), 2));
    p.drawLine(x, int(layout_.plot_top), x, int(layout_.plot_bottom));
  }
}

void PlotView::resizeEvent(QResizeEvent*) {
  Draw();
}

void PlotView::mousePressEvent(QMouseEvent* event) {
  if (const std::optional<double> t = TimeAt(int(event->localPos().x()))) Q_EMIT timeRequested(*t);
}

}  // namespace acro::studio
