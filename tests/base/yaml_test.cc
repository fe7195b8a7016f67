#include "acro/base/yaml.h"

#include <cmath>
#include <string>

#include <gtest/gtest.h>

#include "acro/base/input_error.h"

namespace acro {
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
      "...\n",
      "f.yaml");
  const YamlNode& markers = root.At("markers");
  ASSERT_EQ(markers.items().size(), 2u);
  EXPECT_EQ(markers.items()[0].At("name").AsString(), "LASI");
  EXPECT_EQ(markers.items()[0].At("offset_m").AsDoubleList(), (std::vector<double>{0.1, 0.12, 0}));
  EXPECT_EQ(markers.items()[1].At("name").AsString(), "it's");
  EXPECT_EQ(markers.items()[1].At("segment").line(), 7);
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
  // yaml-cpp's own words, with our file and line in front.
  EXPECT_EQ(ErrorOf("a: 1\n  b: 2\n"), "f.yaml: line 2: illegal map value");
  EXPECT_EQ(ErrorOf("a: 1\n\tb: 2\n"), "f.yaml: line 2: illegal tab when looking for indentation");
  // The end of the file is where the missing bracket is noticed.
  EXPECT_EQ(ErrorOf("a: [1, 2\n"), "f.yaml: line 2: end of sequence flow not found");
  EXPECT_NE(ErrorOf("a:\n  - 1\n  b: 2\n").find("f.yaml: line 3:"), std::string::npos);
  EXPECT_EQ(ErrorOf("just text\nmore: 1\n"), "f.yaml: line 2: illegal map value");
  // What a settings file never needs is refused by us, with the line.
  EXPECT_EQ(ErrorOf("a: 1\n---\nb: 2\n"),
            "f.yaml: line 2: a second document: one document per file");
  EXPECT_EQ(ErrorOf("a: 1\n...\nb: 2\n"),
            "f.yaml: line 3: a second document: one document per file");
  EXPECT_EQ(ErrorOf("a: 1\nb: 2\na: 3\n"), "f.yaml: line 3: duplicate key 'a'");
  EXPECT_EQ(ErrorOf("a: 1\n[1, 2]: 3\n"), "f.yaml: line 2: a key must be a plain name");
}

TEST(Yaml, ReadsWhatYamlCppReads) {
  // Flow maps and sequences, quoted strings with colons and hashes, comments after values, block
  // scalars, anchors and aliases: the shapes a person editing a file by hand may use.
  const YamlNode root = ParseYaml(
      "name: \"Back tuck: 40o # not a comment\"  # a comment\n"
      "take_off: {vz_m_per_s: 7.8, vy_m_per_s: 0.015}\n"
      "arms: &arms [-170, 0, 10]\n"
      "keyframes:\n"
      "  - {name: 'open: kick out', arms: *arms}\n"
      "notes: |\n"
      "  two lines\n"
      "  of notes\n",
      "f.yaml");
  EXPECT_EQ(root.At("name").AsString(), "Back tuck: 40o # not a comment");
  EXPECT_TRUE(root.At("name").quoted());
  EXPECT_DOUBLE_EQ(root.At("take_off").At("vz_m_per_s").AsDouble(), 7.8);
  EXPECT_EQ(root.At("take_off").At("vy_m_per_s").line(), 2);
  const YamlNode& keyframe = root.At("keyframes").items().at(0);
  EXPECT_EQ(keyframe.At("name").AsString(), "open: kick out");
  EXPECT_EQ(keyframe.At("arms").AsDoubleList(), (std::vector<double>{-170, 0, 10}));
  EXPECT_EQ(root.At("notes").AsString(), "two lines\nof notes\n");
}

TEST(Yaml, HostileInputIsRefusedNotFatal) {
  // 30,000 nested brackets: refused (yaml-cpp's depth guard or ours), no stack overflow.
  EXPECT_NE(ErrorOf("a: " + std::string(30000, '[')).find("f.yaml: line 1:"), std::string::npos);
  // Deeper than our limit but shallow for yaml-cpp.
  std::string deep = "a: ";
  for (int i = 0; i < 70; ++i) deep += "[";
  for (int i = 0; i < 70; ++i) deep += "]";
  EXPECT_EQ(ErrorOf(deep), "f.yaml: line 1: nested deeper than 64 levels");
  // Aliases that expand ten-fold per level: 10^7 values from a few hundred bytes.
  std::string bomb = "a0: &a0 [x, x, x, x, x, x, x, x, x, x]\n";
  for (int i = 1; i <= 7; ++i) {
    const std::string prev = "*a" + std::to_string(i - 1);
    bomb += "a" + std::to_string(i) + ": &a" + std::to_string(i) + " [";
    for (int k = 0; k < 10; ++k) bomb += (k ? ", " : "") + prev;
    bomb += "]\n";
  }
  EXPECT_NE(ErrorOf(bomb).find("values (aliases expanding?)"), std::string::npos);
  // A stray comma before any key: yaml-cpp 0.7 hands out empty documents for ever from it (its
  // LoadAll ran out of memory; found by the YAML fuzzer). One line, at once.
  EXPECT_EQ(ErrorOf(",a:"), "f.yaml: line 1: not YAML here (a stray ',' before any key?)");
  EXPECT_EQ(ErrorOf(" ,  joints_deg:\n"),
            "f.yaml: line 1: not YAML here (a stray ',' before any key?)");
  // 200,000 keys: read in linear time (the duplicate check is a hash set).
  std::string many;
  for (int i = 0; i < 200000; ++i) many += "k" + std::to_string(i) + ": 1\n";
  EXPECT_EQ(ParseYaml(many, "f.yaml").entries().size(), 200000u);
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
}  // namespace acro
