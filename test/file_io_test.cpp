// file_io: the number format (YAML 1.1 and 1.2 floats that round-trip
// exactly), whole-file reads, all-or-nothing writes and sameFile.
#include <gtest/gtest.h>
#include <sys/stat.h>
#include <unistd.h>
#include <yaml-cpp/yaml.h>

#include <cmath>
#include <cstdlib>
#include <cstring>
#include <limits>
#include <random>
#include <regex>

#include "stac/error.hpp"
#include "stac/file_io.hpp"
#include "support/test_util.hpp"

namespace stac {
namespace {

// YAML 1.1's float (tag:yaml.org,2002:float, base 10) and YAML 1.2's core
// schema float.
const std::regex kYaml11Float(R"(^[-+]?([0-9][0-9_]*)?\.[0-9.]*([eE][-+][0-9]+)?$)");
const std::regex kYaml12Float(R"(^[-+]?(\.[0-9]+|[0-9]+(\.[0-9]*)?)([eE][-+]?[0-9]+)?$)");

bool sameBits(double a, double b) { return std::memcmp(&a, &b, sizeof a) == 0; }

// The text reads back, with strtod and with yaml-cpp, as exactly v, and is a
// float to YAML 1.1 and 1.2 readers.
void expectRoundTrip(double v) {
  const std::string s = formatNumber(v);
  EXPECT_TRUE(std::regex_match(s, kYaml11Float)) << s;
  EXPECT_TRUE(std::regex_match(s, kYaml12Float)) << s;
  EXPECT_TRUE(sameBits(std::strtod(s.c_str(), nullptr), v)) << s;
  // yaml-cpp reads through an istream, which refuses subnormals.
  if (std::fpclassify(v) != FP_SUBNORMAL) {
    const YAML::Node n = YAML::Load("x: " + s);
    EXPECT_TRUE(sameBits(n["x"].as<double>(), v)) << s;
  }
}

TEST(FormatNumber, Examples) {
  EXPECT_EQ(formatNumber(1.0), "1.0");
  EXPECT_EQ(formatNumber(-3.0), "-3.0");
  EXPECT_EQ(formatNumber(0.5), "0.5");
  EXPECT_EQ(formatNumber(0.1), "0.1");
  EXPECT_EQ(formatNumber(1e-05), "1.0e-05");
  EXPECT_EQ(formatNumber(1.5e-07), "1.5e-07");
  EXPECT_EQ(formatNumber(-2.5e+20), "-2.5e+20");
  EXPECT_EQ(formatNumber(1e100), "1.0e+100");
  EXPECT_EQ(formatNumber(0.0), "0.0");
  EXPECT_EQ(formatNumber(-0.0), "-0.0");
  EXPECT_EQ(formatNumber(0.002), "0.002");
  EXPECT_EQ(formatNumber(std::numeric_limits<double>::quiet_NaN()), ".nan");
  EXPECT_EQ(formatNumber(std::numeric_limits<double>::infinity()), ".inf");
  EXPECT_EQ(formatNumber(-std::numeric_limits<double>::infinity()), "-.inf");
}

TEST(FormatNumber, NonFiniteAreYamlSpecialFloats) {
  EXPECT_TRUE(std::isnan(YAML::Load(formatNumber(NAN)).as<double>()));
  EXPECT_EQ(YAML::Load(formatNumber(INFINITY)).as<double>(), INFINITY);
  EXPECT_EQ(YAML::Load(formatNumber(-INFINITY)).as<double>(), -INFINITY);
}

TEST(FormatNumber, ExtremesRoundTrip) {
  for (double v : {1.0, 0.1, 1.0 / 3.0, M_PI, -M_PI, 1e-05, 1e21, 1e22, 1.2345678901234568e+20,
                   123456789012345680000.0, 9007199254740993.0, 0.30000000000000004,
                   std::numeric_limits<double>::max(), std::numeric_limits<double>::lowest(),
                   std::numeric_limits<double>::min(), std::numeric_limits<double>::epsilon(),
                   std::numeric_limits<double>::denorm_min(), -0.0, 0.0})
    expectRoundTrip(v);
}

TEST(FormatNumber, RandomValuesRoundTrip) {
  std::mt19937_64 rng(3);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  std::uniform_int_distribution<int> e(-60, 60);
  for (int i = 0; i < 3000; ++i) {
    double v = std::ldexp(u(rng), e(rng));
    if (i % 3 == 0) {  // any finite bit pattern
      const uint64_t bits = rng();
      std::memcpy(&v, &bits, sizeof v);
      if (!std::isfinite(v)) continue;
    }
    expectRoundTrip(v);
  }
}

// ---- files ----

TEST(ReadTextFile, ReadsBytesExactly) {
  test::TempDir dir;
  std::string text = "a,b\r\n1,2\n";
  text += std::string(1, '\0') + std::string(200000, 'x');
  test::writeFile(dir.file("f.txt"), text);
  EXPECT_EQ(readTextFile(dir.file("f.txt")), text);
  test::writeFile(dir.file("empty.txt"), "");
  EXPECT_EQ(readTextFile(dir.file("empty.txt")), "");
}

TEST(ReadTextFile, MissingFileIsAnInputErrorNamingIt) {
  test::TempDir dir;
  const std::string path = dir.file("missing.yaml");
  try {
    readTextFile(path);
    FAIL();
  } catch (const InputError& e) {
    EXPECT_EQ(e.file(), path);
    EXPECT_EQ(std::string(e.what()).rfind(path + ": ", 0), 0u) << e.what();
  }
}

TEST(ReadTextFile, DirectoryIsAnInputError) {
  test::TempDir dir;
  try {
    readTextFile(dir.path());
    FAIL();
  } catch (const InputError& e) {
    EXPECT_EQ(e.file(), dir.path());
  }
}

TEST(WriteFileAtomically, CreatesAndReplacesLeavingNoTemporary) {
  test::TempDir dir;
  const std::string path = dir.file("out.yaml");
  writeFileAtomically(path, "first\n");
  EXPECT_EQ(test::readFile(path), "first\n");
  struct stat st;
  ASSERT_EQ(::stat(path.c_str(), &st), 0);
  EXPECT_EQ(st.st_mode & 0777, 0644u);
  ::chmod(path.c_str(), 0600);
  writeFileAtomically(path, "second, longer\n");
  EXPECT_EQ(test::readFile(path), "second, longer\n");
  ASSERT_EQ(::stat(path.c_str(), &st), 0);
  EXPECT_EQ(st.st_mode & 0777, 0600u) << "the replaced file's mode is kept";
  writeFileAtomically(path, "");
  EXPECT_EQ(test::readFile(path), "");
  EXPECT_EQ(dir.list(), std::vector<std::string>{"out.yaml"});
}

TEST(WriteFileAtomically, FailureThrowsAndLeavesNothing) {
  test::TempDir dir;
  // No such directory: the temporary cannot even be created.
  EXPECT_THROW(writeFileAtomically(dir.file("no/such/dir.yaml"), "x"), std::runtime_error);
  // The target is a directory: the rename fails; the temporary is removed.
  ASSERT_EQ(::mkdir(dir.file("sub").c_str(), 0755), 0);
  EXPECT_THROW(writeFileAtomically(dir.file("sub"), "x"), std::runtime_error);
  EXPECT_EQ(dir.list(), std::vector<std::string>{"sub"});
}

TEST(SameFile, DeviceAndInode) {
  test::TempDir dir;
  test::writeFile(dir.file("a"), "1");
  test::writeFile(dir.file("b"), "1");
  ASSERT_EQ(::symlink(dir.file("a").c_str(), dir.file("link").c_str()), 0);
  ASSERT_EQ(::link(dir.file("a").c_str(), dir.file("hard").c_str()), 0);
  EXPECT_TRUE(sameFile(dir.file("a"), dir.file("a")));
  EXPECT_TRUE(sameFile(dir.file("a"), dir.path() + "/./a"));
  EXPECT_TRUE(sameFile(dir.file("a"), dir.file("link")));
  EXPECT_TRUE(sameFile(dir.file("hard"), dir.file("a")));
  EXPECT_FALSE(sameFile(dir.file("a"), dir.file("b")));
  EXPECT_FALSE(sameFile(dir.file("a"), dir.file("missing")));
  EXPECT_FALSE(sameFile(dir.file("missing"), dir.file("missing")));
}

}  // namespace
}  // namespace stac
