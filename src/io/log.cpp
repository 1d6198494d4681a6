// The CSV log (SPEC §2): a hand-written reader, because it must be fast
// (25,000 rows x 140 columns well under a second) and must name the line and
// column of every bad cell.
#include "stac/log.hpp"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdlib>
#include <limits>
#include <set>
#include <stdexcept>
#include <string_view>

#include "stac/error.hpp"
#include "stac/file_io.hpp"

namespace stac {
namespace {

std::string_view trim(std::string_view s) {
  while (!s.empty() && (s.front() == ' ' || s.front() == '\t')) s.remove_prefix(1);
  while (!s.empty() && (s.back() == ' ' || s.back() == '\t' || s.back() == '\r')) s.remove_suffix(1);
  return s;
}

bool isTimeName(const std::string& s) { return s == "time" || s == "t" || s == "timestamp"; }

// "nan", "NaN", "-nan" (what printf writes for a negative NaN), any case.
bool isMissing(std::string_view cell) {
  if (cell.empty()) return true;
  if (cell.front() == '-' || cell.front() == '+') cell.remove_prefix(1);
  return cell.size() == 3 && (cell[0] | 0x20) == 'n' && (cell[1] | 0x20) == 'a' &&
         (cell[2] | 0x20) == 'n';
}

// Parses one cell; NaN for a missing reading. Throws for anything else that
// is not a finite number.
double parseCell(std::string_view cell, const Log& log, int line, int column,
                 const std::string& name) {
  cell = trim(cell);
  if (isMissing(cell)) return std::numeric_limits<double>::quiet_NaN();
  double v = 0;
  const char* begin = cell.data();
  if (*begin == '+' && cell.size() > 1 && cell[1] != '-') ++begin;
  const auto res = std::from_chars(begin, cell.data() + cell.size(), v);
  if (res.ec == std::errc() && res.ptr == cell.data() + cell.size()) {
    if (std::isfinite(v)) return v;
    throw InputError(log.path, line, column,
                     "column '" + name + "': '" + std::string(cell) +
                         "' is not finite (a missing reading is an empty cell or nan)");
  }
  if (res.ec == std::errc::result_out_of_range && res.ptr == cell.data() + cell.size()) {
    // Underflow reads as the nearest double (0 or a subnormal), as strtod
    // does; overflow is an error.
    const std::string copy(cell);
    const double u = std::strtod(copy.c_str(), nullptr);
    if (std::isfinite(u)) return u;
    throw InputError(log.path, line, column,
                     "column '" + name + "': '" + copy + "' is out of range");
  }
  throw InputError(log.path, line, column,
                   "column '" + name + "': '" + std::string(cell) + "' is not a number");
}

// The fast path for a row of plain numbers and empty cells: parses it into
// out[0..n) and returns true, or returns false (with out partly written) at
// anything else (nan, '+', text, inf, a wrong cell count), for the careful
// path to handle or report.
bool parsePlainRow(std::string_view row, size_t n, double* out) {
  const char* p = row.data();
  const char* const end = row.data() + row.size();
  auto blank = [](char c) { return c == ' ' || c == '\t' || c == '\r'; };
  for (size_t c = 0; c < n; ++c) {
    while (p < end && blank(*p)) ++p;
    if (p == end || *p == ',') {
      out[c] = std::numeric_limits<double>::quiet_NaN();
    } else {
      const auto res = std::from_chars(p, end, out[c]);
      if (res.ec != std::errc() || !std::isfinite(out[c])) return false;
      p = res.ptr;
      while (p < end && blank(*p)) ++p;
    }
    if (c + 1 < n) {
      if (p == end || *p != ',') return false;
      ++p;
    } else if (p != end) {
      return false;
    }
  }
  return true;
}

// Reads the text line by line: the header, then one frame per data line,
// each through the fast path first and through the careful one (which
// names the bad cell) when the fast path does not take it.
class LogParser {
 public:
  LogParser(const std::string& text, const std::string& source_name) : text_(text) {
    log_.path = source_name;
    if (text.compare(0, 3, "\xEF\xBB\xBF") == 0) pos_ = 3;  // a UTF-8 byte order mark
  }

