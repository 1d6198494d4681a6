// Shared command-line plumbing for the stac_* apps: option parsing, --help,
// --version, and the mapping of errors to exit codes (SPEC §4: 0 success,
// 2 bad usage or bad input, 3 internal error).
#pragma once

#include <functional>
#include <map>
#include <stdexcept>
#include <string>
#include <vector>

namespace stac::cli {

struct UsageError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

struct Option {
  std::string name;        // without the leading "--"
  std::string value_name;  // "" for a flag
  std::string help;
  bool required = false;
};

class Args {
 public:
  bool has(const std::string& name) const { return values_.count(name) > 0; }
  std::string get(const std::string& name, const std::string& fallback = "") const;
  double getDouble(const std::string& name, double fallback) const;
  int getInt(const std::string& name, int fallback) const;
  // One of `choices`, or fallback when absent; UsageError otherwise.
  std::string getChoice(const std::string& name,
                        const std::vector<std::string>& choices,
                        const std::string& fallback) const;

 private:
  friend Args parseArgs(int, char**, const std::vector<Option>&);
  std::map<std::string, std::string> values_;
};

Args parseArgs(int argc, char** argv, const std::vector<Option>& options);

// Runs body; handles --help/--version; prints "<app>: error: ..." on stderr
// and returns the exit code.
int runApp(int argc, char** argv, const std::string& app,
           const std::string& synopsis, const std::vector<Option>& options,
           const std::function<int(const Args&)>& body);

}  // namespace stac::cli
