#include "library_window.h"

#include <QComboBox>
#include <QDialogButtonBox>
#include <QHBoxLayout>
#include <QHeaderView>
#include <QLabel>
#include <QPushButton>
#include <QTableWidget>
#include <QVBoxLayout>

#include <fmt/format.h>

namespace acro::studio {

LibraryDialog::LibraryDialog(const std::string& library, QWidget* parent)
    : QDialog(parent), path_(library) {
  setWindowTitle(QString::fromStdString("Library: " + library));
  resize(980, 560);
  const library::Library lib(library, library::Library::Mode::kReadOnly);
  auto* layout = new QVBoxLayout(this);
  auto* filter = new QHBoxLayout;
  filter->addWidget(new QLabel("Athlete:"));
  athletes_ = new QComboBox;
  athletes_->addItem("every athlete");
  for (const library::AthleteSummary& a : lib.ListAthletes())
    athletes_->addItem(QString::fromStdString(a.name));
  filter->addWidget(athletes_, 1);
  layout->addLayout(filter);
  table_ = new QTableWidget(0, 7);
  table_->setHorizontalHeaderLabels(
      {"date", "athlete", "jumps", "DD", "ToF (s)", "verdict", "trial"});
  table_->setSelectionBehavior(QAbstractItemView::SelectRows);
  table_->setSelectionMode(QAbstractItemView::SingleSelection);
  table_->setEditTriggers(QAbstractItemView::NoEditTriggers);
  table_->horizontalHeader()->setStretchLastSection(true);
  table_->verticalHeader()->hide();
  layout->addWidget(table_, 1);
  auto* buttons = new QDialogButtonBox(QDialogButtonBox::Open | QDialogButtonBox::Cancel);
  layout->addWidget(buttons);
  connect(buttons, &QDialogButtonBox::accepted, this, &QDialog::accept);
  connect(buttons, &QDialogButtonBox::rejected, this, &QDialog::reject);
  connect(table_, &QTableWidget::cellDoubleClicked, this, [this](int, int) { accept(); });
  connect(
      athletes_, qOverload<int>(&QComboBox::currentIndexChanged), this, [this](int) { Fill(); });
  Fill();
}

LibraryDialog::~LibraryDialog() = default;

void LibraryDialog::Fill() {
  const std::string athlete =
      athletes_->currentIndex() <= 0 ? std::string() : athletes_->currentText().toStdString();
  try {
    const library::Library lib(path_, library::Library::Mode::kReadOnly);
    trials_ = lib.ListTrials(athlete);
  } catch (const std::exception&) {
    trials_.clear();  // (the library was readable a moment ago; an empty table says it now)
  }
  table_->setRowCount(int(trials_.size()));
  for (int r = 0; r < int(trials_.size()); ++r) {
    const library::TrialSummary& t = trials_[size_t(r)];
    const std::string cells[7] = {t.session_date,
                                  t.athlete,
                                  std::to_string(t.num_jumps),
                                  fmt::format("{:.1f}", t.difficulty),
                                  fmt::format("{:.3f}", t.time_of_flight_s),
                                  t.verdict,
                                  t.path};
    for (int c = 0; c < 7; ++c)
      table_->setItem(r, c, new QTableWidgetItem(QString::fromStdString(cells[c])));
  }
  table_->resizeColumnsToContents();
  if (!trials_.empty()) table_->selectRow(0);
}

std::optional<SessionFiles> LibraryDialog::SelectedFiles() const {
  const int row = table_->currentRow();
  if (result() != QDialog::Accepted || row < 0 || row >= int(trials_.size())) return std::nullopt;
  const library::TrialSummary& t = trials_[size_t(row)];
  SessionFiles files;
  files.trial = t.path;
  files.athlete = t.athlete_profile_path;
  if (!t.video_path.empty() && !t.calibration_path.empty()) {
    VideoFiles video;
    video.video = t.video_path;
    video.calibration = t.calibration_path;
    files.videos.push_back(video);
  }
  return files;
}

}  // namespace acro::studio
