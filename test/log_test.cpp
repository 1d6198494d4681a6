// The CSV log (SPEC §2): parsing, every error with its file, line, column and
// column name, the exact writeLog -> readLog round trip, and bindLog.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <limits>
#include <random>
#include <string>

#include "stac/error.hpp"
#include "stac/log.hpp"
#include "support/test_util.hpp"

namespace stac {
namespace {

const double kNaN = std::numeric_limits<double>::quiet_NaN();

bool sameBits(double a, double b) { return std::memcmp(&a, &b, sizeof a) == 0; }

// Parses `csv` as "data.csv" and returns the InputError it must throw.
InputError logError(const std::string& csv) {
  try {
    parseLog(csv, "data.csv");
  } catch (const InputError& e) {
    return e;
  }
  ADD_FAILURE() << "no error for:\n" << csv;
  return InputError("", "");
}

// The error names the file, the line, the 1-based column and `what`.
void expectLogError(const std::string& csv, int line, int column, const std::string& what) {
  const InputError e = logError(csv);
  EXPECT_EQ(e.file(), "data.csv");
  EXPECT_EQ(e.line(), line) << e.what();
  EXPECT_EQ(e.column(), column) << e.what();
  const std::string prefix = "data.csv:" + std::to_string(line) + ":" + std::to_string(column);
  EXPECT_EQ(std::string(e.what()).rfind(prefix, 0), 0u) << e.what();
  EXPECT_NE(std::string(e.what()).find(what), std::string::npos) << e.what();
}

TEST(Log, ParsesTheSpecExample) {
  const Log log = parseLog(
      "time,l_elbow_pot,neck_cyl_1,m_forearm.x,m_forearm.y,m_forearm.z\n"
      "0.00,0.512,1.204,0.3012,-0.1200,0.8891\n"
      "0.01,0.515,1.206,,,\n",
      "spec.csv");
  EXPECT_EQ(log.path, "spec.csv");
  EXPECT_EQ(log.time_name, "time");
  ASSERT_EQ(log.columns.size(), 5u);
  EXPECT_EQ(log.columns[0], "l_elbow_pot");
  EXPECT_EQ(log.columns[4], "m_forearm.z");
  ASSERT_EQ(log.numFrames(), 2);
  EXPECT_EQ(log.time, (std::vector<double>{0.0, 0.01}));
  EXPECT_EQ(log.values(0, 0), 0.512);
  EXPECT_EQ(log.values(0, 3), -0.12);
  EXPECT_EQ(log.values(1, 1), 1.206);
  EXPECT_TRUE(std::isnan(log.values(1, 2)));
  EXPECT_TRUE(std::isnan(log.values(1, 4)));
  EXPECT_EQ(log.header_line, 1);
  EXPECT_EQ(log.line_of_frame, (std::vector<int>{2, 3}));
}

TEST(Log, CommentsBlankLinesCrlfWhitespaceAndBom) {
  const Log log = parseLog(
      "\xEF\xBB\xBF# recorded 2024-01-01\r\n"
      "\r\n"
      "  a , t ,b\r\n"
      "# a comment between rows\r\n"
      " 1.5 ,\t0.25, -2e-3 \r\n"
      "\r\n"
      "+3,0.5,4\r\n",
      "x.csv");
  EXPECT_EQ(log.header_line, 3);
  EXPECT_EQ(log.time_name, "t");  // the time column may be anywhere
  EXPECT_EQ(log.columns, (std::vector<std::string>{"a", "b"}));
  ASSERT_EQ(log.numFrames(), 2);
  EXPECT_EQ(log.time, (std::vector<double>{0.25, 0.5}));
  EXPECT_EQ(log.values(0, 0), 1.5);
  EXPECT_EQ(log.values(0, 1), -2e-3);
  EXPECT_EQ(log.values(1, 0), 3.0);
  EXPECT_EQ(log.values(1, 1), 4.0);
  EXPECT_EQ(log.line_of_frame, (std::vector<int>{5, 7}));
}

TEST(Log, TimeColumnNamesAndNoTime) {
  for (const char* name : {"time", "t", "timestamp"}) {
    const Log log = parseLog(std::string("x,") + name + "\n1,2\n", "f.csv");
    EXPECT_EQ(log.time_name, name);
    EXPECT_EQ(log.time, std::vector<double>{2.0});
    EXPECT_EQ(log.columns, std::vector<std::string>{"x"});
  }
  const Log log = parseLog("x,y\n1,2\n", "f.csv");
  EXPECT_FALSE(log.hasTime());
  EXPECT_TRUE(log.time.empty());
  EXPECT_EQ(log.values.cols(), 2);
}

TEST(Log, MissingReadings) {
  const Log log = parseLog("a,b,c,d,e\n,nan,NaN, ,-nan\n", "f.csv");
  for (int c = 0; c < 5; ++c) EXPECT_TRUE(std::isnan(log.values(0, c))) << c;
}

TEST(Log, UnderflowReadsAsTheNearestDouble) {
  const Log log = parseLog("a,b,c\n1e-400,-1e-400,4.9e-324\n", "f.csv");
  EXPECT_EQ(log.values(0, 0), 0.0);
  EXPECT_EQ(log.values(0, 1), 0.0);
  EXPECT_EQ(log.values(0, 2), std::numeric_limits<double>::denorm_min());
}

TEST(Log, HeaderOnlyGivesNoFrames) {
  const Log log = parseLog("# nothing yet\ntime,a\n", "f.csv");
  EXPECT_EQ(log.numFrames(), 0);
  EXPECT_EQ(log.values.cols(), 1);
}

// ---- every error of SPEC §2 ----

TEST(LogError, Inf) { expectLogError("time,a,b\n0,1,2\n0.1,inf,2\n", 3, 2, "column 'a'"); }
TEST(LogError, MinusInf) { expectLogError("time,a,b\n0,1,-inf\n", 2, 3, "column 'b'"); }
TEST(LogError, InfinityIsNotFinite) {
  expectLogError("a,b\n1,Infinity\n", 2, 2, "not finite");
}
TEST(LogError, Text) { expectLogError("time,a,b\n0,1,2\n0.1,2,abc\n", 3, 3, "'abc' is not a number"); }
TEST(LogError, TrailingGarbage) { expectLogError("a,b\n1.5x,2\n", 2, 1, "column 'a'"); }
TEST(LogError, HexIsText) { expectLogError("a,b\n0x10,2\n", 2, 1, "not a number"); }
TEST(LogError, OutOfRange) { expectLogError("a,b\n1,1e400\n", 2, 2, "column 'b'"); }
TEST(LogError, RowTooShort) {
  expectLogError("# c\ntime,a,b\n0,1,2\n0.1,2\n", 4, 3, "no cell for column 'b'");
}
TEST(LogError, RowTooLong) {
  expectLogError("time,a,b\n0,1,2,3\n", 2, 4, "the row has 4 cells, the header has 3");
}
TEST(LogError, DuplicateHeaderName) {
  expectLogError("time,a,b,a\n0,1,2,3\n", 1, 4, "'a' appears twice");
}
TEST(LogError, EmptyHeaderName) { expectLogError("time,a,,b\n", 1, 3, "empty column name"); }
TEST(LogError, TwoTimeColumns) { expectLogError("t,a,time\n", 1, 3, "two time columns"); }
TEST(LogError, MissingTime) { expectLogError("a,time\n1,0\n2,\n", 3, 2, "the time is missing"); }
TEST(LogError, EmptyFile) {
  const InputError e = logError("# only a comment\n\n");
  EXPECT_EQ(e.file(), "data.csv");
  EXPECT_NE(std::string(e.what()).find("empty"), std::string::npos) << e.what();
}
TEST(LogError, MissingFile) {
  test::TempDir dir;
  try {
    readLog(dir.file("nope.csv"));
    FAIL();
  } catch (const InputError& e) {
    EXPECT_EQ(e.file(), dir.file("nope.csv"));
    EXPECT_NE(std::string(e.what()).find("nope.csv"), std::string::npos);
  }
}

// ---- the round trip ----

TEST(Log, WriteReadRoundTripIsExact) {
  std::mt19937_64 rng(42);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  std::uniform_int_distribution<int> exponent(-300, 300);
  Log log;
  log.time_name = "time";
  log.columns = {"j1_pot", "m.0_tip.x", "m.0_tip.y", "m.0_tip.z", "cyl"};
  const int T = 500;
  log.values.resize(T, 5);
  for (int t = 0; t < T; ++t) {
    log.time.push_back(0.01 * t);
    for (int c = 0; c < 5; ++c) {
      const int kind = static_cast<int>(rng() % 10);
      double v = u(rng);
      if (kind == 0) v = kNaN;
      if (kind == 1) v = std::ldexp(u(rng), exponent(rng));
      if (kind == 2) v = std::numeric_limits<double>::denorm_min() * static_cast<double>(rng() % 1000);
      if (kind == 3) v = -0.0;
      if (kind == 4) {  // any finite bit pattern
        const uint64_t bits = rng();
        std::memcpy(&v, &bits, sizeof v);
        if (!std::isfinite(v)) v = 1.0;
      }
      log.values(t, c) = v;
    }
  }
  test::TempDir dir;
  writeLog(dir.file("out.csv"), log);
  EXPECT_EQ(dir.list(), std::vector<std::string>{"out.csv"}) << "no temporary file left";
  const Log back = readLog(dir.file("out.csv"));
  EXPECT_EQ(back.time_name, "time");
  EXPECT_EQ(back.columns, log.columns);
  ASSERT_EQ(back.numFrames(), T);
  for (int t = 0; t < T; ++t) {
    EXPECT_TRUE(sameBits(back.time[t], log.time[t]));
    for (int c = 0; c < 5; ++c) {
      const double a = log.values(t, c), b = back.values(t, c);
      if (std::isnan(a))
        EXPECT_TRUE(std::isnan(b)) << t << "," << c;
      else
        EXPECT_TRUE(sameBits(a, b)) << t << "," << c << ": " << a << " vs " << b;
    }
  }
  // NaN is written as an empty cell.
  Log one;
  one.columns = {"a", "b"};
  one.values.resize(1, 2);
  one.values << kNaN, 0.5;
  writeLog(dir.file("one.csv"), one);
  EXPECT_EQ(test::readFile(dir.file("one.csv")), "a,b\n,0.5\n");
}

TEST(Log, WriteRejectsInfinity) {
  Log log;
  log.columns = {"a"};
  log.values.resize(1, 1);
  log.values(0, 0) = std::numeric_limits<double>::infinity();
  test::TempDir dir;
  EXPECT_THROW(writeLog(dir.file("x.csv"), log), std::invalid_argument);
  EXPECT_TRUE(dir.list().empty());
}

// ---- bindLog ----

SensorSet exampleSensors() {
  SensorSet s;
  s.markers.resize(2);
  s.markers[0].name = "m_forearm";
  s.markers[1].name = "link_3.0_tip";  // names may contain dots
  s.joint_sensors.resize(1);
  s.joint_sensors[0].name = "l_elbow_pot";
  s.tendon_sensors.resize(1);
  s.tendon_sensors[0].name = "neck_cyl_1";
  return s;
}

const char* kBindCsv =
    "time,link_3.0_tip.z,l_elbow_pot,neck_cyl_1,m_forearm.x,m_forearm.y,m_forearm.z,"
    "link_3.0_tip.x,link_3.0_tip.y\n"
    "0.00,3,0.512,1.204,300,-120,889,1,2\n"
    "0.01,,0.515,,301,-121,890,1,2\n"
    "0.02,3,,1.3,302,,891,1,2\n";

TEST(BindLog, SplitsColumnsPerSensorAndScalesMarkers) {
  const Log log = parseLog(kBindCsv, "d.csv");
  const Observations obs = bindLog(log, exampleSensors(), "s.yaml", 0.001);
  ASSERT_EQ(obs.num_frames, 3);
  EXPECT_EQ(obs.time_name, "time");
  EXPECT_EQ(obs.time, (std::vector<double>{0.0, 0.01, 0.02}));
  ASSERT_EQ(obs.marker.cols(), 6);
  EXPECT_DOUBLE_EQ(obs.marker(0, 0), 0.3);
  EXPECT_DOUBLE_EQ(obs.marker(0, 1), -0.12);
  EXPECT_DOUBLE_EQ(obs.marker(0, 2), 0.889);
  EXPECT_DOUBLE_EQ(obs.marker(0, 3), 0.001);
  EXPECT_DOUBLE_EQ(obs.marker(0, 5), 0.003);
  // A marker missing one coordinate is missing as a whole.
  for (int k = 3; k < 6; ++k) EXPECT_TRUE(std::isnan(obs.marker(1, k)));
  for (int k = 0; k < 3; ++k) EXPECT_TRUE(std::isnan(obs.marker(2, k)));
  EXPECT_FALSE(std::isnan(obs.marker(1, 0)));
  EXPECT_EQ(obs.joint(0, 0), 0.512);  // joint and tendon readings are not scaled
  EXPECT_TRUE(std::isnan(obs.joint(2, 0)));
  EXPECT_EQ(obs.tendon(2, 0), 1.3);
  EXPECT_TRUE(std::isnan(obs.tendon(1, 0)));

  const Observations mid = sliceFrames(obs, 1, 3);
  EXPECT_EQ(mid.num_frames, 2);
  EXPECT_EQ(mid.time, (std::vector<double>{0.01, 0.02}));
  EXPECT_EQ(mid.tendon(1, 0), 1.3);
  EXPECT_EQ(sliceFrames(obs, 5, 9).num_frames, 0);
}

TEST(BindLog, MissingColumnNamesBothFiles) {
  std::string csv = kBindCsv;
  csv.replace(csv.find("neck_cyl_1"), 10, "neck_cyl_9");
  const Log log = parseLog(csv, "d.csv");
  try {
    bindLog(log, exampleSensors(), "s.yaml", 1.0);
    FAIL();
  } catch (const InputError& e) {
    const std::string w = e.what();
    EXPECT_EQ(e.file(), "d.csv");
    EXPECT_EQ(w.rfind("d.csv:1", 0), 0u) << w;
    EXPECT_NE(w.find("s.yaml"), std::string::npos) << w;
    EXPECT_NE(w.find("no column for neck_cyl_1"), std::string::npos) << w;
    EXPECT_NE(w.find("neck_cyl_9"), std::string::npos) << "the extra column is listed: " << w;
  }
}

TEST(BindLog, MissingMarkerCoordinate) {
  const Log log = parseLog("l_elbow_pot,neck_cyl_1,m_forearm.x,m_forearm.y,link_3.0_tip.x,"
                           "link_3.0_tip.y,link_3.0_tip.z\n",
                           "d.csv");
  try {
    bindLog(log, exampleSensors(), "s.yaml", 1.0);
    FAIL();
  } catch (const InputError& e) {
    const std::string w = e.what();
    EXPECT_NE(w.find("m_forearm.z"), std::string::npos) << w;
    EXPECT_EQ(w.find("m_forearm.x"), std::string::npos) << w;
    EXPECT_NE(w.find("s.yaml"), std::string::npos) << w;
  }
}

TEST(BindLog, ExtraColumnsAreListed) {
  const Log log = parseLog(
      "stray_1,l_elbow_pot,neck_cyl_1,m_forearm.x,m_forearm.y,m_forearm.z,link_3.0_tip.x,"
      "link_3.0_tip.y,link_3.0_tip.z,stray_2\n",
      "d.csv");
  try {
    bindLog(log, exampleSensors(), "s.yaml", 1.0);
    FAIL();
  } catch (const InputError& e) {
    const std::string w = e.what();
    EXPECT_EQ(w.rfind("d.csv:1", 0), 0u) << w;
    EXPECT_NE(w.find("stray_1, stray_2"), std::string::npos) << w;
    EXPECT_NE(w.find("s.yaml"), std::string::npos) << w;
  }
}

// A header-only log parses to no frames; binding it is an error naming the
// file (and, under UBSan, no Eigen block of the empty matrix).
TEST(BindLog, HeaderOnlyLogHasNoDataRows) {
  const Log log = parseLog(
      "time,l_elbow_pot,neck_cyl_1,m_forearm.x,m_forearm.y,m_forearm.z,link_3.0_tip.x,"
      "link_3.0_tip.y,link_3.0_tip.z\n\n# only a comment\n\n",
      "d.csv");
  EXPECT_EQ(log.numFrames(), 0);
  EXPECT_EQ(log.values.cols(), 8);
  try {
    bindLog(log, exampleSensors(), "s.yaml", 1.0);
    FAIL();
  } catch (const InputError& e) {
    EXPECT_STREQ(e.what(), "d.csv:1: the log has no data rows (a header and nothing after it)");
  }
}

// A 15,000-column header over 40,000 empty lines (100 KB): the reader
// reserves by what the bytes can hold, not lines x columns (4.8 GB).
TEST(ParseLog, WideHeaderOverEmptyLinesStaysSmall) {
  std::string csv;
  for (int c = 0; c < 15000; ++c) csv += (c ? ",c" : "c") + std::to_string(c);
  csv += std::string(40000, '\n');
  const Log log = parseLog(csv, "d.csv");
  EXPECT_EQ(log.numFrames(), 0);
  EXPECT_EQ(log.values.cols(), 15000);
}

TEST(RequireReadings, NamesTheLogAndWhatIsMissing) {
  const SensorSet sensors = exampleSensors();
  const Observations obs = bindLog(parseLog(kBindCsv, "d.csv"), sensors, "s.yaml", 1.0);
  EXPECT_NO_THROW(requireReadings(obs, sensors, "d.csv", ReadingCheck::kEverySensor));
  // The tendon column emptied, and one marker coordinate in every row.
  const Observations no_tendon = bindLog(
      parseLog("time,link_3.0_tip.z,l_elbow_pot,neck_cyl_1,m_forearm.x,m_forearm.y,m_forearm.z,"
               "link_3.0_tip.x,link_3.0_tip.y\n0,3,0.5,,1,2,3,1,\n0.1,3,0.5,nan,1,2,3,1,\n",
               "d.csv"),
      sensors, "s.yaml", 1.0);
  EXPECT_NO_THROW(requireReadings(no_tendon, sensors, "d.csv", ReadingCheck::kAnyFrame));
  try {
    requireReadings(no_tendon, sensors, "d.csv", ReadingCheck::kEverySensor);
    FAIL();
  } catch (const InputError& e) {
    EXPECT_STREQ(e.what(),
                 "d.csv: no reading at all in the 2 frame(s) for marker 'link_3.0_tip', tendon "
                 "sensor 'neck_cyl_1': a calibration cannot estimate what nothing measures "
                 "(give it readings, or remove it from the sensors)");
  }
  const Observations empty = bindLog(
      parseLog("time,link_3.0_tip.z,l_elbow_pot,neck_cyl_1,m_forearm.x,m_forearm.y,m_forearm.z,"
               "link_3.0_tip.x,link_3.0_tip.y\n0,,,,,,,,\n0.1,nan,,,NaN,,,,\n",
               "d.csv"),
      sensors, "s.yaml", 1.0);
  for (ReadingCheck check : {ReadingCheck::kAnyFrame, ReadingCheck::kEverySensor}) {
    try {
      requireReadings(empty, sensors, "d.csv", check);
      FAIL();
    } catch (const InputError& e) {
      EXPECT_STREQ(e.what(),
                   "d.csv: no usable frame: every reading of the 2 frame(s) is empty (or nan)");
    }
  }
}

}  // namespace
}  // namespace stac
