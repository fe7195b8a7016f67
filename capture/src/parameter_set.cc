#include "acro/capture/parameter_set.h"

#include <algorithm>
#include <cctype>

#include "acro/base/text.h"

namespace acro::capture {
namespace {

// Case-insensitive comparison of group and parameter names (C3D manual, "The parameter section":
// names are stored in upper case, but not every writer follows it).
bool SameName(std::string_view a, std::string_view b) {
  if (a.size() != b.size()) return false;
  for (std::size_t i = 0; i < a.size(); ++i) {
    if (std::toupper(static_cast<unsigned char>(a[i])) !=
        std::toupper(static_cast<unsigned char>(b[i]))) {
      return false;
    }
  }
  return true;
}

// Removes trailing blanks and NULs (C3D pads character arrays with blanks; some writers use NUL).
std::string TrimRight(std::string s) {
  while (!s.empty() && (s.back() == ' ' || s.back() == '\0')) s.pop_back();
  return s;
}

}  // namespace

std::size_t Parameter::ElementCount() const {
  std::size_t n = 1;
  for (std::uint8_t d : dimensions) n *= d;
  return n;
}

std::vector<double> Parameter::AsDoubles() const {
  switch (type) {
    case ParameterType::kByte:
      return std::vector<double>(bytes.begin(), bytes.end());
    case ParameterType::kInt16:
      return std::vector<double>(int16s.begin(), int16s.end());
    case ParameterType::kFloat:
      return std::vector<double>(floats.begin(), floats.end());
    case ParameterType::kChar:
      break;
  }
  return {};
}

std::vector<std::uint32_t> Parameter::AsUnsigned() const {
  std::vector<std::uint32_t> out;
  switch (type) {
    case ParameterType::kByte:
      out.assign(bytes.begin(), bytes.end());
      break;
    case ParameterType::kInt16:
      out.reserve(int16s.size());
      for (std::int16_t v : int16s) out.push_back(static_cast<std::uint16_t>(v));
      break;
    case ParameterType::kFloat:
      out.reserve(floats.size());
      for (float v : floats)
        out.push_back(v > 0 && v < 4.3e9f ? static_cast<std::uint32_t>(v) : 0u);
      break;
    case ParameterType::kChar:
      break;
  }
  return out;
}

std::vector<std::string> Parameter::AsStrings() const {
  std::vector<std::string> out;
  if (type != ParameterType::kChar) return out;
  // A 1-D character array is one string; higher dimensions are strings of dimensions[0] characters.
  if (dimensions.size() <= 1) {
    out.push_back(Utf8FromUtf8OrLatin1(TrimRight(std::string(chars.begin(), chars.end()))));
    return out;
  }
  const std::size_t width = dimensions[0];
  const std::size_t count = width == 0 ? 0 : chars.size() / width;
  out.reserve(count);
  for (std::size_t i = 0; i < count; ++i) {
    out.push_back(Utf8FromUtf8OrLatin1(
        TrimRight(std::string(chars.begin() + i * width, chars.begin() + (i + 1) * width))));
  }
  return out;
}

std::string Parameter::AsString() const {
  if (type != ParameterType::kChar) return {};
  return Utf8FromUtf8OrLatin1(TrimRight(std::string(chars.begin(), chars.end())));
}

const Parameter* ParameterGroup::Find(std::string_view parameter_name) const {
  for (const Parameter& p : parameters) {
    if (SameName(p.name, parameter_name)) return &p;
  }
  return nullptr;
}

Parameter* ParameterGroup::Find(std::string_view parameter_name) {
  for (Parameter& p : parameters) {
    if (SameName(p.name, parameter_name)) return &p;
  }
  return nullptr;
}

const ParameterGroup* ParameterSet::FindGroup(std::string_view group) const {
  for (const ParameterGroup& g : groups_) {
    if (SameName(g.name, group)) return &g;
  }
  return nullptr;
}

ParameterGroup* ParameterSet::FindGroup(std::string_view group) {
  for (ParameterGroup& g : groups_) {
    if (SameName(g.name, group)) return &g;
  }
  return nullptr;
}

const Parameter* ParameterSet::Find(std::string_view group, std::string_view parameter) const {
  // Files may hold two groups of one name (c3d.org sample 33: two PROCESSING groups): look in each.
  for (const ParameterGroup& g : groups_) {
    if (!SameName(g.name, group)) continue;
    if (const Parameter* p = g.Find(parameter)) return p;
  }
  return nullptr;
}

Parameter* ParameterSet::Find(std::string_view group, std::string_view parameter) {
  for (ParameterGroup& g : groups_) {
    if (!SameName(g.name, group)) continue;
    if (Parameter* p = g.Find(parameter)) return p;
  }
  return nullptr;
}

ParameterGroup& ParameterSet::GetOrAddGroup(std::string_view group) {
  if (ParameterGroup* g = FindGroup(group)) return *g;
  // The next free id: C3D group ids are 1..127 in the file (stored negated).
  int id = 1;
  for (const ParameterGroup& g : groups_) id = std::max(id, g.id + 1);
  ParameterGroup added;
  added.id = id;
  added.name = std::string(group);
  groups_.push_back(std::move(added));
  return groups_.back();
}

Parameter& ParameterSet::Set(std::string_view group, Parameter parameter) {
  ParameterGroup& g = GetOrAddGroup(group);
  if (Parameter* existing = g.Find(parameter.name)) {
    // Keep the stored description and lock flag when the new value carries none.
    if (parameter.description.empty()) parameter.description = existing->description;
    parameter.locked = parameter.locked || existing->locked;
    *existing = std::move(parameter);
    return *existing;
  }
  g.parameters.push_back(std::move(parameter));
  return g.parameters.back();
}

std::optional<double> ParameterSet::FindDouble(std::string_view group,
                                               std::string_view parameter) const {
  const Parameter* p = Find(group, parameter);
  if (p == nullptr) return std::nullopt;
  std::vector<double> values = p->AsDoubles();
  if (values.empty()) return std::nullopt;
  return values.front();
}

std::optional<std::string> ParameterSet::FindString(std::string_view group,
                                                    std::string_view parameter) const {
  const Parameter* p = Find(group, parameter);
  if (p == nullptr || p->type != ParameterType::kChar || p->chars.empty()) return std::nullopt;
  std::vector<std::string> strings = p->AsStrings();
  if (strings.empty()) return std::nullopt;
  return strings.front();
}

Parameter MakeFloatParameter(std::string name,
                             std::vector<float> values,
                             std::vector<std::uint8_t> dimensions,
                             std::string description) {
  Parameter p;
  p.name = std::move(name);
  p.description = std::move(description);
  p.type = ParameterType::kFloat;
  p.floats = std::move(values);
  p.dimensions = std::move(dimensions);
  return p;
}

Parameter MakeInt16Parameter(std::string name,
                             std::vector<std::int16_t> values,
                             std::vector<std::uint8_t> dimensions,
                             std::string description) {
  Parameter p;
  p.name = std::move(name);
  p.description = std::move(description);
  p.type = ParameterType::kInt16;
  p.int16s = std::move(values);
  p.dimensions = std::move(dimensions);
  return p;
}

Parameter MakeStringsParameter(std::string name,
                               const std::vector<std::string>& strings,
                               std::size_t width,
                               std::string description) {
  for (const std::string& s : strings) width = std::max(width, s.size());
  width = std::min<std::size_t>(width, 255);
  Parameter p;
  p.name = std::move(name);
  p.description = std::move(description);
  p.type = ParameterType::kChar;
  p.dimensions = {static_cast<std::uint8_t>(width), static_cast<std::uint8_t>(strings.size())};
  p.chars.assign(width * strings.size(), ' ');
  for (std::size_t i = 0; i < strings.size(); ++i) {
    std::copy_n(
        strings[i].begin(), std::min(width, strings[i].size()), p.chars.begin() + i * width);
  }
  return p;
}

Parameter MakeStringParameter(std::string name, const std::string& value, std::string description) {
  Parameter p;
  p.name = std::move(name);
  p.description = std::move(description);
  p.type = ParameterType::kChar;
  const std::size_t n = std::min<std::size_t>(value.size(), 255);
  p.dimensions = {static_cast<std::uint8_t>(n)};
  p.chars.assign(value.begin(), value.begin() + n);
  return p;
}

}  // namespace acro::capture
