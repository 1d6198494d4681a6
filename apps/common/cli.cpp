#include "common/cli.hpp"

#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <exception>
#include <iostream>
#include <new>

#include "common/interrupt.hpp"
#include "stac/error.hpp"

#ifndef STAC_VERSION
#define STAC_VERSION "0.0.0"
#endif

namespace stac::cli {

std::string Args::get(const std::string& name, const std::string& fallback) const {
  auto it = values_.find(name);
  return it == values_.end() ? fallback : it->second;
}

std::string Args::typed(const std::string& name) const {
  return "--" + name + (typed_inline_.count(name) ? "=" : " ") + get(name);
}

void Args::bad(const std::string& name, const std::string& what) const {
  throw UsageError(typed(name) + ": " + what);
}

std::optional<double> parseFiniteNumber(const std::string& text) {
  char* end = nullptr;
  const double v = std::strtod(text.c_str(), &end);
  if (text.empty() || *end != '\0' || !std::isfinite(v)) return std::nullopt;
  return v;
}

double Args::getDouble(const std::string& name, double fallback) const {
  if (!has(name)) return fallback;
  const std::optional<double> v = parseFiniteNumber(get(name));
  if (!v) bad(name, "expects a finite number");
  return *v;
}

int Args::getInt(const std::string& name, int fallback) const {
  if (!has(name)) return fallback;
  const std::string s = get(name);
  char* end = nullptr;
  errno = 0;
  const long v = std::strtol(s.c_str(), &end, 10);
  if (s.empty() || *end != '\0' || errno == ERANGE || v < -1000000000L || v > 1000000000L)
    bad(name, "expects an integer");
  return static_cast<int>(v);
}

std::vector<std::string> Args::getList(const std::string& name, const std::string& item) const {
  std::vector<std::string> out;
  if (!has(name)) return out;
  const std::string v = get(name);
  for (size_t start = 0;;) {
    const size_t comma = v.find(',', start);
    out.push_back(v.substr(start, comma == std::string::npos ? comma : comma - start));
    if (out.back().empty()) bad(name, "an empty " + item);
    if (comma == std::string::npos) return out;
    start = comma + 1;
  }
}

double Args::getPositive(const std::string& name, double fallback) const {
  const double v = getDouble(name, fallback);
  if (has(name) && !(v > 0)) bad(name, "must be positive and finite");
  return v;
}

double Args::getNonNegative(const std::string& name, double fallback) const {
  const double v = getDouble(name, fallback);
  if (has(name) && !(v >= 0)) bad(name, "must be finite and >= 0");
  return v;
}

double Args::getFraction(const std::string& name, double fallback, bool open) const {
  const double v = getDouble(name, fallback);
  if (!has(name)) return v;
  if (open && !(v > 0 && v < 1)) bad(name, "must be a fraction strictly between 0 and 1");
  if (!open && !(v >= 0 && v <= 1)) bad(name, "must be a fraction in [0, 1]");
  return v;
}

int Args::getIntAtLeast(const std::string& name, int fallback, int min,
                        const std::string& meaning) const {
  const int v = getInt(name, fallback);
  if (has(name) && v < min)
    bad(name, "must be at least " + std::to_string(min) +
                  (meaning.empty() ? "" : " (" + meaning + ")"));
  return v;
}

std::uint64_t Args::getUnsigned(const std::string& name, std::uint64_t fallback) const {
  if (!has(name)) return fallback;
  const std::string s = get(name);
  // strtoull accepts "-3" (as 2^64-3) and leading blanks: digits only.
  const bool digits = !s.empty() && s.find_first_not_of("0123456789") == std::string::npos;
  errno = 0;
  const unsigned long long v = digits ? std::strtoull(s.c_str(), nullptr, 10) : 0;
  if (!digits || errno == ERANGE) bad(name, "expects a non-negative integer (at most 2^64-1)");
  return static_cast<std::uint64_t>(v);
}

std::string Args::getChoice(const std::string& name,
                            const std::vector<std::string>& choices,
                            const std::string& fallback) const {
  if (!has(name)) return fallback;
  const std::string v = get(name);
  std::string list;
  for (const std::string& c : choices) {
    if (c == v) return v;
    list += (list.empty() ? "" : "|") + c;
  }
  bad(name, "must be one of " + list);
}

Args parseArgs(int argc, char** argv, const std::vector<Option>& options) {
  Args args;
  for (int i = 1; i < argc; ++i) {
    std::string a = argv[i];
    if (a.rfind("--", 0) != 0)
      throw UsageError("unexpected argument '" + a + "'");
    std::string name = a.substr(2), value;
    bool inline_value = false;
    if (auto eq = name.find('='); eq != std::string::npos) {
      value = name.substr(eq + 1);
      name = name.substr(0, eq);
      inline_value = true;
    }
    const Option* opt = nullptr;
    for (const Option& o : options)
      if (o.name == name) opt = &o;
    if (!opt) throw UsageError("unknown option '--" + name + "' (see --help)");
    if (opt->value_name.empty()) {
      if (inline_value) throw UsageError("--" + name + " takes no value");
      value = "1";
    } else if (!inline_value) {
      // "--urdf-out --quiet" is a forgotten value, not a file named --quiet.
      if (i + 1 >= argc || std::string(argv[i + 1]).rfind("--", 0) == 0)
        throw UsageError("--" + name + " needs a value (" + opt->value_name + ")");
      value = argv[++i];
    }
    if (args.values_.count(name))
      throw UsageError("--" + name + " given twice");
    args.values_[name] = value;
    if (inline_value) args.typed_inline_.insert(name);
  }
  for (const Option& o : options)
    if (o.required && !args.has(o.name))
      throw UsageError("missing required option --" + o.name);
  return args;
}

namespace {
void printHelp(const std::string& synopsis, const std::vector<Option>& options) {
  std::cout << synopsis << "\n\nOptions:\n";
  for (const Option& o : options) {
    std::string left = "  --" + o.name + (o.value_name.empty() ? "" : " " + o.value_name);
    if (left.size() < 28) left.resize(28, ' ');
    else left += "  ";
    std::cout << left << o.help << (o.required ? " (required)" : "") << "\n";
  }
  std::cout << "  --help                    print this help\n"
               "  --version                 print the version\n\n"
               "Exit codes: 0 success, 2 bad usage or input, 3 internal error,\n"
               "130/143 interrupted (SIGINT/SIGTERM; nothing written).\n";
}
}  // namespace

int runApp(int argc, char** argv, const std::string& app,
           const std::string& synopsis, const std::vector<Option>& options,
           const std::function<int(const Args&)>& body) {
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    if (a == "--help" || a == "-h") {
      printHelp(synopsis, options);
      return 0;
    }
    if (a == "--version") {
      std::cout << app << " " << STAC_VERSION << "\n";
      return 0;
    }
  }
  installInterruptHandlers(app);
  try {
    return body(parseArgs(argc, argv, options));
  } catch (const Interrupted& e) {
    return reportInterrupt(app, e.signal);
  } catch (const Cancelled& e) {  // CalibrationOptions::should_stop: an interrupt
    if (pendingInterrupt()) return reportInterrupt(app, pendingInterrupt());
    std::cerr << app << ": internal error: " << e.what() << "\n";
    return 3;
  } catch (const UsageError& e) {
    std::cerr << app << ": error: " << e.what() << "\n"
              << "usage: see '" << app << " --help'\n";
    return 2;
  } catch (const InputError& e) {
    std::cerr << app << ": error: " << e.what() << "\n";
    return 2;
  } catch (const std::invalid_argument& e) {
    std::cerr << app << ": error: " << e.what() << "\n";
    return 2;
  } catch (const std::bad_alloc&) {
    std::cerr << app << ": internal error: out of memory\n";
    return 3;
  } catch (const std::exception& e) {
    std::cerr << app << ": internal error: " << e.what() << "\n";
    return 3;
  }
}

}  // namespace stac::cli
