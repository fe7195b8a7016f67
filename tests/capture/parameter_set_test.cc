// ParameterSet: lookups (case-insensitive, duplicate group names), Set/GetOrAddGroup, value
// conversions and the builders.

#include <gtest/gtest.h>

#include "acro/capture/parameter_set.h"

namespace acro::capture {
namespace {

TEST(ParameterSet, BuildersAndConversions) {
  const Parameter labels =
      MakeStringsParameter("LABELS", {"RASI", "LONGNAME", ""}, 0, "marker names");
  EXPECT_EQ(labels.type, ParameterType::kChar);
  EXPECT_EQ(labels.dimensions, (std::vector<std::uint8_t>{8, 3}));
  EXPECT_EQ(labels.chars.size(), 24u);
  EXPECT_EQ(labels.ElementCount(), 24u);
  EXPECT_EQ(labels.AsStrings(), (std::vector<std::string>{"RASI", "LONGNAME", ""}));
  EXPECT_EQ(labels.description, "marker names");
  EXPECT_TRUE(labels.AsDoubles().empty());
  // Width larger than the longest entry pads with blanks.
  EXPECT_EQ(MakeStringsParameter("L", {"A"}, 4).chars, (std::vector<char>{'A', ' ', ' ', ' '}));

  const Parameter units = MakeStringParameter("UNITS", "mm");
  EXPECT_EQ(units.dimensions, (std::vector<std::uint8_t>{2}));
  EXPECT_EQ(units.AsString(), "mm");
  EXPECT_EQ(units.AsStrings(), (std::vector<std::string>{"mm"}));

  const Parameter frames = MakeInt16Parameter("FRAMES", {-25536}, {});  // 40000 stored in 16 bits
  EXPECT_EQ(frames.ElementCount(), 1u);
  EXPECT_EQ(frames.AsDoubles(), (std::vector<double>{-25536}));
  EXPECT_EQ(frames.AsUnsigned(), (std::vector<std::uint32_t>{40000}));

  const Parameter corners = MakeFloatParameter("CORNERS", std::vector<float>(24, 1.5f), {3, 4, 2});
  EXPECT_EQ(corners.ElementCount(), 24u);
  EXPECT_EQ(corners.AsDoubles().size(), 24u);
  EXPECT_EQ(corners.AsUnsigned()[0], 1u);

  Parameter bytes;
  bytes.type = ParameterType::kByte;
  bytes.bytes = {188};  // c3d.org sample 33: an unsigned byte
  EXPECT_EQ(bytes.AsDoubles(), (std::vector<double>{188}));
  EXPECT_EQ(bytes.AsUnsigned(), (std::vector<std::uint32_t>{188}));

  // Trailing NULs and blanks are trimmed; leading blanks are kept ("Point    1").
  Parameter padded;
  padded.type = ParameterType::kChar;
  padded.dimensions = {6, 2};
  padded.chars = {' ', 'A', ' ', '\0', '\0', ' ', 'B', 'C', 'D', 'E', 'F', 'G'};
  EXPECT_EQ(padded.AsStrings(), (std::vector<std::string>{" A", "BCDEFG"}));
  // A zero first dimension holds no strings.
  Parameter empty;
  empty.type = ParameterType::kChar;
  empty.dimensions = {0, 0};
  EXPECT_TRUE(empty.AsStrings().empty());
  EXPECT_EQ(empty.ElementCount(), 0u);
}

TEST(ParameterSet, FindSetAndGroups) {
  ParameterSet set;
  EXPECT_EQ(set.FindGroup("POINT"), nullptr);
  EXPECT_FALSE(set.FindDouble("POINT", "RATE").has_value());
  set.Set("POINT", MakeFloatParameter("RATE", {120.0f}, {}, "frame rate"));
  set.Set("ANALOG", MakeInt16Parameter("USED", {16}, {}));
  ASSERT_EQ(set.groups().size(), 2u);
  EXPECT_EQ(set.groups()[0].id, 1);
  EXPECT_EQ(set.groups()[1].id, 2);
  // Case-insensitive names.
  EXPECT_EQ(set.FindDouble("point", "rate").value(), 120.0);
  EXPECT_NE(set.Find("Analog", "Used"), nullptr);
  // Replacing keeps the stored description when the new value has none, and the lock flag.
  set.Find("POINT", "RATE")->locked = true;
  set.Set("POINT", MakeFloatParameter("RATE", {240.0f}, {}));
  EXPECT_EQ(set.FindDouble("POINT", "RATE").value(), 240.0);
  EXPECT_EQ(set.Find("POINT", "RATE")->description, "frame rate");
  EXPECT_TRUE(set.Find("POINT", "RATE")->locked);
  EXPECT_EQ(set.FindGroup("POINT")->parameters.size(), 1u);
  // Strings.
  set.Set("POINT", MakeStringParameter("UNITS", "mm"));
  EXPECT_EQ(set.FindString("POINT", "UNITS").value(), "mm");
  EXPECT_FALSE(set.FindString("POINT", "RATE").has_value());
  // GetOrAddGroup returns the existing group, or a new one with the next id.
  EXPECT_EQ(&set.GetOrAddGroup("point"), set.FindGroup("POINT"));
  EXPECT_EQ(set.GetOrAddGroup("EVENT").id, 3);
  // Two groups of one name (c3d.org sample 33): Find looks into each.
  ParameterGroup a{10, "PROCESSING", "", false, {MakeFloatParameter("A", {1.0f}, {})}};
  ParameterGroup b{11, "PROCESSING", "", false, {MakeFloatParameter("B", {2.0f}, {})}};
  set.mutable_groups().push_back(a);
  set.mutable_groups().push_back(b);
  EXPECT_EQ(set.FindDouble("PROCESSING", "A").value(), 1.0);
  EXPECT_EQ(set.FindDouble("PROCESSING", "B").value(), 2.0);
  EXPECT_EQ(set.GetOrAddGroup("NEW").id, 12);
}

}  // namespace
}  // namespace acro::capture
