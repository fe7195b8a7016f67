// A frame step in the studio (docs/performance.md, "Studio"): the sample routine open with its
// 1080p video and the mesh shown, the window 1920 × 1080 under Xvfb; one step is the key press
// handled, the video frame decoded (or taken from the recent frames), the overlay drawn over it,
// the 3D view rendered, and both views repainted. Forward steps read on; backward steps find the
// frame among the last eight decoded. The goal (issue "The workstation window"): ≤ 50 ms from key
// press to both views updated.
// Run: build/bench/studio_bench --benchmark_repetitions=3 (Xvfb or a display).

#include <benchmark/benchmark.h>

#include <QApplication>
#include <QElapsedTimer>
#include <QTest>
#include <QThread>

#include "acro/views/display.h"
#include "main_window.h"
#include "refdata.h"

namespace {

namespace fs = std::filesystem;

acro::studio::MainWindow* OpenSample() {
  static acro::studio::MainWindow* window = [] {
    auto* w = new acro::studio::MainWindow;
    w->resize(1920, 1080);
    w->show();
    const fs::path dir = acro::testing::SourceDir() / "samples/trials/trampoline_routine";
    acro::studio::SessionFiles f;
    f.trial = (dir / "trampoline_routine.c3d").string();
    f.athlete = (acro::testing::SourceDir() / "samples/athletes/sample_athlete.yaml").string();
    acro::studio::VideoFiles v;
    v.video = (dir / "side_camera.mp4").string();
    v.calibration = (dir / "side_camera.toml").string();
    v.offset_s = -0.575;
    f.videos.push_back(v);
    w->OpenFiles(f);
    QElapsedTimer t;
    t.start();
    while ((w->session() == nullptr || w->busy()) && t.elapsed() < 300000) {
      QCoreApplication::processEvents(QEventLoop::AllEvents, 20);
      QThread::msleep(5);
    }
    QApplication::setActiveWindow(w);
    return w;
  }();
  return window;
}

// `key` pressed `state.range(0)` … times from a flight frame, the window repainted each time.
void BM_StudioStep(benchmark::State& state, Qt::Key key) {
  acro::studio::MainWindow* w = OpenSample();
  if (w->session() == nullptr) {
    state.SkipWithError("the sample did not open");
    return;
  }
  // Start in the back pike's flight: forward steps read on from here, backward ones go back over
  // frames decoded on the way in.
  w->SetCursor(w->session()->SampleOf(100));
  for (int k = 0; k < 8; ++k) w->StepFrame(1);
  int steps = 0;
  for (auto _ : state) {
    QTest::keyClick(w, key);
    w->repaint();
    ++steps;
    if (steps % 8 == 0) {  // back where we began, off the clock
      state.PauseTiming();
      w->SetCursor(w->session()->SampleOf(100));
      for (int k = 0; k < 8; ++k) w->StepFrame(1);
      state.ResumeTiming();
    }
  }
}
BENCHMARK_CAPTURE(BM_StudioStep, forward, Qt::Key_Right)->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_StudioStep, backward, Qt::Key_Left)->Unit(benchmark::kMillisecond);

}  // namespace

int main(int argc, char** argv) {
  const acro::ui::XDisplay display;
  QApplication app(argc, argv);
  benchmark::Initialize(&argc, argv);
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}
