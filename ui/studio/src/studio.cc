#include "acro/studio/studio.h"

#include <QApplication>

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
  } else if (!files.trial.empty()) {
    window.OpenFiles(files);
  } else if (!library.empty()) {
    window.OpenFromLibrary(library, false);
  }
  return qt.exec();
}

}  // namespace acro::studio
