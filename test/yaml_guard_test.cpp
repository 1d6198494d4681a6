// The scan in front of yaml-cpp: every input found to hang yaml-cpp 0.7 is
// refused with its file, line and column; valid sensors files, and the
// places where ',' and brackets are text, pass.
#include <gtest/gtest.h>

#include <string>

#include "io/yaml_guard.hpp"
#include "stac/error.hpp"
#include "support/arm_files.hpp"

namespace stac {
namespace {

void expectRefused(const std::string& yaml, int line, int column, const std::string& what) {
  try {
    checkYamlFlowIndicators(yaml, "s.yaml");
    ADD_FAILURE() << "passed: " << yaml;
  } catch (const InputError& e) {
    EXPECT_EQ(e.line(), line) << yaml << "\n" << e.what();
    EXPECT_EQ(e.column(), column) << yaml << "\n" << e.what();
    EXPECT_NE(std::string(e.what()).find(what), std::string::npos) << e.what();
  }
}

const char* kComma = "a ',' outside any [ ] or { } collection";

// Each of these loops yaml-cpp 0.7 (checked under `timeout 5`).
TEST(YamlGuard, RefusesACommaOutsideAnyCollection) {
  expectRefused(",]", 1, 1, kComma);
  expectRefused(", 1]", 1, 1, kComma);
  expectRefused(" ,]", 1, 2, kComma);
  expectRefused("\t,", 1, 2, kComma);
  expectRefused("\xEF\xBB\xBF,", 1, 1, kComma);  // after a byte order mark
  expectRefused(",a", 1, 1, kComma);
  expectRefused("[1], 2", 1, 4, kComma);
  expectRefused("'x' ,", 1, 5, kComma);
  expectRefused("\"x\",", 1, 4, kComma);
  expectRefused("- [1]\n,", 2, 1, kComma);
  expectRefused("- a\n,", 2, 1, kComma);
  expectRefused("# c\n,]", 2, 1, kComma);
  expectRefused("---\n,", 2, 1, kComma);
  expectRefused("--- ,", 1, 5, kComma);
  expectRefused("%YAML 1.2\n---\n,", 3, 1, kComma);
  expectRefused("a: 1\n...\n,", 3, 1, kComma);
  expectRefused("&a ,", 1, 4, kComma);
  expectRefused("!!map ,", 1, 7, kComma);
  expectRefused("mocap:\n  sigma: 0.002\n,", 3, 1, kComma);
}

TEST(YamlGuard, RefusesUnbalancedBrackets) {
  expectRefused("]", 1, 1, "']' closes no '['");
  expectRefused("a: 1\n}", 2, 1, "'}' closes no '{'");
  expectRefused("a: [1, 2}", 1, 9, "'}' does not close the '[' of line 1 column 4");
}

TEST(YamlGuard, PassesCommasAndBracketsThatAreText) {
  for (const char* ok : {
           "a: [1, 2]\nb: {c: 1, d: [3, 4]}\n",
           "a: x,y\nb: x [1, 2\nc: 1 ,\n",       // plain scalars in block context
           "a: 'x, ]' # and, [ here\n",          // quoted, then a comment
           "a: \"x\\\", ]\"\nb: 'it''s, ]'\n",   // escapes inside quotes
           "a: \"two\n  lines, ]\"\n",           // a quoted scalar over two lines
           "a: |\n  , ]\n  {\nb: >-\n  ,\n",     // block scalars
           "a: [x, ,]\nb: {,}\nc: [,]\n",        // empty entries inside collections
           "- [it's, a#b]\n- {k: v}\n",
           "name: a]\nother: 1}\n",
           "",
           "a: [1, 2\n",  // never closed: yaml-cpp reports it (and does not hang)
       })
    EXPECT_NO_THROW(checkYamlFlowIndicators(ok, "s.yaml")) << ok;
  EXPECT_NO_THROW(checkYamlFlowIndicators(test::kArmTruth, "s.yaml"));
  EXPECT_NO_THROW(checkYamlFlowIndicators(test::kArmSeed, "s.yaml"));
}

}  // namespace
}  // namespace stac