  Log parse() && {
    std::string_view row;
    while (nextLine(&row)) {
      const std::string_view t = trim(row);
      if (t.empty() || t.front() == '#') continue;
      if (!header_.empty() && readPlainRow(row)) continue;
      splitCells(row);
      if (header_.empty())
        readHeader();
      else
        readRow();
    }
    if (header_.empty()) throw InputError(log_.path, "the log is empty: no header line");
    const Eigen::Index rows = static_cast<Eigen::Index>(log_.line_of_frame.size());
    const Eigen::Index cols = static_cast<Eigen::Index>(log_.columns.size());
    // Copied only when there is something to copy: a header-only log has
    // no data buffer, and Eigen would offset its null pointer.
    log_.values.resize(rows, cols);
    if (!values_.empty()) std::copy(values_.begin(), values_.end(), log_.values.data());
    return std::move(log_);
  }

 private:
  bool nextLine(std::string_view* row) {
    if (pos_ >= text_.size()) return false;
    size_t end = text_.find('\n', pos_);
    if (end == std::string::npos) end = text_.size();
    *row = std::string_view(text_.data() + pos_, end - pos_);
    pos_ = end + 1;
    ++line_;
    return true;
  }

  bool readPlainRow(std::string_view row) {
    row_buf_.resize(header_.size());
    if (!parsePlainRow(row, header_.size(), row_buf_.data())) return false;
    if (time_col_ >= 0 && std::isnan(row_buf_[time_col_])) missingTime();
    appendFrame();
    return true;
  }

  void splitCells(std::string_view row) {
    cells_.clear();
    size_t start = 0;
    while (true) {
      const size_t comma = row.find(',', start);
      if (comma == std::string_view::npos) {
        cells_.push_back(row.substr(start));
        break;
      }
      cells_.push_back(row.substr(start, comma - start));
      start = comma + 1;
    }
  }

  void readHeader() {
    std::set<std::string> seen;
    for (size_t c = 0; c < cells_.size(); ++c) {
      const std::string name(trim(cells_[c]));
      if (name.empty())
        throw InputError(log_.path, line_, static_cast<int>(c + 1),
                         "empty column name in the header");
      if (!seen.insert(name).second)
        throw InputError(log_.path, line_, static_cast<int>(c + 1),
                         "column '" + name + "' appears twice in the header");
      if (isTimeName(name)) {
        if (time_col_ >= 0)
          throw InputError(log_.path, line_, static_cast<int>(c + 1),
                           "two time columns ('" + header_[time_col_] + "' and '" + name + "')");
        time_col_ = static_cast<int>(c);
        log_.time_name = name;
      }
      header_.push_back(name);
    }
    for (size_t c = 0; c < header_.size(); ++c)
      if (static_cast<int>(c) != time_col_) log_.columns.push_back(header_[c]);
    log_.header_line = line_;
    reserveFrames();
  }

  // Reserves once for the frames the rest of the text can hold: at most
  // one per remaining line, and a data row of n cells takes at least n
  // bytes (n - 1 commas and its newline). The second bound keeps memory in
  // proportion to the file: a wide header over many empty lines would
  // otherwise ask for lines x columns doubles (gigabytes from 100 KB).
  void reserveFrames() {
    const size_t rest = text_.size() - std::min(pos_, text_.size());
    const auto begin = text_.end() - static_cast<std::ptrdiff_t>(rest);
    const size_t lines_left = static_cast<size_t>(std::count(begin, text_.end(), '\n')) + 1;
    const size_t frames = std::min(lines_left, rest / header_.size() + 1);
    values_.reserve(frames * log_.columns.size());
    if (time_col_ >= 0) log_.time.reserve(frames);
    log_.line_of_frame.reserve(frames);
  }

  // The careful path: every cell on its own, so that an error names it.
  void readRow() {
    checkCellCount();
    row_buf_.resize(cells_.size());
    for (size_t c = 0; c < cells_.size(); ++c) {
      row_buf_[c] = parseCell(cells_[c], log_, line_, static_cast<int>(c + 1), header_[c]);
      if (static_cast<int>(c) == time_col_ && std::isnan(row_buf_[c])) missingTime();
    }
    appendFrame();
  }

  void checkCellCount() const {
    if (cells_.size() == header_.size()) return;
    const size_t col = std::min(cells_.size(), header_.size());
    throw InputError(log_.path, line_, static_cast<int>(col + 1),
                     "the row has " + std::to_string(cells_.size()) + " cells, the header has " +
                         std::to_string(header_.size()) +
                         (cells_.size() < header_.size()
                              ? " (no cell for column '" + header_[col] + "')"
                              : " (a cell beyond the last column '" + header_.back() + "')"));
  }

  [[noreturn]] void missingTime() const {
    throw InputError(log_.path, line_, time_col_ + 1,
                     "column '" + header_[time_col_] + "': the time is missing");
  }

