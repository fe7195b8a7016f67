#include "acro/studio/studio.h"

#include <QApplication>
#include <QScreen>

#include <unistd.h>

#include <cstdio>
#include <filesystem>
#include <optional>

#include "acro/base/process.h"
#include "live_window.h"
#include "main_window.h"

namespace acro::studio {

int RunStudio(int argc,
              char** argv,
              const SessionFiles& files,
              const std::string& session_file,
              const std::string& library) {
  QApplication qt(argc, argv);
  MainWindow window;
  window.SetLibrary(library);
  window.show();
  if (!session_file.empty()) {
    window.OpenSessionFile(session_file);
  } else if (!files.trial.empty() || OneVideoAlone(files)) {
    window.OpenFiles(files);
  } else if (!library.empty()) {
    window.OpenFromLibrary(library, false);
  }
  return qt.exec();
}

int RunStudioLive(int argc,
                  char** argv,
                  const pipeline::LiveRequest& request,
                  double delay_s,
                  const std::string& athlete,
                  const std::string& library) {
  QApplication qt(argc, argv);
  // Each routine analysed by the acrolab program installed beside this one, when it is there.
  std::optional<pipeline::RoutineAnalysisOptions> analyses;
  const std::filesystem::path acrolab =
      std::filesystem::path(CurrentExecutable()).parent_path() / "acrolab";
  if (::access(acrolab.c_str(), X_OK) != 0 && (!athlete.empty() || !library.empty())) {
    std::fprintf(stderr,
                 "acrolab-studio: %s: not there, and the routines' analyses (--athlete, "
                 "--library) need it\n",
                 acrolab.c_str());
    return 2;
  }
  if (::access(acrolab.c_str(), X_OK) == 0) {
    analyses.emplace();
    analyses->acrolab = acrolab;
    analyses->athlete = athlete;
    analyses->library = library;
    analyses->intrinsics = request.intrinsics;
    analyses->camera = request.camera;
  }
  LiveWindow window(request, delay_s, analyses);
  // The hall's screen: a second one when there is one (the first stays the operator's).
  const QList<QScreen*> screens = QGuiApplication::screens();
  if (screens.size() > 1) {
    window.setGeometry(screens[1]->availableGeometry());
    window.showMaximized();
  } else {
    window.show();
  }
  return qt.exec();
}

}  // namespace acro::studio
