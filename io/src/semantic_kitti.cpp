#include "fmcw/io/semantic_kitti.hpp"

#include <cmath>
#include <cstdio>
#include <cstring>
#include <stdexcept>

#include "fmcw/core/check.hpp"
#include "fmcw/io/atomic_file.hpp"

namespace fmcw::io {

using core::concat;

namespace {
void append_u32(std::string& out, std::uint32_t bits) {
  for (int b = 0; b < 4; ++b) out.push_back(static_cast<char>((bits >> (8 * b)) & 0xFFu));
}
void append_f32(std::string& out, double value) {
  const float v = static_cast<float>(value);
  std::uint32_t bits = 0;
  std::memcpy(&bits, &v, 4);
  append_u32(out, bits);
}
}  // namespace

std::size_t write_semantic_kitti(const std::string& bin_path, const std::string& label_path, const PcdCloud& cloud,
                                 const PointLabels& labels, const std::string& where) {
  const std::size_t n = cloud.points();
  const PcdField* x = cloud.find("x");
  const PcdField* y = cloud.find("y");
  const PcdField* z = cloud.find("z");
  FMCW_CHECK_ARG(x && y && z, where, ": the cloud has no x y z fields");
  FMCW_CHECK_ARG(labels.semantic.size() == n && labels.instance.size() == n, where, ": ", labels.semantic.size(),
                 " labels for ", n, " points");
  const PcdField* intensity = cloud.find("intensity");
  std::string bin, label;
  std::size_t written = 0;
  for (std::size_t i = 0; i < n; ++i) {
    if (!(std::isfinite(x->values[i]) && std::isfinite(y->values[i]) && std::isfinite(z->values[i]))) continue;
    const double remission = intensity ? intensity->values[i] : 0.0;
    if (!std::isfinite(remission)) {
      throw core::FileError(concat(where, ": point ", i, " has a return but intensity ", remission));
    }
    append_f32(bin, x->values[i]);
    append_f32(bin, y->values[i]);
    append_f32(bin, z->values[i]);
    append_f32(bin, remission);
    // SemanticKITTI: semantic class in the lower 16 bits, instance id in the upper 16.
    append_u32(label, static_cast<std::uint32_t>(labels.semantic[i]) | (static_cast<std::uint32_t>(labels.instance[i]) << 16));
    ++written;
  }
  write_file_atomically(bin_path, [&](std::ostream& out) { out.write(bin.data(), static_cast<std::streamsize>(bin.size())); });
  try {
    write_file_atomically(label_path,
                          [&](std::ostream& out) { out.write(label.data(), static_cast<std::streamsize>(label.size())); });
  } catch (...) {
    // A scan without its labels would look complete to a reader: remove it too.
    std::remove(bin_path.c_str());
    throw;
  }
  return written;
}

}  // namespace fmcw::io
