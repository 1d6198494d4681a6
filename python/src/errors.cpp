// The library's errors as Python exceptions, with the messages stac_calib
// prints (file:line:column: what):
//   stac::InputError        -> stac.InputError (a ValueError) with .file,
//                              .line, .column (0: not applicable)
//   std::invalid_argument   -> ValueError (pybind11's own mapping)
//   any other std::exception -> RuntimeError (pybind11's own mapping)
#include "bindings.hpp"
#include "stac/error.hpp"

namespace stac::python {

void bindErrors(py::module_& m) {
  static py::exception<InputError> input_error(m, "InputError", PyExc_ValueError);
  input_error.doc() =
      "Bad input: a file (or a table given in memory) that breaks the formats of SPEC "
      "§2-3.\n\nstr(e) is what stac_calib prints after 'error: ', starting with "
      "'file:line:column:'. Attributes: file, line, column (1-based; 0 when not "
      "applicable).";
  py::register_exception_translator([](std::exception_ptr p) {
    try {
      if (p) std::rethrow_exception(p);
    } catch (const InputError& e) {
      // py::exception::operator() only sets the error: call the class itself.
      py::object error = py::reinterpret_borrow<py::object>(input_error.ptr())(e.what());
      error.attr("file") = e.file();
      error.attr("line") = e.line();
      error.attr("column") = e.column();
      PyErr_SetObject(input_error.ptr(), error.ptr());
    }
  });
}

}  // namespace stac::python
