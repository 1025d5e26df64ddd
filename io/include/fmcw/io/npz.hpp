#pragma once
// NumPy arrays in .npy bytes and .npz archives (a zip of NAME.npy members), as np.savez and
// np.savez_compressed write them. The zip side is libzip's: a build without libzip reads and
// writes no .npz (npz_supported() says so, and the functions throw naming what is missing).

#include <cstddef>
#include <cstdint>
#include <map>
#include <string>
#include <vector>

namespace fmcw::io {

/// One array: little-endian numbers ('f' float, 'i' signed, 'u' unsigned, 'b' bool) or
/// fixed-width unicode strings ('U', 4 bytes a character), C order. 'O' (a pickled Python object
/// array) keeps its shape and no data: reading it throws.
struct NpyArray {
  char kind = 'f';
  std::size_t item_bytes = 4;        ///< bytes per element (per string for 'U')
  std::vector<std::size_t> shape;
  std::vector<unsigned char> data;   ///< elements in C order, as in the file

  std::size_t size() const;  ///< number of elements (the product of shape)
  /// Numbers as doubles (int64 beyond 2^53 lose precision). core::FileError naming source for
  /// strings.
  std::vector<double> to_doubles(const std::string& source) const;
  /// 'U' arrays as strings (characters beyond ASCII as '?'). core::FileError naming source
  /// for numbers.
  std::vector<std::string> to_strings(const std::string& source) const;
};

/// Parses .npy bytes (format 1.0, 2.0 or 3.0). core::FileError naming source for a bad magic,
/// header or dtype, Fortran order, or data shorter or longer than the shape says.
NpyArray parse_npy(const std::string& bytes, const std::string& source);
/// The .npy bytes of an array (format 1.0).
std::string npy_bytes(const NpyArray& array);

/// Whether this build reads and writes .npz (it was built with libzip).
bool npz_supported();
/// Every NAME.npy member of an .npz, by NAME. core::FileError naming the file (and the member)
/// for a file that is not a zip, a damaged member, a bad array; core::InputError when the build
/// has no libzip.
std::map<std::string, NpyArray> read_npz(const std::string& path);
/// Writes arrays as NAME.npy members of an uncompressed .npz, atomically.
void write_npz(const std::string& path, const std::map<std::string, NpyArray>& arrays);

/// A float32 column (N,) / (N, k) array, an unsigned or signed integer array, a string array.
NpyArray npy_f32(const std::vector<float>& values, std::vector<std::size_t> shape);
NpyArray npy_u32(const std::vector<std::uint32_t>& values, std::vector<std::size_t> shape);
NpyArray npy_i64(const std::vector<std::int64_t>& values, std::vector<std::size_t> shape);
NpyArray npy_strings(const std::vector<std::string>& values, std::vector<std::size_t> shape);

}  // namespace fmcw::io
