// Numpy arrays in and out. Out: views over the library's own storage wherever
// an object keeps it (a log's values, a result's joint angles), copies only
// for small vectors built on the fly. In: one copy into the library's
// storage, which must own its data (a Log is a value the library keeps);
// a second one first when the array is not float64 and C-contiguous.
#include <pybind11/eigen.h>

#include "bindings.hpp"

namespace stac::python {

namespace {
py::array_t<double> readOnly(py::array_t<double> a) {
  // Writing through the view would change an object the library treats as
  // immutable: np.array(view) gives a writable copy.
  py::detail::array_proxy(a.ptr())->flags &= ~py::detail::npy_api::NPY_ARRAY_WRITEABLE_;
  return a;
}
}  // namespace

py::array_t<double> matrixView(const RowMatrix& m, py::handle owner) {
  const py::ssize_t rows = m.rows(), cols = m.cols();
  const py::ssize_t row_stride = cols * static_cast<py::ssize_t>(sizeof(double));
  return readOnly(py::array_t<double>({rows, cols}, {row_stride, py::ssize_t(sizeof(double))},
                                      m.data(), owner));
}

py::array_t<double> vectorView(const std::vector<double>& v, py::handle owner) {
  return readOnly(py::array_t<double>({static_cast<py::ssize_t>(v.size())},
                                      {py::ssize_t(sizeof(double))}, v.data(), owner));
}

py::array_t<double> vectorCopy(const Eigen::VectorXd& v) {
  py::array_t<double> a(v.size());
  std::copy(v.data(), v.data() + v.size(), a.mutable_data());
  return a;
}

py::array_t<double> vector3(const Eigen::Vector3d& v) { return vectorCopy(v); }

MatrixIn matrixFrom(const py::handle& array, const char* what) {
  auto a = py::array_t<double, py::array::c_style | py::array::forcecast>::ensure(array);
  if (!a) throw py::type_error(std::string(what) + ": expected a 2-D array of numbers");
  if (a.ndim() != 2)
    throw py::value_error(std::string(what) + ": expected a 2-D array (frames x columns), got " +
                          std::to_string(a.ndim()) + "-D");
  return MatrixIn{a, Eigen::Map<const RowMatrix>(a.data(), a.shape(0), a.shape(1))};
}

py::str groupKey(SensorGroup g) { return py::str(groupName(g)); }

}  // namespace stac::python

namespace stac::python {

py::array_t<double> matrixOwned(RowMatrix&& m) {
  auto* owned = new RowMatrix(std::move(m));
  py::capsule free_when_done(owned, [](void* p) { delete static_cast<RowMatrix*>(p); });
  return matrixView(*owned, free_when_done);
}

}  // namespace stac::python
