// A log from a table in memory (logFromTable): the CSV reader's rules
// without the text, so that a log handed over by a program (the Python
// module: a numpy array, a pandas DataFrame) is refused where the same
// table written as CSV would be, with the same messages.
#include <cmath>
#include <set>

#include "io/log_header.hpp"
#include "stac/error.hpp"
#include "stac/log.hpp"

namespace stac {

namespace io {

bool isTimeName(const std::string& s) { return s == "time" || s == "t" || s == "timestamp"; }

int readLogHeader(const std::vector<std::string>& names, int line, Log* log) {
  std::set<std::string> seen;
  int time_col = -1;
  for (size_t c = 0; c < names.size(); ++c) {
    const std::string& name = names[c];
    const int column = static_cast<int>(c + 1);
    if (name.empty()) throw InputError(log->path, line, column, "empty column name in the header");
    if (!seen.insert(name).second)
      throw InputError(log->path, line, column, "column '" + name + "' appears twice in the header");
    if (!isTimeName(name)) continue;
    if (time_col >= 0)
      throw InputError(log->path, line, column,
                       "two time columns ('" + names[time_col] + "' and '" + name + "')");
    time_col = static_cast<int>(c);
    log->time_name = name;
  }
  for (size_t c = 0; c < names.size(); ++c)
    if (static_cast<int>(c) != time_col) log->columns.push_back(names[c]);
  log->header_line = line;
  return time_col;
}

std::string missingTimeMessage(const std::string& time_name) {
  return "column '" + time_name + "': the time is missing";
}

}  // namespace io

Log logFromTable(const std::vector<std::string>& header, const Eigen::Ref<const RowMatrix>& values,
                 const std::string& source_name) {
  if (values.cols() != static_cast<Eigen::Index>(header.size()))
    throw std::invalid_argument("the table has " + std::to_string(values.cols()) +
                                " columns, the header " + std::to_string(header.size()));
  Log log;
  log.path = source_name;
  const int time_col = io::readLogHeader(header, 1, &log);
  const Eigen::Index frames = values.rows();
  log.values.resize(frames, static_cast<Eigen::Index>(log.columns.size()));
  log.line_of_frame.resize(frames);
  if (time_col >= 0) log.time.resize(frames);
  for (Eigen::Index t = 0; t < frames; ++t) {
    const int line = static_cast<int>(t) + 2;  // as the table written as CSV
    log.line_of_frame[t] = line;
    Eigen::Index out = 0;
    for (Eigen::Index c = 0; c < values.cols(); ++c) {
      const double v = values(t, c);
      const int column = static_cast<int>(c + 1);
      if (std::isinf(v))
        throw InputError(log.path, line, column,
                         "column '" + header[c] + "': '" + (v > 0 ? "inf" : "-inf") +
                             "' is not finite (a missing reading is NaN)");
      if (c == time_col) {
        if (std::isnan(v)) throw InputError(log.path, line, column, io::missingTimeMessage(header[c]));
        log.time[t] = v;
      } else {
        log.values(t, out++) = v;
      }
    }
  }
  return log;
}

}  // namespace stac
