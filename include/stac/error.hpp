// Errors thrown at the library's I/O boundary.
//
// InputError carries where in which file the problem is, so that apps can
// print "file:line:column: message" and exit with code 2 without parsing text.
#pragma once

#include <stdexcept>
#include <string>

namespace stac {

class InputError : public std::runtime_error {
 public:
  // line/column are 1-based; 0 means "not applicable".
  InputError(std::string file, int line, int column, const std::string& what)
      : std::runtime_error(format(file, line, column, what)),
        file_(std::move(file)),
        line_(line),
        column_(column) {}
  InputError(std::string file, const std::string& what)
      : InputError(std::move(file), 0, 0, what) {}

  const std::string& file() const { return file_; }
  int line() const { return line_; }
  int column() const { return column_; }

 private:
  static std::string format(const std::string& file, int line, int column,
                            const std::string& what) {
    std::string s = file;
    if (line > 0) s += ":" + std::to_string(line);
    if (line > 0 && column > 0) s += ":" + std::to_string(column);
    return s + ": " + what;
  }
  std::string file_;
  int line_;
  int column_;
};

// A calibration stopped because CalibrationOptions::should_stop returned
// true: no result (not an error in the input, nor in the library).
class Cancelled : public std::runtime_error {
 public:
  Cancelled() : std::runtime_error("calibration cancelled") {}
};

}  // namespace stac
