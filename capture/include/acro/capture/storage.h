#pragma once

#include <filesystem>
#include <map>
#include <string>
#include <string_view>
#include <vector>

#include <Eigen/Core>

namespace acro::capture {

/// A time table as OpenSim stores it (.mot motion files and .sto storage files): a time column
/// and named data columns. Angles in degrees only when `in_degrees` says so.
struct Storage {
  std::string name;                 ///< first header line (the table's name)
  std::vector<std::string> labels;  ///< data column labels, without "time"
  Eigen::VectorXd time_s;
  Eigen::MatrixXd data;  ///< rows = time samples, columns = labels
  bool in_degrees = false;
  /// Further header lines "key=value" kept in order of appearance (DataType, OpenSimVersion, ...).
  std::vector<std::pair<std::string, std::string>> metadata;

  int FindColumn(std::string_view label) const;
};

enum class StorageFlavor {
  kMot,  ///< "name / version=1 / nRows / nColumns / inDegrees / endheader" (OpenSim .mot)
  kSto,  ///< "name / version=1 / OpenSimVersion / inDegrees / DataType=double / endheader" (OpenSim
         ///< 4 .sto)
};

/// Writes a .mot or .sto file (tab separated, "time" first), atomically.
void WriteStorage(const Storage& table, const std::filesystem::path& path, StorageFlavor flavor);
std::string WriteStorageToString(const Storage& table, StorageFlavor flavor);

/// Reads OpenSim .mot/.sto files of either flavour (and the older headers with "nRows=",
/// "nColumns=" and a table name). Throws acro::InputError naming the file and line.
Storage ReadStorage(const std::filesystem::path& path);
Storage ReadStorageFromString(std::string_view text, const std::string& name);

}  // namespace acro::capture
