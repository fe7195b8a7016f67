#pragma once

// The studio's routine planner (File → Plan a routine…): the routine a coach writes down as FIG
// codes ("821o 42/ 812/ …"), checked as a panel would count it against a rule file — each element's
// difficulty (a repeat struck), the requirements each meets — with D and whether the routine is
// valid, and what it misses when not (docs/studio.md). The same functions as `acrolab routine
// --rules` (analysis/fig); nothing is simulated here (the command line designs the flights).

#include <QWidget>

#include <string>

#include "acro/fig/rules.h"
#include "acro/fig/score_sheet.h"

class QLabel;
class QLineEdit;
class QTableWidget;

namespace acro::studio {

class RoutinePlanWindow : public QWidget {
  Q_OBJECT

 public:
  explicit RoutinePlanWindow(QWidget* parent = nullptr);

  /// The codes as typed; the sheet follows at once. False (the line under the table names the
  /// code at fault, the last good sheet is cleared) for a code that is not a FIG code.
  bool SetCodes(const std::string& codes);
  /// A rule file (rules/*.yaml); empty: the FIG senior routine. False and the dialog with its
  /// one-line error for a bad file (the rules in use stay).
  bool SetRules(const std::string& path);
  QTableWidget* table() { return table_; }
  /// The line under the table: D, valid or what is missing (or the code at fault).
  std::string summary() const;
  const fig::RoutineScore& score() const { return score_; }
  /// The last error shown in a dialog (empty: none).
  const std::string& last_error() const { return last_error_; }

 private:
  void Refresh();

  QLineEdit* codes_ = nullptr;
  QLabel* rules_label_ = nullptr;
  QTableWidget* table_ = nullptr;
  QLabel* summary_ = nullptr;
  fig::RoutineRules rules_ = fig::RoutineRules::FigSenior();
  fig::RoutineScore score_;
  std::string error_;
  std::string last_error_;
};

}  // namespace acro::studio
