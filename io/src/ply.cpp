#include "fmcw/io/ply.hpp"

#include <cmath>
#include <cstring>
#include <stdexcept>

#include "fmcw/core/check.hpp"
#include "fmcw/io/atomic_file.hpp"

namespace fmcw::io {

using core::concat;

namespace {
const char* ply_type(const PcdField& f) {
  if (f.type == 'F') return f.size == 8 ? "double" : "float";
  if (f.type == 'U') {
    if (f.size == 1) return "uchar";
    if (f.size == 2) return "ushort";
    if (f.size == 4) return "uint";
  }
  if (f.type == 'I') {
    if (f.size == 1) return "char";
    if (f.size == 2) return "short";
    if (f.size == 4) return "int";
  }
  throw core::InputError(concat("PLY: field '", f.name, "' of type ", f.type, f.size,
                                " has no PLY equivalent (8-byte integers)"));
}

// One value in the field's own type and size, little-endian.
void append_value(std::string& out, const PcdField& f, double value) {
  std::uint64_t bits = 0;
  if (f.type == 'F' && f.size == 4) {
    const float v = static_cast<float>(value);
    std::uint32_t b = 0;
    std::memcpy(&b, &v, 4);
    bits = b;
  } else if (f.type == 'F') {
    std::memcpy(&bits, &value, 8);
  } else if (f.type == 'U') {
    bits = static_cast<std::uint64_t>(value);
  } else {
    bits = static_cast<std::uint64_t>(static_cast<std::int64_t>(value));
  }
  for (int b = 0; b < f.size; ++b) out.push_back(static_cast<char>((bits >> (8 * b)) & 0xFFu));
}
}  // namespace

std::size_t write_ply(const std::string& path, const PcdCloud& cloud, const std::vector<Rgb>& colors) {
  const std::size_t n = cloud.points();
  FMCW_CHECK_ARG(colors.empty() || colors.size() == n, "PLY: ", colors.size(), " colours for ", n, " points");
  const PcdField* x = cloud.find("x");
  const PcdField* y = cloud.find("y");
  const PcdField* z = cloud.find("z");
  FMCW_CHECK_ARG(x && y && z, "PLY: the cloud has no x y z fields");
  const bool colored = !colors.empty();
  for (const PcdField& f : cloud.fields) {
    ply_type(f);
    FMCW_CHECK_ARG(!colored || (f.name != "red" && f.name != "green" && f.name != "blue"), "PLY: the cloud has a field '",
                   f.name, "' already; export without colour");
  }
  std::string body;
  std::size_t vertices = 0;
  for (std::size_t i = 0; i < n; ++i) {
    if (!(std::isfinite(x->values[i]) && std::isfinite(y->values[i]) && std::isfinite(z->values[i]))) continue;
    for (const PcdField& f : cloud.fields) append_value(body, f, f.values[i]);
    if (colored) {
      body.push_back(static_cast<char>(colors[i].r));
      body.push_back(static_cast<char>(colors[i].g));
      body.push_back(static_cast<char>(colors[i].b));
    }
    ++vertices;
  }
  std::string header = "ply\nformat binary_little_endian 1.0\ncomment written by fmcw export\n";
  for (const std::string& c : cloud.comments) header += "comment " + c + "\n";
  header += concat("element vertex ", vertices, "\n");
  for (const PcdField& f : cloud.fields) header += concat("property ", ply_type(f), " ", f.name, "\n");
  if (colored) header += "property uchar red\nproperty uchar green\nproperty uchar blue\n";
  header += "end_header\n";
  write_file_atomically(path, [&](std::ostream& out) {
    out << header;
    out.write(body.data(), static_cast<std::streamsize>(body.size()));
  });
  return vertices;
}

}  // namespace fmcw::io
