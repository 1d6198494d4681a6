// The synchronized log (SPEC §2): a CSV file with a header line.
//
// readLog() only parses; bindLog() checks the columns against a SensorSet
// and splits them per sensor group, applying --mocap-units to marker columns.
#pragma once

#include <Eigen/Core>
#include <map>
#include <string>
#include <vector>

#include "stac/sensors.hpp"

namespace stac {

class RobotModel;

using RowMatrix =
    Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;

struct Log {
  std::string path;
  std::vector<std::string> columns;  // header names, the time column excluded
  std::string time_name;             // "time", "t" or "timestamp"; "" if none
  std::vector<double> time;          // one per frame when time_name != ""
  RowMatrix values;                  // frames x columns; NaN = missing
  std::vector<int> line_of_frame;    // 1-based source line of each frame
  int header_line = 1;               // 1-based line of the header

  int numFrames() const { return static_cast<int>(values.rows()); }
  bool hasTime() const { return !time_name.empty(); }
};

// Throws InputError(file, line, column, ...) for text, inf, ragged rows, an
// empty or duplicate header, or a missing file.
Log readLog(const std::string& path);
Log parseLog(const std::string& text, const std::string& source_name);

// Writes a log (numbers with enough digits to round-trip; NaN as empty
// cells), through a temporary file renamed into place.
void writeLog(const std::string& path, const Log& log);

// Readings per sensor group, NaN where missing. Marker rows hold x,y,z of
// marker m at columns 3m..3m+2; a marker missing any coordinate is NaN in all
// three.
struct Observations {
  int num_frames = 0;
  std::vector<double> time;  // empty when the log has none
  std::string time_name;
  RowMatrix marker;          // frames x 3*markers, metres
  RowMatrix joint;           // frames x joint sensors
  RowMatrix tendon;          // frames x tendon sensors
};

// Throws InputError naming the log when it has no data row (a header
// only, or nothing but empty lines and comments after it).
void requireDataRows(const Log& log);

// Where a sensors file names a log column, so that an error about the
// column points there: the key ("joint_sensors[2].column", or the name's
// key for a default column) and its line; `mapped` when the key is a
// `column:`/`columns:` entry rather than the sensor's name.
struct ColumnKey {
  std::string key;
  int line = 0;
  bool mapped = false;
};
using ColumnKeys = std::map<std::string, ColumnKey>;  // log column -> its key

// mocap_scale multiplies marker columns (0.001 for --mocap-units mm).
// Every log column must belong to a sensor or be in sensors.ignore_columns,
// and every sensor must have its column(s): either mismatch throws an
// InputError naming both files (at the key and line in `keys`, when a
// `column:` names a column the log lacks). A column both read and ignored
// throws too. A log without data rows throws as requireDataRows does.
Observations bindLog(const Log& log, const SensorSet& sensors,
                     const std::string& sensors_source, double mocap_scale,
                     const ColumnKeys& keys = {});

// What must hold of the readings for a use of the observations:
//   kAnyFrame     at least one frame with a reading (evaluation);
//   kEverySensor  that, and a reading of every sensor and marker in some
//                 frame: a calibration cannot estimate what nothing measures.
enum class ReadingCheck { kAnyFrame, kEverySensor };

// Throws InputError naming log_path and what is missing (every sensor and
// marker without a reading, by name).
void requireReadings(const Observations& obs, const SensorSet& sensors,
                     const std::string& log_path, ReadingCheck check);

// Frames [begin, end) of the observations.
Observations sliceFrames(const Observations& obs, int begin, int end);

// `count` frame indices spread evenly over [0, frames) (all of them if
// count >= frames), and the observations of such a subset.
std::vector<int> spreadFrames(int frames, int count);
Observations selectFrames(const Observations& obs, const std::vector<int>& frames);

// The first row of a joint-angles log (as written by --joint-angles) as q:
// the log's columns must be exactly the joints of q, in any order. Throws
// InputError naming the log and line for an unknown or missing joint, an
// empty log or a missing value.
Eigen::VectorXd firstJointAngles(const Log& log, const RobotModel& robot);

}  // namespace stac
