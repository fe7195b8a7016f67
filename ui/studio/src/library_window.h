#pragma once

// File → Open from library…: the season library's trials (docs/library.md) in a table — date,
// athlete, jumps, DD, time of flight, verdict, file — filtered by athlete; the chosen trial opens
// in the main window with the athlete profile it was stored with and its attached video.

#include <QDialog>

#include <optional>
#include <string>
#include <vector>

#include "acro/library/library.h"
#include "acro/studio/session.h"

class QComboBox;
class QTableWidget;

namespace acro::studio {

class LibraryDialog : public QDialog {
  Q_OBJECT

 public:
  /// Reads the library's athletes and trials. Throws acro::InputError when `library` cannot be
  /// opened (not there, not a library, damaged: the caller shows the one line).
  LibraryDialog(const std::string& library, QWidget* parent = nullptr);
  ~LibraryDialog() override;

  QTableWidget* table() { return table_; }
  QComboBox* athletes() { return athletes_; }
  /// The files of the selected trial (the dialog accepted), or empty.
  std::optional<SessionFiles> SelectedFiles() const;

 private:
  void Fill();

  std::string path_;
  std::vector<library::TrialSummary> trials_;  // the table's rows
  QComboBox* athletes_ = nullptr;
  QTableWidget* table_ = nullptr;
};

}  // namespace acro::studio