  // Moves the frame in row_buf_ (one value per header column) into the log.
  void appendFrame() {
    for (size_t c = 0; c < header_.size(); ++c) {
      if (static_cast<int>(c) == time_col_)
        log_.time.push_back(row_buf_[c]);
      else
        values_.push_back(row_buf_[c]);
    }
    log_.line_of_frame.push_back(line_);
  }

  const std::string& text_;
  size_t pos_ = 0;
  int line_ = 0;
  Log log_;
  std::vector<std::string> header_;
  int time_col_ = -1;
  std::vector<double> values_;  // row-major, grown row by row
  std::vector<std::string_view> cells_;
  std::vector<double> row_buf_;
};

}  // namespace

Log parseLog(const std::string& text, const std::string& source_name) {
  return LogParser(text, source_name).parse();
}

Log readLog(const std::string& path) { return parseLog(readTextFile(path), path); }

void writeLog(const std::string& path, const Log& log) {
  std::string out;
  out.reserve(static_cast<size_t>(log.values.size()) * 12 + 256);
  bool first = true;
  if (log.hasTime()) out += log.time_name, first = false;
  for (const std::string& c : log.columns) {
    if (!first) out += ',';
    out += c;
    first = false;
  }
  out += '\n';
  if (log.hasTime() && log.time.size() != static_cast<size_t>(log.values.rows()))
    throw std::invalid_argument("writeLog: " + std::to_string(log.time.size()) + " times for " +
                                std::to_string(log.values.rows()) + " rows");
  if (log.columns.size() != static_cast<size_t>(log.values.cols()))
    throw std::invalid_argument("writeLog: " + std::to_string(log.columns.size()) +
                                " column names for " + std::to_string(log.values.cols()) +
                                " columns");
  char buf[64];
  auto number = [&](double v) {
    if (std::isnan(v)) return;
    if (std::isinf(v)) throw std::invalid_argument("writeLog: an infinite value cannot be read back");
    const auto res = std::to_chars(buf, buf + sizeof buf, v);
    out.append(buf, res.ptr);
  };
  for (Eigen::Index t = 0; t < log.values.rows(); ++t) {
    first = true;
    if (log.hasTime()) number(log.time[t]), first = false;
    for (Eigen::Index c = 0; c < log.values.cols(); ++c) {
      if (!first) out += ',';
      number(log.values(t, c));
      first = false;
    }
    out += '\n';
  }
  writeFileAtomically(path, out);
}

Observations sliceFrames(const Observations& obs, int begin, int end) {
  Observations out;
  end = std::clamp(end, 0, obs.num_frames);
  begin = std::clamp(begin, 0, end);
  out.num_frames = std::max(0, end - begin);
  out.time_name = obs.time_name;
  if (!obs.time.empty()) out.time.assign(obs.time.begin() + begin, obs.time.begin() + end);
  out.marker.resize(out.num_frames, obs.marker.cols());
  out.joint.resize(out.num_frames, obs.joint.cols());
  out.tendon.resize(out.num_frames, obs.tendon.cols());
  if (out.num_frames == 0) return out;  // no block of a matrix that may have no rows
  out.marker = obs.marker.middleRows(begin, out.num_frames);
  out.joint = obs.joint.middleRows(begin, out.num_frames);
  out.tendon = obs.tendon.middleRows(begin, out.num_frames);
  return out;
}

std::vector<int> spreadFrames(int frames, int count) {
  std::vector<int> out;
  const int n = std::min(frames, count);
  for (int i = 0; i < n; ++i) out.push_back(static_cast<int>(static_cast<long>(i) * frames / n));
  return out;
}

Observations selectFrames(const Observations& obs, const std::vector<int>& frames) {
  Observations out;
  out.num_frames = static_cast<int>(frames.size());
  out.marker.resize(out.num_frames, obs.marker.cols());
  out.joint.resize(out.num_frames, obs.joint.cols());
  out.tendon.resize(out.num_frames, obs.tendon.cols());
  for (int i = 0; i < out.num_frames; ++i) {
    out.marker.row(i) = obs.marker.row(frames[i]);
    out.joint.row(i) = obs.joint.row(frames[i]);
    out.tendon.row(i) = obs.tendon.row(frames[i]);
    if (!obs.time.empty()) out.time.push_back(obs.time[frames[i]]);
  }
  out.time_name = obs.time_name;
  return out;
}

}  // namespace stac
