#pragma once

// A picture scaled to fit its widget, its aspect kept (the studio's 3D and video views).

#include <QImage>
#include <QPainter>
#include <QWidget>

namespace acro::studio {

class ImageView : public QWidget {
 public:
  explicit ImageView(const QString& empty_text, QWidget* parent = nullptr)
      : QWidget(parent), empty_text_(empty_text) {
    setMinimumSize(320, 180);
  }
  void SetImage(QImage image) {
    image_ = std::move(image);
    update();
  }
  const QImage& image() const { return image_; }

 protected:
  void paintEvent(QPaintEvent*) override {
    QPainter p(this);
    p.fillRect(rect(), QColor(40, 42, 46));
    if (image_.isNull()) {
      p.setPen(QColor(200, 200, 200));
      p.drawText(rect(), Qt::AlignCenter, empty_text_);
      return;
    }
    const QSize fitted = image_.size().scaled(size(), Qt::KeepAspectRatio);
    const QRect target(QPoint((width() - fitted.width()) / 2, (height() - fitted.height()) / 2),
                       fitted);
    p.setRenderHint(QPainter::SmoothPixmapTransform);
    p.drawImage(target, image_);
  }

 private:
  QImage image_;
  QString empty_text_;
};

}  // namespace acro::studio
