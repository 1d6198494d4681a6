// Shared command-line plumbing for the stac_* apps: option parsing, --help,
// --version, and the mapping of errors to exit codes (SPEC §4: 0 success,
// 2 bad usage or bad input, 3 internal error).
#pragma once

#include <cstdint>
#include <functional>
#include <map>
#include <optional>
#include <set>
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

// The whole of `text` as a finite number, or nothing.
std::optional<double> parseFiniteNumber(const std::string& text);

// The parsed options. Every getter that checks a value throws a UsageError
// that names the flag and the value as typed ("--loss-scale -1: must be
// positive and finite"), so every app reports a bad option the same way.
class Args {
 public:
  bool has(const std::string& name) const { return values_.count(name) > 0; }
  std::string get(const std::string& name, const std::string& fallback = "") const;
  // "--name value", or "--name=value" when typed so: the start of a message.
  std::string typed(const std::string& name) const;
  // Any finite number / any integer in ±1e9, or fallback when absent.
  double getDouble(const std::string& name, double fallback) const;
  int getInt(const std::string& name, int fallback) const;
  // A number > 0 / >= 0, finite.
  double getPositive(const std::string& name, double fallback) const;
  double getNonNegative(const std::string& name, double fallback) const;
  // A fraction in [0, 1], or in (0, 1) when open.
  double getFraction(const std::string& name, double fallback, bool open = false) const;
  // An integer >= min; `meaning` (e.g. "0 = all cores") joins the message.
  int getIntAtLeast(const std::string& name, int fallback, int min,
                    const std::string& meaning = "") const;
  // A non-negative integer up to 2^64-1 (a random seed).
  std::uint64_t getUnsigned(const std::string& name, std::uint64_t fallback) const;
  // "a,b,c" -> {a, b, c} (empty when absent); an empty item (",," or a
  // trailing comma) is a typo: UsageError "an empty <item>".
  std::vector<std::string> getList(const std::string& name, const std::string& item) const;
  // One of `choices`, or fallback when absent; UsageError otherwise.
  std::string getChoice(const std::string& name,
                        const std::vector<std::string>& choices,
                        const std::string& fallback) const;

 private:
  [[noreturn]] void bad(const std::string& name, const std::string& what) const;
  friend Args parseArgs(int, char**, const std::vector<Option>&);
  std::map<std::string, std::string> values_;
  std::set<std::string> typed_inline_;  // given as --name=value
};

Args parseArgs(int argc, char** argv, const std::vector<Option>& options);

// Runs body; handles --help/--version; prints "<app>: error: ..." on stderr
// and returns the exit code.
int runApp(int argc, char** argv, const std::string& app,
           const std::string& synopsis, const std::vector<Option>& options,
           const std::function<int(const Args&)>& body);

}  // namespace stac::cli
