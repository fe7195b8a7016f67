// The studio driven as a user would, under Xvfb (test.sh runs the suite under xvfb-run; without a
// display the test starts its own): the sample routine opened with its video and calibration; the
// timeline's six jumps with their codes; a frame either way by the arrow keys, the video view
// showing exactly the decoded frame of the cursor and the 3D view the athlete at that sample;
// play for a second and pause; a click on jump 6 in the table puts the cursor at its take-off; the
// session saved and reopened; a bad file is a dialog and the session stays. With
// ACRO_STUDIO_SCREENSHOTS=DIR each state is saved as a picture there (docs/studio.md).

#include "main_window.h"

#include <gtest/gtest.h>

#include <QApplication>
#include <QComboBox>
#include <QElapsedTimer>
#include <QMessageBox>
#include <QPushButton>
#include <QScreen>
#include <QTabWidget>
#include <QTableWidget>
#include <QTest>
#include <QThread>

#include <unistd.h>

#include <cmath>
#include <cstdlib>
#include <fstream>
#include <functional>

#include <fmt/format.h>
#include <Eigen/Geometry>

#include "acro/athlete/standard_human.h"
#include "acro/base/input_error.h"
#include "acro/library/add_trial.h"
#include "acro/scene/skill_ghost.h"
#include "acro/views/display.h"
#include "compare_window.h"
#include "image_view.h"
#include "library_window.h"
#include "plot_view.h"
#include "pose_model_cache.h"
#include "qt_wait.h"
#include "refdata.h"
#include "routine_plan_window.h"
#include "skill_window.h"
#include "timeline.h"

