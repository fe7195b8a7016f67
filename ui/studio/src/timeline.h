#pragma once

// The whole trial on one strip (the studio's timeline): the flights shaded in their verdict's
// colour and labelled with their FIG code, the contacts between, the events (take-offs and
// landings found by the analysis, the file's own events such as a C3D's Foot Strike) as ticks, the
// cursor as a red line. A click or a drag asks for the cursor there (cursorRequested); the wheel
// zooms about the pointer; an event's name shows when the pointer rests on it.

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

  struct Event {
    int sample = 0;
    std::string label;       ///< "take-off 3", "Left Foot Strike"
    bool from_file = false;  ///< the trial file's own event (drawn taller, labelled)
  };

  explicit Timeline(QWidget* parent = nullptr);

  void SetTrial(int num_samples,
                double rate_hz,
                std::vector<Jump> jumps,
                std::vector<Event> events = {});
  const std::vector<Event>& events() const { return events_; }
  /// The event drawn nearest pixel column x, within 4 pixels (nullptr: none).
  const Event* EventAt(int x) const;
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
  std::vector<Event> events_;
  int cursor_ = 0;
  double first_ = 0, last_ = 1;  // the samples shown (zoom)
};

}  // namespace acro::studio
