#pragma once
// NumPy's .npy files (format version 1.0), the arrays np.load reads: here 2-D float32 arrays in
// C order, little-endian, as OpenPCDet takes its point clouds.

#include <cstddef>
#include <string>
#include <vector>

namespace fmcw::io {

/// The file's header: the magic "\x93NUMPY", version 1.0, the header length (uint16,
/// little-endian) and the dict {'descr': '<f4', 'fortran_order': False, 'shape': (rows, cols), }
/// padded with spaces and ended by a newline so that the data starts at a multiple of 64 bytes.
std::string npy_f32_header(std::size_t rows, std::size_t cols);

/// Writes values (rows x cols, row-major) as a float32 .npy atomically. std::invalid_argument
/// when values.size() != rows * cols; std::runtime_error when the file cannot be written.
void write_npy_f32(const std::string& path, const std::vector<float>& values, std::size_t rows, std::size_t cols);

}  // namespace fmcw::io
