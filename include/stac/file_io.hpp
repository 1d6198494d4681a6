// Whole-file reads and all-or-nothing writes.
#pragma once

#include <string>

namespace stac {

// Throws InputError(path, ...) if the file cannot be read.
std::string readTextFile(const std::string& path);

// Writes to "<path>.tmp.XXXXXX" beside the target, then renames it over the
// target, so a reader never sees a half-written file. Throws
// std::runtime_error on failure (and removes the temporary file).
void writeFileAtomically(const std::string& path, const std::string& content);

// True if both paths name the same existing file (device and inode).
bool sameFile(const std::string& a, const std::string& b);

// Formats a double so that YAML 1.1 and 1.2 and CSV readers see a number
// that round-trips exactly ("1.0e-05", "0.5", "-3.0"; never "1e-05").
std::string formatNumber(double v);

}  // namespace stac
