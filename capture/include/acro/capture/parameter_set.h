#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace acro::capture {

/// Storage type of a C3D parameter (C3D manual, "The parameter section"): the signed byte that
/// precedes the dimensions. -1 = character, 1 = byte, 2 = 16-bit integer, 4 = 32-bit float.
enum class ParameterType : std::int8_t { kChar = -1, kByte = 1, kInt16 = 2, kFloat = 4 };

/// One C3D parameter with its values decoded to host representation. Multi-dimensional arrays are
/// stored flat in file order (first dimension fastest), `dimensions` gives their shape; a scalar
/// has no dimensions. Character arrays keep every byte, padding included, so that a written file
/// reproduces them exactly.
struct Parameter {
  std::string name;
  std::string description;
  bool locked = false;  // the C3D "locked" flag: a negative name length
  ParameterType type = ParameterType::kInt16;
  std::vector<std::uint8_t> dimensions;
  std::vector<char> chars;           // kChar
  std::vector<std::uint8_t> bytes;   // kByte
  std::vector<std::int16_t> int16s;  // kInt16
  std::vector<float> floats;         // kFloat

  /// Number of elements (product of the dimensions; 1 for a scalar).
  std::size_t ElementCount() const;
  /// Values as doubles whatever the storage type (int16 as signed). Empty for kChar.
  std::vector<double> AsDoubles() const;
  /// int16 values read as unsigned 16-bit (for counts that exceed 32767, e.g. POINT:FRAMES).
  std::vector<std::uint32_t> AsUnsigned() const;
  /// Character arrays split into strings of dimensions[0] characters, trailing blanks and NULs
  /// removed, as UTF-8 (a string that is not UTF-8 is read as Latin-1 and transcoded; `chars`
  /// keeps the file's bytes, which the writer keeps when the text is unchanged).
  std::vector<std::string> AsStrings() const;
  /// The whole character array as one string, trailing blanks and NULs removed, as UTF-8.
  std::string AsString() const;
};

/// A C3D parameter group: a numeric id (positive in the file; parameters refer to it by -id) and
/// its parameters in file order.
struct ParameterGroup {
  int id = 0;
  std::string name;
  std::string description;
  bool locked = false;
  std::vector<Parameter> parameters;

  const Parameter* Find(std::string_view parameter_name) const;
  Parameter* Find(std::string_view parameter_name);
};

/// Every group and parameter of a C3D file, in file order. Names are compared case-insensitively
/// (the C3D manual: names are upper case, but some writers do not follow it).
class ParameterSet {
 public:
  const std::vector<ParameterGroup>& groups() const { return groups_; }
  std::vector<ParameterGroup>& mutable_groups() { return groups_; }

  const ParameterGroup* FindGroup(std::string_view group) const;
  ParameterGroup* FindGroup(std::string_view group);
  const Parameter* Find(std::string_view group, std::string_view parameter) const;
  Parameter* Find(std::string_view group, std::string_view parameter);

  /// Returns the group, creating it (with the next free id) if it does not exist.
  ParameterGroup& GetOrAddGroup(std::string_view group);
  /// Sets (replacing or appending) a parameter in a group that is created if needed.
  Parameter& Set(std::string_view group, Parameter parameter);

  /// Convenience lookups: std::nullopt when absent or empty.
  std::optional<double> FindDouble(std::string_view group, std::string_view parameter) const;
  std::optional<std::string> FindString(std::string_view group, std::string_view parameter) const;

 private:
  std::vector<ParameterGroup> groups_;
};

/// Builders for writers and tests.
Parameter MakeFloatParameter(std::string name,
                             std::vector<float> values,
                             std::vector<std::uint8_t> dimensions,
                             std::string description = {});
Parameter MakeInt16Parameter(std::string name,
                             std::vector<std::int16_t> values,
                             std::vector<std::uint8_t> dimensions,
                             std::string description = {});
/// A 2-D character array of `strings.size()` entries padded with blanks to the longest (or to
/// `width` when larger).
Parameter MakeStringsParameter(std::string name,
                               const std::vector<std::string>& strings,
                               std::size_t width = 0,
                               std::string description = {});
Parameter MakeStringParameter(std::string name,
                              const std::string& value,
                              std::string description = {});

}  // namespace acro::capture
