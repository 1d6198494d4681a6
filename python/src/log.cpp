// stac.Log: the synchronized log (SPEC §2), from a CSV file or from a table
// in memory (a numpy array and column names, or a pandas DataFrame).
#include <pybind11/stl.h>

#include "bindings.hpp"

namespace stac::python {

using namespace pybind11::literals;

namespace {

// The header of a table: `columns`, or a DataFrame's own .columns.
std::vector<std::string> headerOf(const py::object& data, const py::object& columns) {
  py::object names = columns;
  if (names.is_none()) {
    if (!py::hasattr(data, "columns"))
      throw py::type_error("Log: give the column names (columns=...) or a pandas DataFrame");
    names = data.attr("columns");
  }
  std::vector<std::string> header;
  for (const py::handle name : names) header.push_back(py::str(name));
  return header;
}

std::shared_ptr<Log> fromTable(const py::object& data, const py::object& columns,
                               const std::string& source) {
  const std::vector<std::string> header = headerOf(data, columns);
  // A DataFrame: its values through .to_numpy() (a view where pandas has one).
  const py::object table =
      py::hasattr(data, "to_numpy") ? data.attr("to_numpy")("dtype"_a = "float64") : data;
  const MatrixIn in = matrixFrom(table, "Log values");
  if (in.matrix.cols() != static_cast<Eigen::Index>(header.size()))
    throw py::value_error("Log: " + std::to_string(in.matrix.cols()) + " columns of values but " +
                          std::to_string(header.size()) + " column names");
  return std::make_shared<Log>(logFromTable(header, in.matrix, source));
}

}  // namespace

void bindLog(py::module_& m) {
  py::class_<Log, std::shared_ptr<Log>>(
      m, "Log",
      "A synchronized log: one row per frame, one column per sensor reading (a marker: "
      "<name>.x/.y/.z), NaN where a reading is missing, and an optional time column.")
      .def(py::init(&fromTable), py::arg("data"), py::arg("columns") = py::none(),
           py::arg("source") = "<table>",
           "A log from a table in memory: a 2-D array (frames x columns) and its column names "
           "(a time column, 'time', 't' or 'timestamp', among them as in a CSV header), or a "
           "pandas DataFrame (its .to_numpy() and .columns). The values are copied once into "
           "the log. Checked as the same table written as CSV (header on line 1): errors "
           "name `source`, line and column.")
      .def_readonly("source", &Log::path, "The file (or source name) the log came from.")
      .def_readonly("columns", &Log::columns, "Column names, the time column excluded.")
      .def_readonly("time_name", &Log::time_name, "The time column's name, '' if none.")
      .def_property_readonly("frames", &Log::numFrames)
      .def_property_readonly(
          "values", [](py::object self) { return matrixView(self.cast<const Log&>().values, self); },
          "frames x columns float64, NaN = missing: a read-only view of the log's own data "
          "(no copy; np.array(log.values) for a writable one).")
      .def_property_readonly(
          "time",
          [](py::object self) -> py::object {
            const Log& log = self.cast<const Log&>();
            if (!log.hasTime()) return py::none();
            return vectorView(log.time, self);
          },
          "The time column (a read-only view), or None.")
      .def("__len__", &Log::numFrames)
      .def("__repr__", [](const Log& log) {
        return "<stac.Log from " + log.path + ": " + std::to_string(log.numFrames()) +
               " frames x " + std::to_string(log.columns.size()) + " columns>";
      });

  m.def(
      "read_log", [](const Path& path) { return readLog(path.string()); }, py::arg("path"),
        "Reads a CSV log. Raises InputError naming the file, line and column of a bad cell.");
  m.def("parse_log", &parseLog, py::arg("text"), py::arg("source") = "<string>",
        "Parses CSV text; `source` names it in errors.");
  m.def(
      "write_log", [](const Path& path, const Log& log) { writeLog(path.string(), log); },
      py::arg("path"), py::arg("log"),
      "Writes the log as CSV (numbers that read back exactly; NaN as empty cells).");
}

}  // namespace stac::python
