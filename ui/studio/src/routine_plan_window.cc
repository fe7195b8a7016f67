#include "routine_plan_window.h"

#include <QFileDialog>
#include <QHBoxLayout>
#include <QHeaderView>
#include <QLabel>
#include <QLineEdit>
#include <QMessageBox>
#include <QPushButton>
#include <QTableWidget>
#include <QVBoxLayout>

#include <exception>
#include <vector>

#include <fmt/format.h>

namespace acro::studio {

RoutinePlanWindow::RoutinePlanWindow(QWidget* parent) : QWidget(parent, Qt::Window) {
  setWindowTitle("Acrolab Studio — plan a routine");
  codes_ = new QLineEdit;
  codes_->setPlaceholderText("FIG codes, e.g. 821o 42/ 812/ 800< 43/ …");
  connect(codes_, &QLineEdit::textChanged, this, [this](const QString& text) {
    SetCodes(text.toStdString());
  });
  rules_label_ = new QLabel;
  auto* rules_button = new QPushButton("Rules…");
  connect(rules_button, &QPushButton::clicked, this, [this] {
    const QString path =
        QFileDialog::getOpenFileName(this, "Rule file", {}, "Rule files (*.yaml *.yml)");
    if (!path.isEmpty()) SetRules(path.toStdString());
  });
  auto* senior = new QPushButton("FIG senior");
  connect(senior, &QPushButton::clicked, this, [this] { SetRules(""); });
  table_ = new QTableWidget(0, 6);
  table_->setHorizontalHeaderLabels(
      {"element", "code", "skill", "DD", "counted", "requirements met"});
  table_->setEditTriggers(QAbstractItemView::NoEditTriggers);
  table_->horizontalHeader()->setStretchLastSection(true);
  table_->verticalHeader()->hide();
  summary_ = new QLabel;
  summary_->setWordWrap(true);
  summary_->setTextInteractionFlags(Qt::TextSelectableByMouse);
  auto* rules_bar = new QHBoxLayout;
  rules_bar->addWidget(rules_label_, 1);
  rules_bar->addWidget(senior);
  rules_bar->addWidget(rules_button);
  auto* layout = new QVBoxLayout(this);
  layout->addWidget(codes_);
  layout->addLayout(rules_bar);
  layout->addWidget(table_, 1);
  layout->addWidget(summary_);
  resize(900, 480);
  Refresh();
}

bool RoutinePlanWindow::SetCodes(const std::string& codes) {
  if (codes_->text().toStdString() != codes) {
    const QSignalBlocker block(codes_);
    codes_->setText(QString::fromStdString(codes));
  }
  error_.clear();
  score_ = fig::RoutineScore{};
  try {
    score_ = fig::ScoreRoutine(rules_, fig::PlannedFlights(codes));
  } catch (const std::exception& e) {
    error_ = e.what();
  }
  Refresh();
  return error_.empty();
}

bool RoutinePlanWindow::SetRules(const std::string& path) {
  try {
    rules_ = path.empty() ? fig::RoutineRules::FigSenior() : fig::LoadRules(path);
  } catch (const std::exception& e) {
    last_error_ = e.what();
    // Not modal: the window stays live (and a test can read it).
    auto* box = new QMessageBox(QMessageBox::Critical,
                                "Acrolab",
                                QString::fromStdString(last_error_),
                                QMessageBox::Ok,
                                this);
    box->setAttribute(Qt::WA_DeleteOnClose);
    box->open();
    return false;
  }
  SetCodes(codes_->text().toStdString());
  return true;
}

std::string RoutinePlanWindow::summary() const {
  if (!error_.empty()) return "Not a routine yet: " + error_;
  if (score_.elements.empty()) return "Type the routine's FIG codes above.";
  const fig::RoutineScore& s = score_;
  std::string text = fmt::format(
      "<b>D {:.1f}</b>{} over {} of {} elements. ",
      s.difficulty,
      s.difficulty_capped ? fmt::format(" (capped; {:.1f} planned)", s.difficulty_uncapped) : "",
      s.elements.size(),
      s.expected_elements);
  std::vector<std::string> why;
  if (s.interrupted) why.push_back(s.interruption);
  for (const std::string& m : s.requirements_missing) why.push_back("requirement missing: " + m);
  for (const std::string& b : s.rule_breaks) why.push_back(b);
  if (why.empty()) {
    text += "<span style=\"color:#1e8c32\"><b>Valid</b> by these rules.</span>";
  } else {
    text += "<span style=\"color:#c8281e\"><b>Not valid</b>:</span> ";
    for (size_t k = 0; k < why.size(); ++k) text += (k ? "; " : "") + why[k];
    text += ".";
  }
  return text;
}

void RoutinePlanWindow::Refresh() {
  rules_label_->setText(
      QString::fromStdString("Rules: <b>" + rules_.name + "</b> (" + rules_.source + ")"));
  table_->setRowCount(int(score_.elements.size()));
  for (size_t r = 0; r < score_.elements.size(); ++r) {
    const fig::ScoredElement& e = score_.elements[r];
    std::string reqs;
    for (const std::string& q : e.requirements) reqs += (reqs.empty() ? "" : "; ") + q;
    const std::vector<std::string> cells = {std::to_string(e.element),
                                            e.code,
                                            e.name,
                                            fmt::format("{:.1f}", e.difficulty.total()),
                                            e.difficulty_counted ? "yes" : "no: " + e.note,
                                            reqs};
    for (size_t c = 0; c < cells.size(); ++c) {
      auto* item = new QTableWidgetItem(QString::fromStdString(cells[c]));
      if (c == 4 && !e.difficulty_counted) item->setForeground(QColor(200, 40, 30));
      table_->setItem(int(r), int(c), item);
    }
  }
  table_->resizeColumnsToContents();
  summary_->setText(QString::fromStdString(summary()));
}

}  // namespace acro::studio