namespace acro::studio {
namespace {

namespace fs = std::filesystem;

bool WaitUntil(const std::function<bool()>& done, int ms) {
  return acro::testing::WaitUntil(done, ms);
}

// Closes the message boxes left open (a test reads last_error(); a person presses OK).
void CloseDialogs() {
  for (QWidget* top : QApplication::topLevelWidgets())
    if (auto* box = qobject_cast<QMessageBox*>(top)) box->close();
  QCoreApplication::processEvents();
}

// The whole screen (the window and any dialog over it).
void Shot(const std::string& name) {
  const char* dir = std::getenv("ACRO_STUDIO_SCREENSHOTS");
  if (dir == nullptr || *dir == 0) return;
  QTest::qWait(200);
  QGuiApplication::primaryScreen()->grabWindow(0).save(
      QString::fromStdString((fs::path(dir) / (name + ".png")).string()));
}

// A click on jump `index`'s row of the jump table.
void GoToJumpByClick(MainWindow& w, int index) {
  QTableWidget* table = w.jump_table();
  table->scrollToItem(table->item(index - 1, 0));
  const QRect row = table->visualItemRect(table->item(index - 1, 0));
  QTest::mouseClick(table->viewport(), Qt::LeftButton, {}, row.center());
}

SessionFiles SampleFiles() {
  const fs::path dir = acro::testing::SourceDir() / "samples/trials/trampoline_routine";
  SessionFiles f;
  f.trial = (dir / "trampoline_routine.c3d").string();
  f.athlete = (acro::testing::SourceDir() / "samples/athletes/sample_athlete.yaml").string();
  VideoFiles v;
  v.video = (dir / "side_camera.mp4").string();
  v.calibration = (dir / "side_camera.toml").string();
  v.offset_s = -0.575;  // video_truth.json (the automatic sync is analyze's, tested there)
  f.videos.push_back(v);
  return f;
}

TEST(Studio, TheSampleRoutineWithItsVideoAtOneCursor) {
  MainWindow w;
  w.resize(1920, 1080);
  w.show();
  ASSERT_TRUE(QTest::qWaitForWindowExposed(&w));
  QApplication::setActiveWindow(&w);
  w.OpenFiles(SampleFiles());
  ASSERT_TRUE(WaitUntil([&] { return w.session() != nullptr && !w.busy(); }, 180000))
      << w.last_error();
  ASSERT_TRUE(w.last_error().empty()) << w.last_error();
  Session& s = *w.session();

  // The timeline: six jumps with their codes.
  const std::vector<std::string> codes = {"00", "40o", "40<", "41/", "42/", "800o"};
  ASSERT_EQ(w.timeline()->jumps().size(), codes.size());
  for (size_t k = 0; k < codes.size(); ++k)
    EXPECT_EQ(w.timeline()->jumps()[k].label, std::to_string(k + 1) + "  " + codes[k]);
  EXPECT_EQ(w.jump_table()->rowCount(), 6);
  // Its events: each jump's take-off and landing, named when the pointer rests on one.
  ASSERT_EQ(w.timeline()->events().size(), 2 * codes.size());
  const analysis::JumpMetrics& first_jump = s.analysis().jumps.at(0);
  const Timeline::Event* takeoff =
      w.timeline()->EventAt(w.timeline()->XOf(first_jump.flight.takeoff_frame));
  ASSERT_NE(takeoff, nullptr);
  EXPECT_EQ(takeoff->label, "take-off 1");

  // A frame forward and back with the arrow keys: the video view shows the reader's frame of the
  // cursor, the 3D view the athlete at the cursor.
  w.SetCursor(s.SampleOf(120));
  ASSERT_EQ(w.video_frame_index(), 120);
  capture::VideoReader reader(SampleFiles().videos.at(0).video);
  for (const auto& [key, expected] :
       {std::pair{Qt::Key_Right, 121}, {Qt::Key_Right, 122}, {Qt::Key_Left, 121}}) {
    QTest::keyClick(&w, key);
    QCoreApplication::processEvents();
    ASSERT_EQ(w.video_frame_index(), expected);
    EXPECT_EQ(w.cursor(), s.SampleOf(expected));
    const capture::VideoFrame truth = reader.Frame(expected);
    EXPECT_TRUE(w.filmed_frame().pixels == truth.pixels) << "frame " << expected;
    ASSERT_NE(w.view_frame(), nullptr);
    EXPECT_EQ(w.view_frame()->sample, w.cursor());
  }
  Shot("studio_frame_121");

  // Zoom on the video view about the pointer (the picture point under it stays there), pan by a
  // drag, a double click shows the whole frame again.
  ImageView* video = w.video_view();
  const QPoint at = video->TargetRect().topLeft() +
                    QPoint(video->TargetRect().width() / 4, video->TargetRect().height() / 4);
  const QRectF whole = video->SourceRect();
  // The picture point under the pointer before the zoom (about a quarter in).
  const QPointF under = {whole.x() + double(at.x() - video->TargetRect().x()) /
                                         video->TargetRect().width() * whole.width(),
                         whole.y() + double(at.y() - video->TargetRect().y()) /
                                         video->TargetRect().height() * whole.height()};
  QWheelEvent wheel(at,
                    video->mapToGlobal(at),
                    {},
                    {0, 120},
                    Qt::NoButton,
                    Qt::NoModifier,
                    Qt::NoScrollPhase,
                    false);
  for (int k = 0; k < 3; ++k) QApplication::sendEvent(video, &wheel);
  EXPECT_NEAR(video->zoom(), 1.25 * 1.25 * 1.25, 1e-9);
  const QRectF zoomed = video->SourceRect();
  EXPECT_NEAR(zoomed.width(), whole.width() / video->zoom(), 1e-6);
  // The picture point under the pointer is the same as before the zoom.
  EXPECT_NEAR(zoomed.x() + double(at.x() - video->TargetRect().x()) * zoomed.width() /
                               video->TargetRect().width(),
              under.x(),
              1e-6);
  EXPECT_NEAR(zoomed.y() + double(at.y() - video->TargetRect().y()) * zoomed.height() /
                               video->TargetRect().height(),
              under.y(),
              1e-6);
  QTest::mousePress(video, Qt::LeftButton, {}, at);
  // (QTest::mouseMove carries no button in Qt 5: the drag's move is sent as the window would.)
  QMouseEvent drag(
      QEvent::MouseMove, at + QPoint(40, 0), Qt::NoButton, Qt::LeftButton, Qt::NoModifier);
  QApplication::sendEvent(video, &drag);
  QTest::mouseRelease(video, Qt::LeftButton, {}, at + QPoint(40, 0));
  EXPECT_LT(video->SourceRect().x(), zoomed.x());  // dragged right: the view moved left
  QTest::mouseDClick(video, Qt::LeftButton, {}, at);
  EXPECT_EQ(video->zoom(), 1.0);

  // Play for a second, then pause: the cursor moved about a second of trial (one at speed 1).
  const int before = w.cursor();
  QTest::keyClick(&w, Qt::Key_Space);
  EXPECT_TRUE(w.playing());
  QTest::qWait(1000);
  QTest::keyClick(&w, Qt::Key_Space);
  EXPECT_FALSE(w.playing());
  const double played_s = (w.cursor() - before) / s.rate_hz();
  EXPECT_GT(played_s, 0.5);
  EXPECT_LT(played_s, 1.3);

  // A click on jump 6 in the table: the cursor at its take-off.
  GoToJumpByClick(w, 6);
  const analysis::JumpMetrics& six = s.analysis().jumps.at(5);
  EXPECT_EQ(w.cursor(), six.flight.takeoff_frame);
  Shot("studio_jump_6");

  // The verdict panel: a row per judged flight, all passing; a click on flight 4 puts the cursor
  // on its judged frames, where its largest residual window starts.
  QTableWidget* verdict = w.verdict_table();
  ASSERT_EQ(verdict->rowCount(), int(s.analysis().check.flights.size()));
  for (int r = 0; r < verdict->rowCount(); ++r) EXPECT_EQ(verdict->item(r, 6)->text(), "pass");
  const analysis::FlightCheck& four = s.analysis().check.flights.at(3);
  {
    auto* tabs = w.findChild<QTabWidget*>();
    ASSERT_NE(tabs, nullptr);
    tabs->setCurrentIndex(1);
    QCoreApplication::processEvents();
    const QRect row = verdict->visualItemRect(verdict->item(3, 0));
    QTest::mouseClick(verdict->viewport(), Qt::LeftButton, {}, row.center());
  }
  EXPECT_GE(w.cursor(), four.first_frame);
  EXPECT_LE(w.cursor(), four.last_frame);
  Shot("studio_verdict");

  // The score sheet panel: the routine's five elements after its in-bounce with their codes and
  // DD, D, T and H below; a click on element 4 puts the cursor at its take-off, a click on its
  // faults where its most serious measurement is worst (docs/scoring.md).
  {
    const fig::RoutineScore& score = s.analysis().score;
    QTableWidget* sheet = w.score_table();
    ASSERT_EQ(sheet->rowCount(), 5);
    ASSERT_EQ(score.elements.size(), 5u);
    for (int r = 0; r < 5; ++r) {
      EXPECT_EQ(sheet->item(r, 2)->text().toStdString(), score.elements[size_t(r)].code);
      EXPECT_EQ(sheet->item(r, 5)->text(), "A");
      EXPECT_NE(sheet->item(r, 8)->text().toStdString().find("none beyond the uncertainty"),
                std::string::npos);
    }
    EXPECT_EQ(sheet->item(3, 2)->text(), "42/");
    const std::string summary = w.score_summary();
    EXPECT_NE(summary.find("<b>D 3.5</b>"), std::string::npos) << summary;
    EXPECT_NE(summary.find(fmt::format("<b>T {:.3f}</b>", score.time_of_flight)), std::string::npos)
        << summary;
    EXPECT_NE(summary.find("interrupted"), std::string::npos) << summary;
    auto* tabs = w.findChild<QTabWidget*>();
    tabs->setCurrentIndex(2);
    QCoreApplication::processEvents();
    sheet->resizeColumnsToContents();
    QTest::mouseClick(
        sheet->viewport(), Qt::LeftButton, {}, sheet->visualItemRect(sheet->item(3, 0)).center());
    const analysis::JumpMetrics& full = s.analysis().jumps.at(size_t(score.elements[3].flight - 1));
    EXPECT_EQ(w.cursor(), full.flight.takeoff_frame);
    sheet->scrollToItem(sheet->item(3, 8));
    QTest::mouseClick(
        sheet->viewport(), Qt::LeftButton, {}, sheet->visualItemRect(sheet->item(3, 8)).center());
    int worst_frame = -1;
    double worst = 0;
    for (const fig::MeasuredFault& f : score.elements[3].faults)
      if (std::isfinite(f.threshold) && f.threshold > 0 && f.frame >= 0) {
        const double severity = f.smaller_is_worse ? f.threshold / f.value : f.value / f.threshold;
        if (severity > worst) {
          worst = severity;
          worst_frame = f.frame;
        }
      }
    ASSERT_GE(worst_frame, 0);
    EXPECT_EQ(w.cursor(), worst_frame);
    EXPECT_GE(w.cursor(), full.flight.takeoff_frame);
    EXPECT_LE(w.cursor(), full.flight.landing_frame);
    sheet->scrollToItem(sheet->item(3, 0));
    Shot("studio_score_sheet");
    EXPECT_FALSE(w.GoToElement(6, false));
  }
  w.findChild<QTabWidget*>()->setCurrentIndex(0);

  // The plot follows the cursor; a click on it moves the cursor to the time under the pointer
  // (within a pixel's worth of samples); it exports as PNG, SVG and CSV.
  PlotView* plot = w.plot();
  ASSERT_FALSE(plot->chart().title.empty());
  const analysis::JumpMetrics& three = s.analysis().jumps.at(2);
  const int x = plot->XOf(three.flight.takeoff_s);
  ASSERT_GE(x, 0);
  QTest::mouseClick(plot, Qt::LeftButton, {}, QPoint(x, plot->height() / 2));
  const double per_pixel_samples =
      (plot->TimeAt(x + 1).value_or(0) - plot->TimeAt(x).value_or(0)) * s.rate_hz();
  EXPECT_NEAR(w.cursor(), three.flight.takeoff_s * s.rate_hz(), per_pixel_samples + 1.0);
  const fs::path exported = acro::testing::ScratchDir("studio_plot");
  for (const char* ext : {".png", ".svg", ".csv"}) {
    plot->Export((exported / (std::string("plot") + ext)).string());
    EXPECT_GT(fs::file_size(exported / (std::string("plot") + ext)), 100u) << ext;
  }
  std::ifstream csv(exported / "plot.csv");
  std::string header;
  std::getline(csv, header);
  EXPECT_EQ(header, "series,x,y");
  Shot("studio_plot_click");
  // The silhouettes (the video's athlete against the reconstruction, as `analyze --video` checks
  // them): the IoU of every filmed flight frame as a plot, each jump's median in the table.
  ASSERT_FALSE(s.silhouettes().iou.empty());
  int iou_plot = -1;
  for (int i = 0; i < w.plot_count(); ++i)
    if (w.plot_title(i) == "Silhouettes: video against reconstruction") iou_plot = i;
  ASSERT_GE(iou_plot, 0);
  w.ShowPlot(iou_plot);
  EXPECT_EQ(plot->chart().series.at(0).y.size(), s.silhouettes().iou.size());
  EXPECT_GT(s.silhouettes().median_iou, 0.8);  // docs/overlay.md: 0.894 at the true sync
  const int iou_column = 8;
  EXPECT_EQ(w.jump_table()->horizontalHeaderItem(iou_column)->text(), "silhouette IoU");
  for (const analysis::JumpMetrics& j : s.analysis().jumps) {
    if (!j.silhouette_iou) continue;
    EXPECT_EQ(w.jump_table()->item(j.index - 1, iou_column)->text().toStdString(),
              fmt::format("{:.2f}", *j.silhouette_iou));
  }
  Shot("studio_silhouettes");
  GoToJumpByClick(w, 6);

  // Compare mode with jumps 2 and 3: the cursor at A's take-off is τ = 0 in the compare window,
  // and moves with it; B is the ghost in A's flight in the main window's views.
  ASSERT_TRUE(w.OpenCompare(2, 3)) << w.last_error();
  ASSERT_NE(w.compare(), nullptr);
  const analysis::JumpMetrics& two = s.analysis().jumps.at(1);
  EXPECT_EQ(w.cursor(), two.flight.takeoff_frame);
  EXPECT_NEAR(
      w.compare()->tau(), two.flight.takeoff_frame / s.rate_hz() - two.flight.takeoff_s, 1e-9);
  EXPECT_LT(std::abs(w.compare()->tau()), 1.0 / s.rate_hz());
  w.SetCursor(two.flight.takeoff_frame + 60);  // half a second into the back tuck
  EXPECT_NEAR(w.compare()->tau(),
              (two.flight.takeoff_frame + 60) / s.rate_hz() - two.flight.takeoff_s,
              1e-9);
  ASSERT_NE(w.view_frame(), nullptr);
  EXPECT_TRUE(w.view_frame()->ghost_shown);
  EXPECT_NE(w.view_frame()->heads_up.find("ghost: jump 3"), std::string::npos)
      << w.view_frame()->heads_up;
  Shot("studio_compare");
  w.compare()->hide();

  // Compare with a jump of another trial (another day's file of the same routine: analysed on the
  // worker, without its video): its jump 3 is the ghost in every flight — its own number is
  // another trial's, so in jump 3's flight here too — and the compare window names its file.
  const fs::path other_dir = acro::testing::ScratchDir("studio_other_trial");
  fs::copy_file(
      SampleFiles().trial, other_dir / "another_day.c3d", fs::copy_options::overwrite_existing);
  SessionFiles other;
  other.trial = (other_dir / "another_day.c3d").string();
  other.athlete = SampleFiles().athlete;
  w.OpenCompareWithTrial(2, other, 3);
  ASSERT_TRUE(WaitUntil([&] { return !w.busy(); }, 180000));
  ASSERT_TRUE(w.last_error().empty()) << w.last_error();
  ASSERT_NE(w.compare(), nullptr);
  EXPECT_NE(w.compare()->scene().b().label.find("of another_day.c3d"), std::string::npos)
      << w.compare()->scene().b().label;
  EXPECT_EQ(w.session(), &s);  // the session open stays
  EXPECT_EQ(w.cursor(), two.flight.takeoff_frame);
  const analysis::JumpMetrics& pike = s.analysis().jumps.at(2);
  w.SetCursor((pike.flight.takeoff_frame + pike.flight.landing_frame) / 2);
  ASSERT_TRUE(w.view_frame()->ghost_shown);
  EXPECT_NE(w.view_frame()->heads_up.find("of another_day.c3d"), std::string::npos)
      << w.view_frame()->heads_up;
  // The other trial's jump 3 in this trial's jump 3: the same motion at its own take-off.
  EXPECT_LT((w.view_frame()->ghost.com_W - w.view_frame()->athlete.com_W).norm(), 1e-6);
  w.SetCursor(two.flight.takeoff_frame + 60);
  Shot("studio_compare_other_trial");
  w.compare()->hide();
  // A bad other trial: the dialog, and the comparison and session stay.
  CompareWindow* kept_compare = w.compare();
  std::ofstream(other_dir / "broken.c3d") << "not a C3D\n";
  other.trial = (other_dir / "broken.c3d").string();
  w.OpenCompareWithTrial(2, other, 3);
  ASSERT_TRUE(WaitUntil([&] { return !w.busy(); }, 60000));
  EXPECT_NE(w.last_error().find("broken.c3d"), std::string::npos) << w.last_error();
  EXPECT_EQ(w.compare(), kept_compare);
  EXPECT_EQ(w.session(), &s);
  GoToJumpByClick(w, 6);

  // The 3D view: the toolbar's toggles (the skeleton and the markers, no mesh), a drag orbits it
  // (a third of a degree per pixel), the wheel moves it closer; the picture changes each time, and
  // the session keeps it all.
  {
    const QImage with_mesh = w.view3d()->image();
    w.SetShown("skeleton,markers,com");
    EXPECT_EQ(w.shown(), "skeleton,markers,com");
    const QImage skeleton = w.view3d()->image();
    EXPECT_NE(skeleton, with_mesh);
    ImageView* view3d = w.view3d();
    const QPoint from = view3d->rect().center();
    QTest::mousePress(view3d, Qt::LeftButton, {}, from);
    QMouseEvent orbit(
        QEvent::MouseMove, from + QPoint(-100, 30), Qt::NoButton, Qt::LeftButton, Qt::NoModifier);
    QApplication::sendEvent(view3d, &orbit);
    QTest::mouseRelease(view3d, Qt::LeftButton, {}, from + QPoint(-100, 30));
    EXPECT_NEAR(w.view().orbit_azimuth_deg, 35.0, 1e-9);
    EXPECT_NEAR(w.view().orbit_elevation_deg, 10.5, 1e-9);
    QWheelEvent closer(from,
                       view3d->mapToGlobal(from),
                       {},
                       {0, 240},
                       Qt::NoButton,
                       Qt::NoModifier,
                       Qt::NoScrollPhase,
                       false);
    QApplication::sendEvent(view3d, &closer);
    EXPECT_NEAR(w.view().orbit_distance_scale, 0.81, 1e-9);
    EXPECT_NE(w.view3d()->image(), skeleton);
    CloseDialogs();
    Shot("studio_orbit");
    // Farther out, with the cameras: the video's camera drawn as a frustum beside the trampoline.
    w.Orbit(-10, 10, 2.5);
    const QImage without_cameras = w.view3d()->image();
    w.SetShown("skeleton,markers,com,cameras");
    EXPECT_EQ(w.shown(), "skeleton,markers,com,cameras");
    EXPECT_NE(w.view3d()->image(), without_cameras);
    Shot("studio_cameras");
    w.Orbit(10, -10, 1 / 2.5);
    w.SetShown("skeleton,markers,com");
  }

  // The session saved and reopened in another window: the same files, cursor and view.
  const fs::path dir = acro::testing::ScratchDir("studio_session");
  ASSERT_TRUE(w.SaveSessionFile((dir / "sample.acrolab").string())) << w.last_error();
  MainWindow again;
  again.OpenSessionFile((dir / "sample.acrolab").string());
  ASSERT_TRUE(WaitUntil([&] { return again.session() != nullptr && !again.busy(); }, 180000))
      << again.last_error();
  EXPECT_EQ(again.cursor(), w.cursor());
  EXPECT_EQ(fs::weakly_canonical(again.session()->files().trial),
            fs::weakly_canonical(s.files().trial));
  EXPECT_EQ(again.session()->sync().offset_s, s.sync().offset_s);
  EXPECT_EQ(again.shown(), "skeleton,markers,com");
  EXPECT_NEAR(again.view().orbit_azimuth_deg, 35.0, 1e-9);
  EXPECT_NEAR(again.view().orbit_distance_scale, 0.81, 1e-9);
  w.ResetOrbit();
  w.SetShown("mesh,skeleton,com");

  // Opening again and cancelling during the analysis: it stops within a second or two (the inverse
  // kinematics asks every ten frames), no dialog, the session and cursor stay.
  {
    const int cursor = w.cursor();
    const std::string error_before = w.last_error();
    w.OpenFiles(SampleFiles());
    ASSERT_TRUE(WaitUntil(
        [&] { return w.status_text().find("inverse kinematics") != std::string::npos; }, 30000))
        << w.status_text();
    ASSERT_TRUE(w.busy());
    QPushButton* cancel = nullptr;
    for (QPushButton* b : w.findChildren<QPushButton*>())
      if (b->text() == "Cancel") cancel = b;
    ASSERT_NE(cancel, nullptr);
    QElapsedTimer stopping;
    stopping.start();
    QTest::mouseClick(cancel, Qt::LeftButton);
    ASSERT_TRUE(WaitUntil([&] { return !w.busy(); }, 30000));
    std::printf("loading cancelled in %lld ms\n", static_cast<long long>(stopping.elapsed()));
    EXPECT_LT(stopping.elapsed(), 3000);
    EXPECT_EQ(w.last_error(), error_before);  // no new dialog
    EXPECT_EQ(w.session(), &s);
    EXPECT_EQ(w.cursor(), cursor);
  }

  // A bad file: a dialog with its one-line error; the session stays as it was.
  std::ofstream(dir / "not_a_trial.c3d") << "this is not a C3D file\n";
  SessionFiles bad = SampleFiles();
  bad.trial = (dir / "not_a_trial.c3d").string();
  Session* kept = w.session();
  w.OpenFiles(bad);
  ASSERT_TRUE(WaitUntil([&] { return !w.busy() && !w.last_error().empty(); }, 60000));
  EXPECT_NE(w.last_error().find("not_a_trial.c3d"), std::string::npos) << w.last_error();
  EXPECT_EQ(w.last_error().find('\n'), std::string::npos) << w.last_error();
  EXPECT_EQ(w.session(), kept);
  EXPECT_EQ(w.cursor(), six.flight.takeoff_frame);
  Shot("studio_bad_file");
}

// Several cameras: the sample routine with its video twice (two views, one above the other; a
// session shows up to four), each view showing its reader's decoded frame of the cursor; the
// session file keeps both (version 2), and a version 1 file (one video) still opens.
// File → Open from library: the season library's trials in a table; the chosen one opens with the
// athlete it was stored with and its attached video. A file that is not a library is the dialog.
TEST(Studio, OpensATrialFromTheLibrary) {
  const fs::path dir =
      fs::temp_directory_path() / ("acro_studio_library_" + std::to_string(getpid()));
  fs::remove_all(dir);
  fs::create_directories(dir);
  const fs::path library = dir / "library.sqlite";
  {
    const SessionFiles sample = SampleFiles();
    acro::library::Library lib(library, acro::library::Library::Mode::kReadWrite);
    acro::library::AddRequest request;
    request.trial = sample.trial;
    request.athlete_profile = sample.athlete;
    request.session_date = "2026-09-01";
    request.video = sample.videos[0].video;
    request.calibration = sample.videos[0].calibration;
    ASSERT_EQ(acro::library::AddTrial(lib, request).num_jumps, 6);
  }
  MainWindow w;
  w.resize(1600, 900);
  w.show();
  ASSERT_TRUE(QTest::qWaitForWindowExposed(&w));
  LibraryDialog* dialog = w.OpenFromLibrary(library.string(), false);
  ASSERT_NE(dialog, nullptr) << w.last_error();
  ASSERT_TRUE(QTest::qWaitForWindowExposed(dialog));
  ASSERT_EQ(dialog->table()->rowCount(), 1);
  EXPECT_EQ(dialog->table()->item(0, 0)->text().toStdString(), "2026-09-01");
  EXPECT_EQ(dialog->table()->item(0, 1)->text().toStdString(), "Sample Athlete");
  EXPECT_EQ(dialog->table()->item(0, 2)->text().toStdString(), "6");
  EXPECT_EQ(dialog->table()->item(0, 5)->text().toStdString(), "pass");
  EXPECT_EQ(dialog->athletes()->count(), 2);  // every athlete, Sample Athlete
  Shot("studio_library");
  // A double click on the row opens it.
  const QRect row = dialog->table()->visualItemRect(dialog->table()->item(0, 0));
  // (item views take a double click after a click: press, release, then the double click)
  QTest::mouseClick(dialog->table()->viewport(), Qt::LeftButton, {}, row.center());
  QTest::mouseDClick(dialog->table()->viewport(), Qt::LeftButton, {}, row.center());
  EXPECT_EQ(dialog->result(), QDialog::Accepted);
  ASSERT_TRUE(WaitUntil([&] { return w.session() != nullptr && !w.busy(); }, 180000))
      << w.last_error() << " / " << w.status_text();
  EXPECT_TRUE(w.last_error().empty()) << w.last_error();
  EXPECT_EQ(fs::path(w.session()->files().trial), fs::weakly_canonical(SampleFiles().trial));
  EXPECT_EQ(fs::path(w.session()->files().athlete), fs::weakly_canonical(SampleFiles().athlete));
  EXPECT_EQ(w.session()->num_videos(), 1);
  EXPECT_EQ(w.timeline()->jumps().size(), 6u);
  // Not a library: one line in the dialog, nothing opened instead.
  const fs::path bad = dir / "notes.sqlite";
  std::ofstream(bad) << "not a database";
  EXPECT_EQ(w.OpenFromLibrary(bad.string(), false), nullptr);
  EXPECT_NE(w.last_error().find("not an Acrolab library"), std::string::npos) << w.last_error();
  CloseDialogs();
  fs::remove_all(dir);
}

TEST(Studio, TwoVideoViewsFollowTheCursor) {
  SessionFiles files = SampleFiles();
  files.videos.push_back(files.videos.front());
  files.videos.back().offset_s = -0.575 + 1.0 / 30;  // a camera that started a frame later
  MainWindow w;
  w.resize(1920, 1080);
  w.show();
  w.OpenFiles(files);
  ASSERT_TRUE(WaitUntil([&] { return w.session() != nullptr && !w.busy(); }, 180000))
      << w.last_error();
  Session& s = *w.session();
  QApplication::setActiveWindow(&w);
  QTest::qWait(100);  // the views laid out
  ASSERT_EQ(w.num_video_views(), 2);
  EXPECT_LT(w.video_view(0)->geometry().bottom(), w.video_view(1)->geometry().top() + 1);
  capture::VideoReader reader(files.videos[0].video);
  w.SetCursor(s.SampleOf(120, 0));
  for (int step = 0; step < 3; ++step) {
    EXPECT_EQ(w.video_frame_index(0), 120 + step);
    // The second camera's clock is a frame later: the same instant is its frame 121 + step.
    EXPECT_EQ(w.video_frame_index(1), 121 + step);
    EXPECT_TRUE(w.filmed_frame(0).pixels == reader.Frame(120 + step).pixels);
    EXPECT_TRUE(w.filmed_frame(1).pixels == reader.Frame(121 + step).pixels);
    QTest::keyClick(&w, Qt::Key_Right);
    QCoreApplication::processEvents();
  }
  Shot("studio_two_videos");
  const fs::path dir = acro::testing::ScratchDir("studio_two_videos");
  WriteSessionFile(dir / "two.acrolab", s.files(), w.view());
  const auto [read, view] = ReadSessionFile(dir / "two.acrolab");
  ASSERT_EQ(read.videos.size(), 2u);
  EXPECT_EQ(read.videos[1].offset_s, files.videos[1].offset_s);
  EXPECT_EQ(view.cursor_sample, w.cursor());
  // Version 1: one video's keys at the top level.
  std::ofstream(dir / "old.acrolab")
      << "{\"format\": \"acrolab-session\", \"version\": 1, \"trial\": \"" << files.trial
      << "\", \"video\": \"" << files.videos[0].video << "\", \"calibration\": \""
      << files.videos[0].calibration << "\", \"offset_s\": -0.575}\n";
  const auto [old_files, old_view] = ReadSessionFile(dir / "old.acrolab");
  ASSERT_EQ(old_files.videos.size(), 1u);
  EXPECT_EQ(old_files.videos[0].offset_s, -0.575);
  // Five videos: one line naming the file and the field.
  SessionFiles five = files;
  five.videos.assign(5, files.videos[0]);
  WriteSessionFile(dir / "five.acrolab", five, view);
  try {
    ReadSessionFile(dir / "five.acrolab");
    ADD_FAILURE() << "five videos were read";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("five.acrolab"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("videos"), std::string::npos) << e.what();
  }
}

// The skill designer: the paper's example skill (1¾ front with ½ twist) opened, its keyframes in
// the table, Model 2 run on the worker thread: J drops at least 10 times (docs/skill-design.md:
// 10.1), the timing chart is shown, the flight is simulated and previewed beside the design; Model
// 1 cancelled; the design saved is a folder `overlay --ghost` reads; a bad skill file is a dialog
// and the skill stays. Then the back tuck: a joint angle edited in the pose table (the result goes,
// the skill file saved reads back with it), an edit the reader refuses (the dialog, nothing
// changes), Model 2, the design shown over the sample routine's video as the ghost, and compared
// with the real back tuck.
TEST(Studio, TheSkillDesignerRunsModel2OnThePapersExample) {
  MainWindow w;
  w.resize(1920, 1080);
  w.show();
  const fs::path skill = acro::testing::SourceDir() / "samples/skills/front_1_3_4_half_twist.yaml";
  SkillWindow* designer = w.OpenSkillDesigner(skill.string());
  ASSERT_NE(designer, nullptr);
  ASSERT_TRUE(designer->last_error().empty()) << designer->last_error();
  const analysis::Skill file = analysis::ReadSkill(skill);
  ASSERT_EQ(designer->keyframes()->rowCount(), int(file.keyframes.size()));
  EXPECT_EQ(designer->keyframes()->item(0, 0)->text().toStdString(), file.keyframes[0].name);
  designer->Run(2);
  ASSERT_TRUE(
      WaitUntil([&] { return !designer->running() && designer->result() != nullptr; }, 120000))
      << designer->last_error();
  const analysis::SkillOptimizationResult& r = *designer->result();
  EXPECT_GE(r.objective_initial / r.objective, 10.0);
  EXPECT_EQ(designer->timing_plot()->chart().title.rfind("Keyframe timing", 0), 0u);
  EXPECT_FALSE(designer->keyframes()->item(1, 2)->text().isEmpty());  // optimised times shown
  // The momentum chart: |H| about the centre of mass, initial against optimised.
  designer->ShowChart(1);
  EXPECT_EQ(designer->timing_plot()->chart().title, "Angular momentum about the centre of mass");
  ASSERT_EQ(designer->timing_plot()->chart().series.size(), 2u);
  designer->ShowChart(0);
  // The flight simulated: its landing in the line under the window, and beside the design in the
  // preview (two rows) at the landing.
  ASSERT_NE(designer->simulation(), nullptr);
  EXPECT_NE(designer->summary().find("The simulated flight"), std::string::npos)
      << designer->summary();
  designer->SetPreviewTime(file.flight_time_s);
  EXPECT_EQ(designer->preview()->image().height(), 2 * 300);
  Shot("studio_skill_designer");
  // Model 1 takes minutes here: Cancel stops it within a few seconds, the Model 2 result stays.
  designer->Run(1);
  EXPECT_TRUE(designer->running());
  QTest::qWait(500);
  QElapsedTimer stopping;
  stopping.start();
  designer->Cancel();
  ASSERT_TRUE(WaitUntil([&] { return !designer->running(); }, 60000));
  EXPECT_LT(stopping.elapsed(), 15000);
  EXPECT_NE(designer->summary().find("Cancelled"), std::string::npos) << designer->summary();
  ASSERT_NE(designer->result(), nullptr);
  EXPECT_EQ(designer->result()->model, analysis::SkillModel::kTiming);
  EXPECT_TRUE(designer->last_error().empty()) << designer->last_error();
  const fs::path dir = acro::testing::ScratchDir("studio_design");
  ASSERT_TRUE(designer->SaveDesign((dir / "design").string())) << designer->last_error();
  const analysis::SkillGhost saved = analysis::ReadSkillGhost(
      dir / "design", analysis::MakeStandardHumanModel(analysis::MakeAthleteBody(file.athlete)));
  EXPECT_EQ(saved.name, file.name);
  std::ofstream(dir / "bad.yaml") << "name: [unclosed\n";
  EXPECT_FALSE(designer->OpenSkill((dir / "bad.yaml").string()));
  EXPECT_NE(designer->last_error().find("bad.yaml"), std::string::npos) << designer->last_error();
  EXPECT_EQ(designer->keyframes()->rowCount(), int(file.keyframes.size()));  // kept

  // The back tuck: its "tuck" keyframe's right knee edited in the pose table.
  const fs::path tuck_file = acro::testing::SourceDir() / "samples/skills/back_tuck.yaml";
  ASSERT_TRUE(designer->OpenSkill(tuck_file.string())) << designer->last_error();
  designer->Run(2);
  ASSERT_TRUE(
      WaitUntil([&] { return !designer->running() && designer->result() != nullptr; }, 120000));
  const int tuck = 2;
  ASSERT_EQ(designer->skill()->keyframes[tuck].name, "tuck");
  designer->keyframes()->setCurrentCell(tuck, 0);
  QTableWidget* pose = designer->pose();
  int knee_row = -1;
  for (int row = 0; row < pose->rowCount(); ++row)
    if (pose->item(row, 0)->text() == "r_knee_flexion") knee_row = row;
  ASSERT_GE(knee_row, 3);
  pose->item(knee_row, 1)->setText("120");
  const int knee = analysis::StandardJointDofIndex("r_shank", 0);
  EXPECT_NEAR(designer->skill()->keyframes[tuck].joint_angles_rad(knee), 120 * M_PI / 180, 1e-12);
  EXPECT_EQ(designer->result(), nullptr);  // it described the old pose
  ASSERT_TRUE(designer->SaveSkill((dir / "my_tuck.yaml").string())) << designer->last_error();
  const analysis::Skill mine = analysis::ReadSkill(dir / "my_tuck.yaml");
  EXPECT_NEAR(mine.keyframes[tuck].joint_angles_rad(knee), 120 * M_PI / 180, 1e-12);
  EXPECT_NEAR(mine.keyframes[tuck].joint_angles_rad(analysis::StandardJointDofIndex("l_shank", 0)),
              145 * M_PI / 180,  // the file's, untouched
              1e-12);
  // A somersault 170° or more from the next keyframe's: the reader's words, nothing changes.
  const double before = designer->skill()->keyframes[tuck].somersault_rad;
  EXPECT_FALSE(designer->EditPose(tuck, 0, 135.0));  // 175° from the closing's −40°
  EXPECT_NE(designer->last_error().find("170"), std::string::npos) << designer->last_error();
  EXPECT_EQ(designer->skill()->keyframes[tuck].somersault_rad, before);

  // The design over the athlete: the sample routine open, Model 2 again, the ghost in every flight.
  w.OpenFiles(SampleFiles());
  ASSERT_TRUE(WaitUntil([&] { return w.session() != nullptr && !w.busy(); }, 180000))
      << w.last_error();
  designer->Run(2);
  ASSERT_TRUE(
      WaitUntil([&] { return !designer->running() && designer->result() != nullptr; }, 120000));
  ASSERT_TRUE(designer->ShowOverAthlete()) << designer->last_error();
  const analysis::JumpMetrics& two = w.session()->analysis().jumps.at(1);
  w.SetCursor(two.flight.takeoff_frame + 50);
  ASSERT_NE(w.view_frame(), nullptr);
  EXPECT_TRUE(w.view_frame()->ghost_shown);
  EXPECT_NE(w.view_frame()->heads_up.find("ghost: back tuck (design)"), std::string::npos)
      << w.view_frame()->heads_up;
  designer->hide();
  CloseDialogs();
  Shot("studio_design_ghost");
  // And compared with the real back tuck (jump 2), from the design's folder.
  ASSERT_TRUE(designer->SaveDesign((dir / "my_tuck").string())) << designer->last_error();
  ASSERT_TRUE(w.OpenCompareWithDesign(2, (dir / "my_tuck").string())) << w.last_error();
  EXPECT_EQ(w.compare()->scene().b().label, "back tuck (design)");
  EXPECT_EQ(w.cursor(), two.flight.takeoff_frame);
  w.SetCursor(two.flight.takeoff_frame + 50);
  EXPECT_GT(w.compare()->tau(), 0.4);
  Shot("studio_compare_design");
  EXPECT_FALSE(w.OpenCompareWithDesign(2, (dir / "no_such_design").string()));
  EXPECT_NE(w.last_error().find("no_such_design"), std::string::npos) << w.last_error();
}

// Video → Detect the athlete (docs/studio.md): the sample's video in a folder of its own (the
// detections are kept beside it), detected with the full model on the worker, then drawn over the
// video around the athlete; a second run reads them back from that folder; without the models
// installed, the one line saying what to run and nothing started.
TEST(Studio, DetectsTheAthleteInTheVideoAndDrawsTheKeypoints) {
  ACRO_REQUIRE_POSE_MODELS();
  const fs::path dir = acro::testing::ScratchDir("studio_detect");
  SessionFiles files = SampleFiles();
  fs::copy_file(files.videos.at(0).video, dir / "side_camera.mp4");
  files.videos.at(0).video = (dir / "side_camera.mp4").string();
  MainWindow w;
  w.resize(1920, 1080);
  w.show();
  ASSERT_TRUE(QTest::qWaitForWindowExposed(&w));
  w.OpenFiles(files);
  ASSERT_TRUE(WaitUntil([&] { return w.session() != nullptr && !w.busy(); }, 180000))
      << w.last_error();
  ASSERT_TRUE(w.last_error().empty()) << w.last_error();
  Session& s = *w.session();
  constexpr int kFrame = 150;  // in the third jump's flight
  w.SetCursor(s.SampleOf(kFrame));
  ASSERT_EQ(w.video_frame_index(), kFrame);
  const capture::VideoFrame before = w.drawn_frame();
  EXPECT_EQ(w.detected_frames(), 0);

  // Without the models: one line, nothing started.
  const char* models = std::getenv("ACRO_MODELS");
  const std::string kept = models ? models : "";
  setenv("ACRO_MODELS", (dir / "no_models").c_str(), 1);
  EXPECT_FALSE(w.DetectPoses(0, "full"));
  if (kept.empty())
    unsetenv("ACRO_MODELS");
  else
    setenv("ACRO_MODELS", kept.c_str(), 1);
  const std::string refused = w.last_error();
  EXPECT_NE(refused.find("install-models.sh"), std::string::npos) << refused;
  EXPECT_FALSE(w.busy());
  CloseDialogs();

  ASSERT_TRUE(w.DetectPoses(0, "full"));
  ASSERT_TRUE(WaitUntil([&] { return !w.busy(); }, 600000));
  ASSERT_EQ(w.last_error(), refused);  // no new dialog
  const int detected = w.detected_frames();
  EXPECT_GE(detected, 0.9 * s.video(0).num_frames()) << detected;  // the athlete is always in view
  EXPECT_TRUE(fs::exists(dir / "acrolab-detect/side_camera/detect.json"));
  EXPECT_NE(w.status_text().find("kept in"), std::string::npos) << w.status_text();
  Shot("studio_detect");

  // The keypoints drawn: pixels changed, all of them around the athlete (the box of the skeleton
  // drawn, grown by the dots' and lines' width).
  const capture::VideoFrame& after = w.drawn_frame();
  ASSERT_EQ(after.index, kFrame);
  ASSERT_EQ(after.pixels.size(), before.pixels.size());
  const capture::DetectedPerson* pose = w.detected_pose(0, kFrame);
  ASSERT_NE(pose, nullptr);
  Eigen::AlignedBox2d box;
  for (int j = 0; j < pose->cols(); ++j)
    if ((*pose)(2, j) >= 0.2) box.extend(Eigen::Vector2d((*pose)(0, j), (*pose)(1, j)));
  ASSERT_FALSE(box.isEmpty());
  int changed = 0, outside = 0;
  for (int y = 0; y < after.height; ++y)
    for (int x = 0; x < after.width; ++x) {
      const size_t i = 3 * (size_t(y) * after.width + x);
      if (after.pixels[i] == before.pixels[i] && after.pixels[i + 1] == before.pixels[i + 1] &&
          after.pixels[i + 2] == before.pixels[i + 2])
        continue;
      ++changed;
      outside += box.exteriorDistance(Eigen::Vector2d(x + 0.5, y + 0.5)) > 12.0 ? 1 : 0;
    }
  EXPECT_GT(changed, 500);
  EXPECT_EQ(outside, 0) << changed;

  // A second run: read back from beside the video, the same frames.
  ASSERT_TRUE(w.DetectPoses(0, "full"));
  ASSERT_TRUE(WaitUntil([&] { return !w.busy(); }, 120000));
  EXPECT_EQ(w.detected_frames(), detected);
}

}  // namespace
}  // namespace acro::studio

