#pragma once

// The whole trial on one strip (the studio's timeline): the flights shaded in their verdict's
// colour and labelled with their FIG code, the contacts between, the cursor as a red line. A click
// or a drag asks for the cursor there (cursorRequested); the wheel zooms about the pointer.

#include <QWidget>

#include <string>
#include <vector>

namespace acro::studio {

class Timeline : public QWidget {
  Q_OBJECT

 public:
  struct Jump {
    int takeoff_sample = 0;
    int landing_sample = 0;
    std::string label;  ///< "3  40<"
    bool judged = false;
    bool pass = false;
  };

  explicit Timeline(QWidget* parent = nullptr);

  void SetTrial(int num_samples, double rate_hz, std::vector<Jump> jumps);
  void SetCursor(int sample);
  int cursor() const { return cursor_; }
  const std::vector<Jump>& jumps() const { return jumps_; }
  /// The sample under pixel column x (the inverse of the drawing).
  int SampleAt(int x) const;
  int XOf(double sample) const;

  QSize sizeHint() const override { return {800, 70}; }

 Q_SIGNALS:
  void cursorRequested(int sample);

 protected:
  void paintEvent(QPaintEvent* event) override;
  void mousePressEvent(QMouseEvent* event) override;
  void mouseMoveEvent(QMouseEvent* event) override;
  void wheelEvent(QWheelEvent* event) override;

 private:
  int num_samples_ = 0;
  double rate_hz_ = 1.0;
  std::vector<Jump> jumps_;
  int cursor_ = 0;
  double first_ = 0, last_ = 1;  // the samples shown (zoom)
};

}  // namespace acro::studio
