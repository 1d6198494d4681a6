// The sensors file reader's checked access to yaml-cpp nodes (internal):
// keys allowed and not repeated, numbers, vectors, names and held parts,
// each failing with an InputError that names the file, the line and the
// key; it also records which log column each key reads or ignores.
#pragma once

#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <map>
#include <optional>
#include <set>
#include <string>
#include <utility>
#include <vector>

#include "io/yaml_number.hpp"
#include "stac/error.hpp"
#include "stac/robot_model.hpp"
#include "stac/sensors_file.hpp"

namespace stac::sensors_yaml {

class Reader {
 public:
  Reader(std::string file, const RobotModel& robot) : file_(std::move(file)), robot_(robot) {}

  [[noreturn]] void fail(const YAML::Node& at, const std::string& key,
                         const std::string& what) const {
    const int line = at.Mark().line >= 0 ? at.Mark().line + 1 : 0;
    throw InputError(file_, line, 0, "key '" + key + "': " + what);
  }

  // Checks a mapping: only `allowed` keys, none twice (yaml-cpp keeps both
  // entries of a duplicated key, so they are seen here). Returns key -> value.
  std::map<std::string, YAML::Node> fields(const YAML::Node& node, const std::string& key,
                                           const std::set<std::string>& allowed) const {
    if (!node.IsMap()) {
      std::string list;
      for (const std::string& a : allowed) list += (list.empty() ? "" : ", ") + a;
      fail(node, key, "expected a mapping (with keys among: " + list + ")");
    }
    static const std::set<std::string> kMayBeEmpty = {
        "mocap", "frame", "markers", "joint_sensors", "tendon_sensors", "summary", "std", "residual"};
    std::map<std::string, YAML::Node> out;
    std::map<std::string, int> lines;
    for (auto it = node.begin(); it != node.end(); ++it) {
      if (!it->first.IsScalar()) fail(it->first, key, "a key must be a plain name");
      const std::string k = it->first.Scalar();
      const std::string path = key == kTop ? k : key + "." + k;
      if (!allowed.count(k)) {
        std::string list;
        for (const std::string& a : allowed) list += (list.empty() ? "" : ", ") + a;
        fail(it->first, path, "unknown key (expected one of: " + list + ")");
      }
      if (out.count(k))
        fail(it->first, path, "given twice (first on line " + std::to_string(lines[k]) + ")");
      // An empty value is an empty section, or else an error reported on
      // the key's line (yaml-cpp marks an empty value at the next token).
      if (it->second.IsNull() && !kMayBeEmpty.count(k))
        fail(it->first, path, "expected a value, got nothing");
      out.emplace(k, it->second);
      lines[k] = it->first.Mark().line + 1;
    }
    return out;
  }

  double number(const YAML::Node& n, const std::string& key) const {
    if (!n.IsScalar()) fail(n, key, n.IsNull() ? "expected a number, got nothing" : "expected a number");
    const std::string& s = n.Scalar();
    if (n.Tag() == "!") fail(n, key, "expected a number, got the quoted string \"" + s + "\"");
    const std::optional<double> v = parseYamlNumber(s);
    if (!v) fail(n, key, "expected a number, got '" + s + "'");
    if (!std::isfinite(*v)) fail(n, key, "'" + s + "' is not a finite number");
    return *v;
  }

  double sigma(const YAML::Node& n, const std::string& key) const {
    const double v = number(n, key);
    if (!(v > 0)) fail(n, key, "a sigma must be positive and finite, got " + n.Scalar());
    return v;
  }

  bool boolean(const YAML::Node& n, const std::string& key) const {
    if (!n.IsScalar() || n.Tag() == "!") fail(n, key, "expected true or false");
    const std::string& s = n.Scalar();
    if (s == "true" || s == "True" || s == "TRUE") return true;
    if (s == "false" || s == "False" || s == "FALSE") return false;
    fail(n, key, "expected true or false, got '" + s + "'");
  }

  // `fixed`: true or false (every part), or the list of the parts to hold
  // among `parts` (the item's own, e.g. gain and bias). Returns, per part,
  // whether it is held.
  std::vector<bool> heldParts(const YAML::Node& n, const std::string& key, const char* item,
                              const std::vector<std::string>& parts) const {
    if (!n.IsSequence()) return std::vector<bool>(parts.size(), boolean(n, key));
    std::string list;
    for (const std::string& p : parts) list += (list.empty() ? "" : ", ") + p;
    std::vector<bool> held(parts.size(), false);
    std::map<std::string, int> seen;  // part -> line
    for (const YAML::Node& e : n) {
      if (!e.IsScalar() || e.Tag() == "!")
        fail(e, key, "expected true, false or a list of parameter names (" + list + ")");
      const std::string& name = e.Scalar();
      const auto it = std::find(parts.begin(), parts.end(), name);
      if (it == parts.end())
        fail(e, key,
             kAnyPart.count(name) ? std::string(item) + " has no " + name + " (its parameters: " +
                                        list + ")"
                                  : "unknown parameter '" + name + "' (expected some of: " +
                                        list + ")");
      if (seen.count(name))
        fail(e, key,
             "'" + name + "' given twice (first on line " + std::to_string(seen[name]) + ")");
      seen[name] = e.Mark().line + 1;
      held[it - parts.begin()] = true;
    }
    return held;
  }

