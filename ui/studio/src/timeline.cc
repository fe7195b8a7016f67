#include "timeline.h"

#include <QMouseEvent>
#include <QPainter>
#include <QWheelEvent>

#include <algorithm>
#include <cmath>

namespace acro::studio {

namespace {
constexpr int kMargin = 8;
}

Timeline::Timeline(QWidget* parent) : QWidget(parent) {
  setMinimumHeight(60);
  setMouseTracking(true);  // an event's name when the pointer rests on it
}

void Timeline::SetTrial(int num_samples,
                        double rate_hz,
                        std::vector<Jump> jumps,
                        std::vector<Event> events) {
  num_samples_ = std::max(1, num_samples);
  rate_hz_ = rate_hz > 0 ? rate_hz : 1.0;
  jumps_ = std::move(jumps);
  events_ = std::move(events);
  first_ = 0;
  last_ = num_samples_ - 1;
  cursor_ = 0;
  update();
}

void Timeline::SetCursor(int sample) {
  cursor_ = sample;
  // Keep the cursor in view when zoomed.
  const double span = last_ - first_;
  if (sample < first_ || sample > last_) {
    first_ = std::clamp(sample - span / 2, 0.0, std::max(0.0, num_samples_ - 1 - span));
    last_ = first_ + span;
  }
  update();
}

int Timeline::XOf(double sample) const {
  const double w = std::max(1, width() - 2 * kMargin);
  return kMargin + int(std::lround((sample - first_) / std::max(1e-9, last_ - first_) * w));
}

int Timeline::SampleAt(int x) const {
  const double w = std::max(1, width() - 2 * kMargin);
  const double s = first_ + (x - kMargin) / w * (last_ - first_);
  return std::clamp(int(std::lround(s)), 0, num_samples_ - 1);
}

void Timeline::paintEvent(QPaintEvent*) {
  QPainter p(this);
  p.fillRect(rect(), QColor(245, 246, 248));
  const int top = 18, bottom = height() - 6;
  p.fillRect(QRect(kMargin, top, width() - 2 * kMargin, bottom - top), QColor(225, 228, 232));
  p.setPen(QColor(90, 90, 90));
  p.setFont(QFont(font().family(), 8));
  // Seconds along the top.
  const double seconds = (last_ - first_) / rate_hz_;
  const double step = seconds > 20 ? 5 : seconds > 8 ? 1 : seconds > 2 ? 0.5 : 0.1;
  for (double t = std::ceil(first_ / rate_hz_ / step) * step; t * rate_hz_ <= last_; t += step) {
    const int x = XOf(t * rate_hz_);
    p.drawLine(x, top - 4, x, top);
    p.drawText(x + 2, top - 6, QString::number(t, 'g', 4) + " s");
  }
  // Flights: the verdict's colour (green pass, red fail, grey not judged), the code inside.
  for (const Jump& j : jumps_) {
    const int x0 = XOf(j.takeoff_sample), x1 = XOf(j.landing_sample);
    if (x1 < 0 || x0 > width()) continue;
    const QColor colour = !j.judged ? QColor(170, 170, 170)
                          : j.pass  ? QColor(110, 200, 120)
                                    : QColor(230, 110, 100);
    p.fillRect(QRect(x0, top + 2, std::max(1, x1 - x0), bottom - top - 4), colour);
    p.setPen(Qt::black);
    p.drawText(QRect(x0, top + 2, std::max(1, x1 - x0), bottom - top - 4),
               Qt::AlignCenter,
               QString::fromStdString(j.label));
  }
  // Events: ticks under the strip (the analysis' take-offs and landings short, the file's own tall
  // and named).
  for (const Event& e : events_) {
    const int ex = XOf(e.sample);
    if (ex < 0 || ex > width()) continue;
    p.setPen(QPen(e.from_file ? QColor(120, 40, 160) : QColor(60, 60, 60), e.from_file ? 2 : 1));
    p.drawLine(ex, bottom - (e.from_file ? 16 : 7), ex, bottom);
    if (e.from_file) p.drawText(ex + 3, bottom - 8, QString::fromStdString(e.label));
  }
  // The cursor.
  const int x = XOf(cursor_);
  p.setPen(QPen(QColor(200, 20, 20), 2));
  p.drawLine(x, top - 2, x, bottom);
}

void Timeline::mousePressEvent(QMouseEvent* event) {
  Q_EMIT cursorRequested(SampleAt(int(event->localPos().x())));
}

const Timeline::Event* Timeline::EventAt(int x) const {
  const Event* best = nullptr;
  int best_d = 5;
  for (const Event& e : events_) {
    const int d = std::abs(XOf(e.sample) - x);
    if (d < best_d) {
      best_d = d;
      best = &e;
    }
  }
  return best;
}

void Timeline::mouseMoveEvent(QMouseEvent* event) {
  if (event->buttons() & Qt::LeftButton) {
    Q_EMIT cursorRequested(SampleAt(int(event->localPos().x())));
    return;
  }
  const Event* e = EventAt(int(event->localPos().x()));
  const QString tip =
      e ? QString::fromStdString(e->label) + QString(" (%1 s)").arg(e->sample / rate_hz_, 0, 'f', 3)
        : QString();
  if (tip != toolTip()) setToolTip(tip);
}

void Timeline::wheelEvent(QWheelEvent* event) {
  // Zoom about the pointer: a notch in halves or doubles the span shown (down to 1 s).
  const double at = SampleAt(int(event->position().x()));
  const double factor = event->angleDelta().y() > 0 ? 0.5 : 2.0;
  double span = std::clamp((last_ - first_) * factor, rate_hz_, double(num_samples_ - 1));
  first_ = std::clamp(at - (at - first_) * span / std::max(1e-9, last_ - first_),
                      0.0,
                      std::max(0.0, num_samples_ - 1 - span));
  last_ = first_ + span;
  update();
}

}  // namespace acro::studio
