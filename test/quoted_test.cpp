// Double-quoted strings for JSON and YAML: one escaper, two styles.
#include "io/quoted.hpp"

#include <gtest/gtest.h>

namespace stac {
namespace {

TEST(Quoted, CommonEscapesAreAlike) {
  for (QuoteStyle style : {QuoteStyle::kJson, QuoteStyle::kYaml})
    EXPECT_EQ(doubleQuoted("a\"b\\c\nd\re\tf", style), "\"a\\\"b\\\\c\\nd\\re\\tf\"");
}

TEST(Quoted, OtherControlCharactersPerStyle) {
  const std::string s = std::string("x\x01y\x1f") + "\x7f" + "\xc3\xa9";  // é stays UTF-8
  EXPECT_EQ(doubleQuoted(s, QuoteStyle::kJson), "\"x\\u0001y\\u001f\x7f\xc3\xa9\"");
  EXPECT_EQ(doubleQuoted(s, QuoteStyle::kYaml), "\"x\\x01y\\x1F\\x7F\xc3\xa9\"");
  EXPECT_EQ(doubleQuoted("", QuoteStyle::kYaml), "\"\"");
}

}  // namespace
}  // namespace stac
