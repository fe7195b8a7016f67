#include "acro/analysis/yaml.h"

#include <cmath>
#include <string>

#include <gtest/gtest.h>

#include "acro/base/input_error.h"

namespace acro::analysis {
namespace {

// The message of the InputError that parsing `text` throws ("" when it does not throw).
std::string ErrorOf(const std::string& text) {
  try {
    ParseYaml(text, "f.yaml");
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

TEST(Yaml, NestedMapsSequencesAndScalars) {
  const YamlNode root = ParseYaml(
      "# athlete\n"
      "name: \"Ann # not a comment\"   # a comment\n"
      "height_m: 1.75\n"
      "tags: [a, 'b c', \"d\"]\n"
      "nested:\n"
      "  inner:\n"
      "    x: -2.5e-1\n"
      "  list:\n"
      "    - 1\n"
      "    - 2\n"
      "  flat:\n"
      "  - 3\n"
      "  - [4, 5]\n"
      "empty:\n"
      "last: ~\n",
      "f.yaml");
  ASSERT_TRUE(root.IsMap());
  EXPECT_EQ(root.At("name").AsString(), "Ann # not a comment");
  EXPECT_EQ(root.At("height_m").AsDouble(), 1.75);
  EXPECT_EQ(root.At("height_m").line(), 3);
  EXPECT_EQ(root.At("tags").AsStringList(), (std::vector<std::string>{"a", "b c", "d"}));
  EXPECT_EQ(root.At("nested").At("inner").At("x").AsDouble(), -0.25);
  EXPECT_EQ(root.At("nested").At("list").AsDoubleList(), (std::vector<double>{1, 2}));
  const YamlNode& flat = root.At("nested").At("flat");
  ASSERT_EQ(flat.items().size(), 2u);
  EXPECT_EQ(flat.items()[0].AsInt(), 3);
  EXPECT_EQ(flat.items()[1].AsDoubleList(), (std::vector<double>{4, 5}));
  EXPECT_TRUE(root.At("empty").IsNull());
  EXPECT_TRUE(root.At("last").IsNull());
  EXPECT_EQ(root.Find("absent"), nullptr);
  // Entries keep file order.
  ASSERT_EQ(root.entries().size(), 6u);
  EXPECT_EQ(root.entries()[0].first, "name");
  EXPECT_EQ(root.entries()[5].first, "last");
}

TEST(Yaml, SequenceOfMapsOnTheDashLine) {
  const YamlNode root = ParseYaml(
      "---\n"
      "markers:\n"
      "  - name: LASI\n"
      "    segment: pelvis\n"
      "    offset_m: [0.1, 0.12, 0]\n"
      "  - name: 'it''s'\n"
      "    segment: thorax\n"
      "...\n"
      "ignored: after the end marker\n",
      "f.yaml");
  const YamlNode& markers = root.At("markers");
  ASSERT_EQ(markers.items().size(), 2u);
  EXPECT_EQ(markers.items()[0].At("name").AsString(), "LASI");
  EXPECT_EQ(markers.items()[0].At("offset_m").AsDoubleList(), (std::vector<double>{0.1, 0.12, 0}));
  EXPECT_EQ(markers.items()[1].At("name").AsString(), "it's");
  EXPECT_EQ(markers.items()[1].At("segment").line(), 7);
  EXPECT_EQ(root.Find("ignored"), nullptr);
}

TEST(Yaml, QuotedEscapesAndColonsInPlainScalars) {
  const YamlNode root =
      ParseYaml("url: http://example.org/a#b\nq: \"tab\\there\\n\"\nk: \"7\"\n", "f.yaml");
  EXPECT_EQ(root.At("url").AsString(), "http://example.org/a#b");
  EXPECT_EQ(root.At("q").AsString(), "tab\there\n");
  // A quoted number stays a string.
  EXPECT_TRUE(root.At("k").quoted());
  EXPECT_THROW(root.At("k").AsDouble(), InputError);
}

TEST(Yaml, NumbersFollowYamlSpelling) {
  double v = 0;
  EXPECT_TRUE(ParseYamlNumber(".01", &v));
  EXPECT_EQ(v, 0.01);
  EXPECT_TRUE(ParseYamlNumber("+4", &v));
  EXPECT_EQ(v, 4.0);
  EXPECT_TRUE(ParseYamlNumber("-1e3", &v));
  EXPECT_EQ(v, -1000.0);
  EXPECT_TRUE(ParseYamlNumber(".inf", &v));
  EXPECT_TRUE(std::isinf(v));
  EXPECT_FALSE(ParseYamlNumber("inf", &v));
  EXPECT_FALSE(ParseYamlNumber("1.2.3", &v));
  EXPECT_FALSE(ParseYamlNumber("12 cm", &v));
  EXPECT_FALSE(ParseYamlNumber("+-1", &v));
  EXPECT_FALSE(ParseYamlNumber("-", &v));
  EXPECT_FALSE(ParseYamlNumber("", &v));
}

TEST(Yaml, ByteOrderMarkAndWindowsLineEndingsAreAccepted) {
  const YamlNode root = ParseYaml("\xEF\xBB\xBFname: A\r\nlist: [1, 2]\r\n", "f.yaml");
  EXPECT_EQ(root.At("name").AsString(), "A");
  EXPECT_EQ(root.At("list").AsDoubleList(), (std::vector<double>{1, 2}));
}

TEST(Yaml, EmptyDocumentIsNull) {
  EXPECT_TRUE(ParseYaml("", "f.yaml").IsNull());
  EXPECT_TRUE(ParseYaml("# only a comment\n\n", "f.yaml").IsNull());
}

TEST(Yaml, SyntaxErrorsNameFileAndLine) {
  EXPECT_EQ(ErrorOf("a: 1\n  b: 2\n"), "f.yaml: line 2: unexpected indentation");
  EXPECT_EQ(ErrorOf("a: 1\na: 2\n"), "f.yaml: line 2: duplicate key 'a'");
  EXPECT_EQ(ErrorOf("a: 1\n\tb: 2\n"), "f.yaml: line 2: tab character in indentation");
  EXPECT_NE(ErrorOf("a: [1, 2\n").find("f.yaml: line 1: unterminated flow sequence"),
            std::string::npos);
  EXPECT_NE(ErrorOf("a: {b: 1}\n").find("line 1: flow maps"), std::string::npos);
  EXPECT_NE(ErrorOf("a: |\n  text\n").find("line 1: block scalars"), std::string::npos);
  EXPECT_NE(ErrorOf("a: &x 1\n").find("line 1: anchors"), std::string::npos);
  EXPECT_NE(ErrorOf("a: \"open\n").find("line 1: unterminated quoted string"), std::string::npos);
  EXPECT_NE(ErrorOf("a:\n  - 1\n  b: 2\n").find("line 3:"), std::string::npos);
  EXPECT_EQ(ErrorOf("just text\nmore: 1\n"),
            "f.yaml: line 2: unexpected content after a top-level value");
  EXPECT_NE(ErrorOf("a: 1\n---\nb: 2\n").find("line 2: a second document"), std::string::npos);
}

TEST(Yaml, TypeErrorsNameFileLineAndKey) {
  const YamlNode root = ParseYaml("x: 1\nmass_kg: heavy\nlist: [1, b]\nnone:\n", "p.yaml");
  try {
    root.At("mass_kg").AsDouble();
    FAIL() << "no exception";
  } catch (const InputError& e) {
    EXPECT_STREQ(e.what(), "p.yaml: line 2: mass_kg: 'heavy' is not a number");
  }
  try {
    root.At("none").AsDouble();
    FAIL() << "no exception";
  } catch (const InputError& e) {
    EXPECT_STREQ(e.what(), "p.yaml: line 4: none: has no value (expected a number)");
  }
  EXPECT_THROW(root.At("list").AsDoubleList(), InputError);
  EXPECT_THROW(root.At("x").AsStringList(), InputError);
  try {
    root.At("height_m");
    FAIL() << "no exception";
  } catch (const InputError& e) {
    EXPECT_STREQ(e.what(), "p.yaml: line 1: the required key 'height_m' is missing");
  }
  try {
    root.RequireKnownKeys({"x", "mass_kg", "list"});
    FAIL() << "no exception";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("p.yaml: line 4: unknown key 'none'"), std::string::npos);
  }
}

}  // namespace
}  // namespace acro::analysis