// The display (an Xvfb of its own when there is none) and the application outlive every test and
// end before the program's static objects (Qt's post routines must run while its GUI is alive).
int main(int argc, char** argv) {
  ::testing::InitGoogleTest(&argc, argv);
  const acro::ui::XDisplay display;
  QApplication app(argc, argv);
  return RUN_ALL_TESTS();
}

namespace acro::studio {
namespace {

// File → Plan a routine…: FIG codes checked against the rules as a panel counts them.
TEST(Studio, RoutinePlannerSaysDAndWhatTheRoutineMisses) {
  MainWindow w;
  RoutinePlanWindow* plan = w.OpenRoutinePlanner();
  ASSERT_NE(plan, nullptr);
  ASSERT_TRUE(QTest::qWaitForWindowExposed(plan));
  // Ten different elements of a senior routine: valid, D the sum of their DD.
  const std::string ten = "822/ 813< 800< 821/ 44/ 43/ 803< 42/ 41< 40<";
  ASSERT_TRUE(plan->SetCodes(ten));
  EXPECT_EQ(plan->table()->rowCount(), 10);
  double sum = 0;
  for (const fig::ScoredElement& e : plan->score().elements) sum += e.difficulty.total();
  EXPECT_NEAR(plan->score().difficulty, sum, 1e-9);
  EXPECT_NE(plan->summary().find("<b>Valid</b>"), std::string::npos) << plan->summary();
  EXPECT_NE(plan->summary().find(fmt::format("<b>D {:.1f}</b>", sum)), std::string::npos)
      << plan->summary();
  Shot("studio_routine_plan");
  // A repeated element: its DD struck and said; the routine still ten elements.
  ASSERT_TRUE(plan->SetCodes("822/ 813< 800< 821/ 44/ 43/ 803< 42/ 41< 822/"));
  EXPECT_TRUE(plan->table()->item(9, 4)->text().startsWith("no: "));
  // An age group's first routine: its missing requirement named.
  ASSERT_TRUE(plan->SetRules(
      (acro::testing::SourceDir() / "rules/fig-wagc-13-16-first-routine.yaml").string()));
  EXPECT_NE(plan->summary().find("requirement missing"), std::string::npos) << plan->summary();
  EXPECT_NE(plan->summary().find("Not valid"), std::string::npos);
  // Short: interrupted. A typo: said, with the code.
  ASSERT_TRUE(plan->SetRules(""));
  ASSERT_TRUE(plan->SetCodes("40o 41/"));
  EXPECT_NE(plan->summary().find("ends after 2 of 10"), std::string::npos) << plan->summary();
  EXPECT_FALSE(plan->SetCodes("40o 4x1/"));
  EXPECT_NE(plan->summary().find("4x1/"), std::string::npos) << plan->summary();
  EXPECT_EQ(plan->table()->rowCount(), 0);
  // A bad rule file: the dialog, the rules in use stay.
  const fs::path bad = acro::testing::ScratchDir("studio_rules") / "bad.yaml";
  std::ofstream(bad) << "name: x\nsource: y\nroutine:\n  elements: 99\n";
  EXPECT_FALSE(plan->SetRules(bad.string()));
  EXPECT_NE(plan->last_error().find("bad.yaml"), std::string::npos) << plan->last_error();
  CloseDialogs();
}

}  // namespace
}  // namespace acro::studio
