#include "acro/studio/studio.h"

#include <QApplication>

#include "main_window.h"

namespace acro::studio {

int RunStudio(int argc, char** argv, const SessionFiles& files, const std::string& session_file) {
  QApplication qt(argc, argv);
  MainWindow window;
  window.show();
  if (!session_file.empty()) {
    window.OpenSessionFile(session_file);
  } else if (!files.trial.empty()) {
    window.OpenFiles(files);
  }
  return qt.exec();
}

}  // namespace acro::studio
