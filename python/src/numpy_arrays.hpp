#pragma once
// Copies between the core's row-major vectors and numpy arrays of shape (rows, cols).
// Copies, not views: a Scan handed to Python stays valid whatever happens to the array.

#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <stdexcept>
#include <string>
#include <vector>

#include "fmcw/core/errors.hpp"

namespace fmcw::python {

namespace py = pybind11;

/// A (rows, cols) array holding a copy of values (row-major).
template <typename T, typename Out = T>
py::array_t<Out> to_image(const std::vector<T>& values, int rows, int cols) {
  py::array_t<Out> out({static_cast<py::ssize_t>(rows), static_cast<py::ssize_t>(cols)});
  std::copy(values.begin(), values.end(), out.mutable_data());
  return out;
}

/// Values of a 2-D array of the expected shape, converted to T. rows/cols < 0 take the array's
/// shape and report it back. ValueError (std::invalid_argument) naming the argument otherwise.
template <typename T>
std::vector<T> from_image(const py::handle& obj, int& rows, int& cols, const char* name) {
  const auto a = py::array_t<T, py::array::c_style | py::array::forcecast>::ensure(obj);
  if (!a) throw core::InputError(std::string("'") + name + "' must be a numeric array");
  if (a.ndim() != 2) {
    throw core::InputError(std::string("'") + name + "' must have shape (rows, cols), got " +
                           std::to_string(a.ndim()) + " dimensions");
  }
  const auto r = static_cast<int>(a.shape(0));
  const auto c = static_cast<int>(a.shape(1));
  if (rows >= 0 && (r != rows || c != cols)) {
    throw core::InputError(std::string("'") + name + "' has shape (" + std::to_string(r) + ", " + std::to_string(c) +
                           "), expected (" + std::to_string(rows) + ", " + std::to_string(cols) + ") like x");
  }
  rows = r;
  cols = c;
  return std::vector<T>(a.data(), a.data() + a.size());
}

/// Values of a 1-D array of n entries (n < 0: any length).
template <typename T>
std::vector<T> from_vector(const py::handle& obj, py::ssize_t n, const char* name) {
  const auto a = py::array_t<T, py::array::c_style | py::array::forcecast>::ensure(obj);
  if (!a || a.ndim() != 1) throw core::InputError(std::string("'") + name + "' must be a 1-D numeric array");
  if (n >= 0 && a.shape(0) != n) {
    throw core::InputError(std::string("'") + name + "' has " + std::to_string(a.shape(0)) + " values, expected " +
                           std::to_string(n) + " like x");
  }
  return std::vector<T>(a.data(), a.data() + a.size());
}

inline py::array_t<double> to_array(const Eigen::Vector3d& v) {
  py::array_t<double> out(3);
  std::copy(v.data(), v.data() + 3, out.mutable_data());
  return out;
}

inline py::array_t<double> to_array(const Eigen::Matrix3d& m) {
  py::array_t<double> out({3, 3});
  for (int r = 0; r < 3; ++r) {
    for (int c = 0; c < 3; ++c) out.mutable_at(r, c) = m(r, c);
  }
  return out;
}

/// A pose as a 4x4 homogeneous matrix.
inline py::array_t<double> to_array(const Eigen::Isometry3d& T) {
  py::array_t<double> out({4, 4});
  for (int r = 0; r < 4; ++r) {
    for (int c = 0; c < 4; ++c) out.mutable_at(r, c) = T.matrix()(r, c);
  }
  return out;
}

/// A 4x4 rigid transform; ValueError when it is not one (shape, bottom row, rotation).
inline Eigen::Isometry3d to_isometry(const py::handle& obj, const char* name) {
  const auto a = py::array_t<double, py::array::c_style | py::array::forcecast>::ensure(obj);
  if (!a || a.ndim() != 2 || a.shape(0) != 4 || a.shape(1) != 4) {
    throw core::InputError(std::string("'") + name + "' must be a 4x4 array");
  }
  Eigen::Matrix4d m;
  for (int r = 0; r < 4; ++r) {
    for (int c = 0; c < 4; ++c) m(r, c) = a.at(r, c);
  }
  const Eigen::Matrix3d R = m.topLeftCorner<3, 3>();
  if (!m.row(3).isApprox(Eigen::RowVector4d(0, 0, 0, 1)) || !(R.transpose() * R).isIdentity(1e-6) || R.determinant() < 0) {
    throw core::InputError(std::string("'") + name + "' must be a 4x4 rigid transform (rotation, translation, "
                           "bottom row 0 0 0 1)");
  }
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.linear() = R;
  T.translation() = m.topRightCorner<3, 1>();
  return T;
}

}  // namespace fmcw::python
