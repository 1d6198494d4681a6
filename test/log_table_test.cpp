// logFromTable: a table in memory read as the same table written as CSV
// (the Python module's arrays and DataFrames), computed both ways.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "stac/error.hpp"
#include "stac/log.hpp"

namespace stac {
namespace {

const double kNaN = std::numeric_limits<double>::quiet_NaN();

RowMatrix table() {
  RowMatrix t(3, 3);
  t << 0.0, 1.5, kNaN,  //
      0.01, -2.0, 3.25,  //
      0.02, kNaN, 1e-5;
  return t;
}

TEST(LogTable, EqualsTheSameTableReadAsCsv) {
  const Log csv = parseLog("a,time,b\n1.5,0.0,\n-2.0,0.01,3.25\n,0.02,1.0e-05\n", "x.csv");
  RowMatrix t = table();
  t.col(0).swap(t.col(1));  // the time column second, as in the CSV
  const Log log = logFromTable({"a", "time", "b"}, t, "x.csv");
  EXPECT_EQ(log.path, csv.path);
  EXPECT_EQ(log.columns, csv.columns);
  EXPECT_EQ(log.time_name, csv.time_name);
  EXPECT_EQ(log.time, csv.time);
  EXPECT_EQ(log.line_of_frame, csv.line_of_frame);
  EXPECT_EQ(log.header_line, csv.header_line);
  ASSERT_EQ(log.values.rows(), 3);
  ASSERT_EQ(log.values.cols(), 2);
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 2; ++j) {
      EXPECT_EQ(std::isnan(log.values(i, j)), std::isnan(csv.values(i, j)));
      if (!std::isnan(csv.values(i, j))) {
        EXPECT_EQ(log.values(i, j), csv.values(i, j));
      }
    }
}

std::string errorOf(const std::vector<std::string>& header, const RowMatrix& t) {
  try {
    logFromTable(header, t, "t");
  } catch (const InputError& e) {
    return e.what();
  }
  return "no error";
}

TEST(LogTable, RefusesWhatTheCsvReaderRefusesWithItsMessages) {
  RowMatrix t = table();
  EXPECT_EQ(errorOf({"time", "a", "a"}, t), "t:1:3: column 'a' appears twice in the header");
  EXPECT_EQ(errorOf({"time", "", "b"}, t), "t:1:2: empty column name in the header");
  EXPECT_EQ(errorOf({"time", "t", "b"}, t), "t:1:2: two time columns ('time' and 't')");
  t(1, 0) = kNaN;
  EXPECT_EQ(errorOf({"time", "a", "b"}, t), "t:3:1: column 'time': the time is missing");
  t(1, 0) = 0.01;
  t(2, 2) = -std::numeric_limits<double>::infinity();
  EXPECT_EQ(errorOf({"time", "a", "b"}, t),
            "t:4:3: column 'b': '-inf' is not finite (a missing reading is NaN)");
  EXPECT_THROW(logFromTable({"time", "a"}, t, "t"), std::invalid_argument);
}

TEST(LogTable, WithoutTimeAndWithoutFrames) {
  const Log log = logFromTable({"a", "b"}, RowMatrix(0, 2), "t");
  EXPECT_FALSE(log.hasTime());
  EXPECT_EQ(log.numFrames(), 0);
  EXPECT_EQ(log.columns, (std::vector<std::string>{"a", "b"}));
}

}  // namespace
}  // namespace stac
