#pragma once

// A picture scaled to fit its widget, its aspect kept (the studio's 3D and video views), with zoom
// and pan as in video players: the wheel zooms about the pointer (up to 16×), a drag pans, a
// double click shows the whole picture again. A view that draws a 3D scene takes the mouse itself
// (SetNavigation: a drag orbits, the wheel moves closer) instead.

#include <QImage>
#include <QMouseEvent>
#include <QPainter>
#include <QWheelEvent>
#include <QWidget>

#include <algorithm>
#include <cmath>
#include <functional>

namespace acro::studio {

class ImageView : public QWidget {
 public:
  explicit ImageView(const QString& empty_text, QWidget* parent = nullptr)
      : QWidget(parent), empty_text_(empty_text) {
    setMinimumSize(320, 180);
  }
  void SetImage(QImage image) {
    const bool resized = image.size() != image_.size();
    image_ = std::move(image);
    if (resized) ResetZoom();
    update();
  }
  const QImage& image() const { return image_; }
  /// The mouse moves the scene instead of the picture: `drag` gets each drag step (widget pixels),
  /// `wheel` the wheel's notches (positive away from the user), `reset` a double click.
  void SetNavigation(std::function<void(QPointF)> drag,
                     std::function<void(double)> wheel,
                     std::function<void()> reset) {
    on_drag_ = std::move(drag);
    on_wheel_ = std::move(wheel);
    on_reset_ = std::move(reset);
  }
  double zoom() const { return zoom_; }
  /// The part of the picture shown (picture pixels).
  QRectF SourceRect() const {
    const double w = image_.width() / zoom_, h = image_.height() / zoom_;
    const double x = std::clamp(centre_.x() - w / 2, 0.0, image_.width() - w);
    const double y = std::clamp(centre_.y() - h / 2, 0.0, image_.height() - h);
    return {x, y, w, h};
  }
  /// Where the picture is drawn in the widget.
  QRect TargetRect() const {
    const QSize fitted = image_.size().scaled(size(), Qt::KeepAspectRatio);
    return {QPoint((width() - fitted.width()) / 2, (height() - fitted.height()) / 2), fitted};
  }
  void ResetZoom() {
    zoom_ = 1.0;
    centre_ = QPointF(image_.width() / 2.0, image_.height() / 2.0);
    update();
  }

 protected:
  void paintEvent(QPaintEvent*) override {
    QPainter p(this);
    p.fillRect(rect(), QColor(40, 42, 46));
    if (image_.isNull()) {
      p.setPen(QColor(200, 200, 200));
      p.drawText(rect(), Qt::AlignCenter, empty_text_);
      return;
    }
    p.setRenderHint(QPainter::SmoothPixmapTransform);
    p.drawImage(QRectF(TargetRect()), image_, SourceRect());
  }
  void wheelEvent(QWheelEvent* event) override {
    if (on_wheel_) return on_wheel_(event->angleDelta().y() / 120.0);
    if (image_.isNull()) return;
    // The picture point under the pointer stays under it.
    const QPointF before = ToImage(event->position());
    zoom_ = std::clamp(zoom_ * (event->angleDelta().y() > 0 ? 1.25 : 0.8), 1.0, 16.0);
    const QPointF after = ToImage(event->position());
    centre_ += before - after;
    Clamp();
    update();
  }
  void mousePressEvent(QMouseEvent* event) override { drag_ = event->localPos(); }
  void mouseMoveEvent(QMouseEvent* event) override {
    if (on_drag_ && (event->buttons() & Qt::LeftButton)) {
      on_drag_(event->localPos() - drag_);
      drag_ = event->localPos();
      return;
    }
    if (!(event->buttons() & Qt::LeftButton) || image_.isNull()) return;
    const double scale = SourceRect().width() / std::max(1, TargetRect().width());
    centre_ -= (event->localPos() - drag_) * scale;
    drag_ = event->localPos();
    Clamp();
    update();
  }
  void mouseDoubleClickEvent(QMouseEvent*) override {
    if (on_reset_) return on_reset_();
    ResetZoom();
  }

 private:
  // The picture point under widget point `w`.
  QPointF ToImage(const QPointF& w) const {
    const QRect t = TargetRect();
    const QRectF s = SourceRect();
    return {s.x() + (w.x() - t.x()) / std::max(1, t.width()) * s.width(),
            s.y() + (w.y() - t.y()) / std::max(1, t.height()) * s.height()};
  }
  void Clamp() {
    const QRectF s = SourceRect();
    centre_ = s.center();
  }

  QImage image_;
  QString empty_text_;
  double zoom_ = 1.0;
  QPointF centre_;
  QPointF drag_;
  std::function<void(QPointF)> on_drag_;
  std::function<void(double)> on_wheel_;
  std::function<void()> on_reset_;
};

}  // namespace acro::studio