  // A marker's position is held or free as a whole: no list.
  bool markerFixed(const YAML::Node& n, const std::string& key) const {
    if (!n.IsSequence()) return boolean(n, key);
    const YAML::Node at = n.size() > 0 ? n[0] : n;
    const std::string name = at.IsScalar() ? at.Scalar() : "";
    fail(at, key,
         (kAnyPart.count(name) && name != "position" ? "a marker has no " + name + "; " : "") +
             std::string("a marker's position is held or free as a whole (expected true or "
                         "false, not a list)"));
  }

  FixedGainBias fixedGainBias(const YAML::Node& n, const std::string& key,
                              const char* item) const {
    const std::vector<bool> held = heldParts(n, key, item, {"gain", "bias"});
    return {held[0], held[1]};
  }

  std::string text(const YAML::Node& n, const std::string& key) const {
    if (!n.IsScalar() || n.Scalar().empty()) fail(n, key, "expected a name");
    return n.Scalar();
  }

  Eigen::VectorXd vector(const YAML::Node& n, const std::string& key, int size) const {
    if (!n.IsSequence())
      fail(n, key, "expected a list of " + std::to_string(size) + " numbers");
    if (static_cast<int>(n.size()) != size)
      fail(n, key,
           "expected a list of " + std::to_string(size) + " numbers, got " +
               std::to_string(n.size()));
    Eigen::VectorXd v(size);
    for (int i = 0; i < size; ++i) v[i] = number(n[i], key + "[" + std::to_string(i) + "]");
    return v;
  }

  int link(const YAML::Node& n, const std::string& key) const {
    const std::string name = text(n, key);
    const auto idx = robot_.linkIndex(name);
    if (!idx) fail(n, key, "unknown link '" + name + "' (not in " + robot_.sourceName() + ")");
    return *idx;
  }

  int joint(const YAML::Node& n, const std::string& key) const {
    const std::string name = text(n, key);
    const auto idx = robot_.movableJointIndex(name);
    if (!idx) {
      const auto& all = robot_.allJointNames();
      const bool exists = std::find(all.begin(), all.end(), name) != all.end();
      fail(n, key, exists ? "joint '" + name + "' is fixed: it has no angle to sense"
                          : "unknown joint '" + name + "' (not in " + robot_.sourceName() + ")");
    }
    return *idx;
  }

  // A sensor's or marker's name. It is the default of its log column(s)
  // (claimed apart, by claimColumn), so it must be one that a CSV can hold.
  std::string sensorName(const YAML::Node& n, const std::string& key) {
    const std::string name = text(n, key);
    if (!names_.insert(name).second) fail(n, key, "name '" + name + "' is used twice");
    return name;
  }

  // A log column named by `column:`, `columns:` or `ignore_columns:`.
  std::string columnName(const YAML::Node& n, const std::string& key) const {
    const std::string name = text(n, key);
    requireCsvName(n, key, "column", name);
    return name;
  }

  // Notes that the item at `key` reads log column `column` (given by
  // `column:`/`columns:` when mapped, else its name): no two may share one,
  // and none may be the time column.
  void claimColumn(const YAML::Node& at, const std::string& key, const std::string& column,
                   bool mapped) {
    if (!mapped) requireCsvName(at, key, "name", column);
    if (io::isTimeName(column))
      fail(at, key,
           mapped ? "column '" + column + "' is the log's time column, not a sensor's"
                  : "name '" + column + "' is reserved for the log's time column");
    const auto [it, fresh] = columns_.emplace(column, ColumnKey{key, line(at), mapped});
    if (fresh) return;
    const std::string first =
        " (" + it->second.key + ", line " + std::to_string(it->second.line) + ")";
    fail(at, key,
         mapped ? "column '" + column + "' is read by another sensor too" + first
                : "name '" + keyName(at) + "' gives log column '" + column +
                      "', which another sensor has" + first);
  }

  // An `ignore_columns` entry: no sensor may read it.
  void ignoreColumn(const YAML::Node& at, const std::string& key, const std::string& column) {
    const auto [it, fresh] = columns_.emplace(column, ColumnKey{key, line(at), false});
    if (fresh) return;
    fail(at, key,
         "column '" + column + "' is " +
             (it->second.key.rfind("ignore_columns", 0) == 0
                  ? "listed twice (" + it->second.key + ", line " +
                        std::to_string(it->second.line) + ")"
                  : "read by " + it->second.key + " (line " + std::to_string(it->second.line) +
                        "): a column is a sensor's or ignored, not both"));
  }

  ColumnKeys columnKeys() const { return columns_; }

  static constexpr const char* kTop = "(top level)";
  // Every parameter name some item's `fixed` list may give.
  inline static const std::set<std::string> kAnyPart = {"gain", "bias", "rotation",
                                                        "translation", "position", "xyz", "rpy"};

 private:
  std::string file_;
  const RobotModel& robot_;
  static int line(const YAML::Node& n) { return n.Mark().line >= 0 ? n.Mark().line + 1 : 0; }
  static std::string keyName(const YAML::Node& n) { return n.IsScalar() ? n.Scalar() : ""; }

  void requireCsvName(const YAML::Node& n, const std::string& key, const char* what,
                      const std::string& name) const {
    if (name.find_first_of(",\n\r\"") != std::string::npos || name.front() == '#' ||
        std::isspace(static_cast<unsigned char>(name.front())) ||
        std::isspace(static_cast<unsigned char>(name.back())))
      fail(n, key,
           std::string(what) + " '" + name +
               "' cannot be a CSV column (no commas, quotes, leading '#' or surrounding spaces)");
  }

  std::set<std::string> names_;
  ColumnKeys columns_;  // log column -> the key that reads or ignores it
};

}  // namespace stac::sensors_yaml
