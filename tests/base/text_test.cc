// Text helpers for messages and labels: control bytes escaped for a terminal, UTF-8 validated
// against the standard's table of well-formed sequences (Unicode 15, table 3-7), Latin-1
// transcoded. Each checked against bytes written out by hand.
#include "acro/base/text.h"

#include <string>

#include <gtest/gtest.h>

namespace acro {
namespace {

TEST(Text, EscapeForTerminalShowsControlBytes) {
  EXPECT_EQ(EscapeForTerminal(std::string("a\nb\tc\rd", 7)), "a\\nb\\tc\\rd");
  EXPECT_EQ(EscapeForTerminal(std::string("1\x1b[2J\0x", 7)), "1\\x1b[2J\\x00x");
  EXPECT_EQ(EscapeForTerminal("\x7f"), "\\x7f");
  EXPECT_EQ(EscapeForTerminal("Genou_\xc3\xa9"), "Genou_\xc3\xa9");  // UTF-8 kept
  EXPECT_EQ(EscapeForTerminal(std::string(10, 'x'), 4), "xxxx… (6 more bytes)");
}

TEST(Text, Utf8IsValidatedByTheStandardsTable) {
  EXPECT_TRUE(IsValidUtf8("plain ascii"));
  EXPECT_TRUE(IsValidUtf8("\xc3\xa9"));           // é
  EXPECT_TRUE(IsValidUtf8("\xe2\x82\xac"));       // €
  EXPECT_TRUE(IsValidUtf8("\xf0\x9f\xa4\xb8"));   // 🤸 (U+1F938)
  EXPECT_FALSE(IsValidUtf8("\xe9"));              // Latin-1 é
  EXPECT_FALSE(IsValidUtf8("\xc0\xaf"));          // overlong '/'
  EXPECT_FALSE(IsValidUtf8("\xe0\x80\xaf"));      // overlong, three bytes
  EXPECT_FALSE(IsValidUtf8("\xed\xa0\x80"));      // a surrogate, U+D800
  EXPECT_FALSE(IsValidUtf8("\xf4\x90\x80\x80"));  // above U+10FFFF
  EXPECT_FALSE(IsValidUtf8("\xe2\x82"));          // cut short
  EXPECT_FALSE(IsValidUtf8("\x80"));              // a lone continuation byte
}

TEST(Text, Latin1IsTranscodedAndUtf8KeptAsItIs) {
  EXPECT_EQ(Utf8FromUtf8OrLatin1("Genou_\xe9"), "Genou_\xc3\xa9");
  EXPECT_EQ(Utf8FromUtf8OrLatin1("\xb0\xff"), "\xc2\xb0\xc3\xbf");  // ° ÿ
  EXPECT_EQ(Utf8FromUtf8OrLatin1("Genou_\xc3\xa9"), "Genou_\xc3\xa9");
  EXPECT_EQ(Utf8FromUtf8OrLatin1("LKNE"), "LKNE");
}

}  // namespace
}  // namespace acro
