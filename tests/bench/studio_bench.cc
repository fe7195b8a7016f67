// A frame step in the studio (docs/performance.md, "Studio"): the sample routine open with its
// 1080p video and the mesh shown, the window 1920 × 1080 under Xvfb; one step is the key press
// handled, the video frame decoded (or taken from the recent frames), the overlay drawn over it,
// the 3D view rendered, and both views repainted. Forward steps read on; backward steps find the
// frame among the last eight decoded. The goal (issue "The workstation window"): ≤ 50 ms from key
// press to both views updated.
// The live mode's buffer (docs/live.md, "The window"): every frame of every camera is compressed
// on its source's thread as it comes, every frame shown decompressed — a 640 × 360 frame of the
// sample's side video. The goal (issue "In the hall"): both within 5 ms, so that two 60-fps
// cameras cost under two thirds of one core.
// Run: build/bench/studio_bench --benchmark_repetitions=3 (Xvfb or a display).

#include <benchmark/benchmark.h>

#include <QApplication>
#include <QElapsedTimer>
#include <QTest>
#include <QThread>

#include "acro/capture/video.h"
#include "acro/views/display.h"
#include "live_window.h"
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

// The sample's side video, frame 100 (in the air), at the live analysis width.
const acro::capture::VideoFrame& LiveFrame() {
  static const acro::capture::VideoFrame frame = [] {
    acro::capture::VideoReader reader(acro::testing::SourceDir() /
                                      "samples/trials/trampoline_routine/side_camera.mp4");
    const acro::capture::VideoFrame full = reader.Frame(100);
    const QImage small =
        QImage(full.pixels.data(), full.width, full.height, 3 * full.width, QImage::Format_RGB888)
            .scaled(640, 360, Qt::IgnoreAspectRatio, Qt::SmoothTransformation)
            .convertToFormat(QImage::Format_RGB888);
    acro::capture::VideoFrame f;
    f.width = small.width();
    f.height = small.height();
    f.channels = 3;
    for (int y = 0; y < f.height; ++y)
      f.pixels.insert(f.pixels.end(), small.constScanLine(y), small.constScanLine(y) + 3 * f.width);
    return f;
  }();
  return frame;
}

void BM_LiveBufferCompress(benchmark::State& state) {
  const acro::capture::VideoFrame& frame = LiveFrame();
  size_t bytes = 0;
  for (auto _ : state)
    bytes = static_cast<size_t>(acro::studio::LiveWindow::Compress(frame).size());
  state.counters["KB"] = double(bytes) / 1024.0;
}
BENCHMARK(BM_LiveBufferCompress)->Unit(benchmark::kMillisecond);

void BM_LiveBufferDecompress(benchmark::State& state) {
  const QByteArray jpeg = acro::studio::LiveWindow::Compress(LiveFrame());
  for (auto _ : state) benchmark::DoNotOptimize(acro::studio::LiveWindow::Decompress(jpeg));
}
BENCHMARK(BM_LiveBufferDecompress)->Unit(benchmark::kMillisecond);

}  // namespace

int main(int argc, char** argv) {
  const acro::ui::XDisplay display;
  QApplication app(argc, argv);
  benchmark::Initialize(&argc, argv);
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}
