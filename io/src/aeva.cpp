#include "fmcw/io/aeva.hpp"

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <stdexcept>

#include "fmcw/core/check.hpp"
#include "fmcw/io/atomic_file.hpp"
#include "fmcw/io/input_file.hpp"

namespace fmcw::io {

using core::concat;
namespace fs = std::filesystem;

namespace {
// The datasets' tools switch to 29-byte records (with intensity) for scans stamped after this
// time [ns]; used only when the file size fits both layouts.
constexpr std::uint64_t kIntensityFromStampNs = 1691936557946849179ULL;

// Fields are assembled byte by byte from little-endian order, so the reader does not depend on
// the host's byte order.
std::uint32_t load_u32(const unsigned char* p) {
  return static_cast<std::uint32_t>(p[0]) | (static_cast<std::uint32_t>(p[1]) << 8) |
         (static_cast<std::uint32_t>(p[2]) << 16) | (static_cast<std::uint32_t>(p[3]) << 24);
}
float load_f32(const unsigned char* p) {
  const std::uint32_t bits = load_u32(p);
  float value = 0.0f;
  std::memcpy(&value, &bits, sizeof value);
  return value;
}
void store_u32(std::uint32_t bits, char* p) {
  for (int b = 0; b < 4; ++b) p[b] = static_cast<char>((bits >> (8 * b)) & 0xFFu);
}
void store_f32(float value, char* p) {
  std::uint32_t bits = 0;
  std::memcpy(&bits, &value, sizeof bits);
  store_u32(bits, p);
}

// The file name as a nanosecond time stamp, as the datasets name their scans: 16 to 19 digits
// (19 fit uint64; fewer than 16 is more likely a frame number than a time after 1970).
bool stamp_from_name(const std::string& path, std::uint64_t& stamp_ns) {
  const std::string stem = fs::path(path).stem().string();
  if (stem.size() < 16 || stem.size() > 19 || stem.find_first_not_of("0123456789") != std::string::npos) return false;
  stamp_ns = std::stoull(stem);
  return true;
}

std::size_t record_bytes(AevaLayout layout) {
  return layout == AevaLayout::k29 ? kAevaRecordWithIntensityBytes : kAevaRecordBytes;
}
}  // namespace

AevaLayout parse_aeva_layout(const std::string& text) {
  if (text == "auto") return AevaLayout::kAuto;
  if (text == "25") return AevaLayout::k25;
  if (text == "29") return AevaLayout::k29;
  throw core::InputError("Aeva record layout must be auto, 25 or 29, got '" + text + "'");
}

AevaLayout detect_aeva_layout(const std::string& path, std::uintmax_t size_bytes) {
  const bool fits25 = size_bytes % kAevaRecordBytes == 0;
  const bool fits29 = size_bytes % kAevaRecordWithIntensityBytes == 0;
  if (fits25 && !fits29) return AevaLayout::k25;
  if (fits29 && !fits25) return AevaLayout::k29;
  if (!fits25 && !fits29) {
    throw core::FileError(concat(path, ": size ", size_bytes,
                                 " bytes is not a whole number of Aeva records: neither 25-byte (", size_bytes,
                                 " mod 25 = ", size_bytes % kAevaRecordBytes, ") nor 29-byte (", size_bytes,
                                 " mod 29 = ", size_bytes % kAevaRecordWithIntensityBytes,
                                 "); the file is truncated or not an Aeva scan"));
  }
  std::uint64_t stamp_ns = 0;
  if (stamp_from_name(path, stamp_ns)) {
    return stamp_ns > kIntensityFromStampNs ? AevaLayout::k29 : AevaLayout::k25;
  }
  throw core::FileError(concat(path, ": size ", size_bytes,
                               " bytes fits both 25- and 29-byte Aeva records and the name is not a time "
                               "stamp; give the layout (--aeva-record 25 or 29)"));
}

AevaRecords read_aeva(const std::string& path, AevaLayout layout) {
  // The size decides the layout and the record count before a byte is read: a file of the wrong
  // size costs an error, not its size in memory.
  const std::uintmax_t size = regular_file_size(path, "Aeva file");
  if (size == 0) throw core::FileError(concat(path, ": empty Aeva file (no records)"));
  if (layout == AevaLayout::kAuto) layout = detect_aeva_layout(path, size);
  const std::size_t stride = record_bytes(layout);
  if (size % stride != 0) {
    throw core::FileError(concat(path, ": size ", size, " bytes is not a multiple of the ", stride,
                                 "-byte Aeva record (", size / stride, " whole records and ", size % stride,
                                 " bytes left over)"));
  }
  const auto n = static_cast<std::size_t>(size / stride);
  std::ifstream in(path, std::ios::binary);
  if (!in) throw core::FileError(concat(path, ": cannot open Aeva file: ", std::strerror(errno)));
  AevaRecords r;
  for (auto* column : {&r.x_m, &r.y_m, &r.z_m, &r.reflectivity, &r.velocity_mps}) column->resize(n);
  r.time_offset_ns.resize(n);
  r.line_index.resize(n);
  if (layout == AevaLayout::k29) r.intensity.resize(n);
  static const char* const kFloatNames[] = {"x", "y", "z", "reflectivity", "velocity"};
  // Records are read a block at a time into the columns, never as a whole copy of the file.
  constexpr std::size_t kBlockRecords = 1 << 15;
  std::vector<unsigned char> block(std::min(n, kBlockRecords) * stride);
  for (std::size_t first = 0; first < n; first += kBlockRecords) {
    const std::size_t count = std::min(kBlockRecords, n - first);
    in.read(reinterpret_cast<char*>(block.data()), static_cast<std::streamsize>(count * stride));
    if (static_cast<std::size_t>(in.gcount()) != count * stride) {
      throw core::FileError(concat(path, ": read failed at byte ", first * stride + static_cast<std::size_t>(in.gcount()),
                                   " of ", size, " (did the file change while it was read?)"));
    }
    for (std::size_t i = first; i < first + count; ++i) {
      const unsigned char* p = block.data() + (i - first) * stride;
      float* floats[] = {&r.x_m[i], &r.y_m[i], &r.z_m[i], &r.reflectivity[i], &r.velocity_mps[i]};
      for (int f = 0; f < 5; ++f) {
        *floats[f] = load_f32(p + 4 * f);
        if (!std::isfinite(*floats[f])) {
          throw core::FileError(concat(path, ": record ", i, " (byte ", i * stride + 4 * static_cast<std::size_t>(f),
                                       "): field '", kFloatNames[f], "' is ", *floats[f],
                                       ", expected a finite number"));
        }
      }
      r.time_offset_ns[i] = static_cast<std::int32_t>(load_u32(p + 20));
      r.line_index[i] = p[24];
      if (layout == AevaLayout::k29) {
        r.intensity[i] = load_f32(p + 25);
        if (!std::isfinite(r.intensity[i])) {
          throw core::FileError(concat(path, ": record ", i, " (byte ", i * stride + 25, "): field 'intensity' is ",
                                       r.intensity[i], ", expected a finite number"));
        }
      }
    }
  }
  return r;
}

void write_aeva(const std::string& path, const AevaRecords& r) {
  const std::size_t n = r.size();
  for (const auto* column : {&r.y_m, &r.z_m, &r.reflectivity, &r.velocity_mps}) {
    FMCW_CHECK_ARG(column->size() == n, "Aeva records: columns of different lengths (", column->size(), " vs ", n, ")");
  }
  FMCW_CHECK_ARG(r.time_offset_ns.size() == n && r.line_index.size() == n,
                 "Aeva records: time_offset_ns and line_index need one value per record");
  FMCW_CHECK_ARG(r.intensity.empty() || r.intensity.size() == n,
                 "Aeva records: intensity needs one value per record, or none");
  const std::size_t stride = r.has_intensity() ? kAevaRecordWithIntensityBytes : kAevaRecordBytes;
  std::vector<char> bytes(n * stride);
  for (std::size_t i = 0; i < n; ++i) {
    char* p = bytes.data() + i * stride;
    const float floats[] = {r.x_m[i], r.y_m[i], r.z_m[i], r.reflectivity[i], r.velocity_mps[i]};
    for (int f = 0; f < 5; ++f) store_f32(floats[f], p + 4 * f);
    store_u32(static_cast<std::uint32_t>(r.time_offset_ns[i]), p + 20);
    p[24] = static_cast<char>(r.line_index[i]);
    if (r.has_intensity()) store_f32(r.intensity[i], p + 25);
  }
  write_file_atomically(path, [&](std::ostream& out) { out.write(bytes.data(), static_cast<std::streamsize>(bytes.size())); });
}

AevaRecords aeva_records_from_scan(const core::Scan& scan) {
  scan.validate();
  FMCW_CHECK_ARG(scan.heads.size() == 1, "Aeva records: the scan has ", scan.heads.size(),
                 " heads; an Aeva file holds one sensor's points (export a one-head rig)");
  const Eigen::Isometry3d T_head_rig = scan.heads[0].T_rig_head.inverse();
  AevaRecords r;
  for (int row = 0; row < scan.rows; ++row) {
    for (int col = 0; col < scan.cols; ++col) {
      const std::size_t i = scan.index(row, col);
      if (!scan.valid[i]) continue;
      const int line = scan.line_index.empty() ? row : scan.line_index[i];
      FMCW_CHECK_ARG(line <= 255, "Aeva records: line ", line, " (row ", row, ") does not fit the record's 8-bit line_index");
      const Eigen::Vector3d p = T_head_rig * scan.position(i);
      r.x_m.push_back(static_cast<float>(p.x()));
      r.y_m.push_back(static_cast<float>(p.y()));
      r.z_m.push_back(static_cast<float>(p.z()));
      r.reflectivity.push_back(scan.intensity[i]);
      r.velocity_mps.push_back(scan.radial_velocity_mps[i]);
      const double t = scan.time_offset_s.empty() ? 0.0 : static_cast<double>(scan.time_offset_s[i]);
      r.time_offset_ns.push_back(static_cast<std::int32_t>(std::llround(t * 1e9)));
      r.line_index.push_back(static_cast<std::uint8_t>(line));
    }
  }
  return r;
}

std::string aeva_file_name(double stamp_s) {
  FMCW_CHECK_ARG(std::isfinite(stamp_s) && stamp_s >= 0.0 && stamp_s < 9.2e9, "Aeva file name: stamp ", stamp_s,
                 " s is not a time after 1970 that a 19-digit nanosecond name can hold");
  std::string digits = std::to_string(static_cast<unsigned long long>(std::llround(stamp_s * 1e9)));
  return std::string(19 - std::min<std::size_t>(19, digits.size()), '0') + digits + ".bin";
}

core::PointList aeva_points(const AevaRecords& r, bool negate_velocity) {
  core::PointList points;
  points.x_m = r.x_m;
  points.y_m = r.y_m;
  points.z_m = r.z_m;
  points.radial_velocity_mps = r.velocity_mps;
  if (negate_velocity) {
    for (float& v : points.radial_velocity_mps) v = -v;
  }
  points.intensity = r.has_intensity() ? r.intensity : r.reflectivity;
  points.time_offset_s.resize(r.size());
  for (std::size_t i = 0; i < r.size(); ++i) points.time_offset_s[i] = static_cast<float>(r.time_offset_ns[i] * 1e-9);
  points.line_index.assign(r.line_index.begin(), r.line_index.end());
  return points;
}

core::GridProjection read_aeva_scan(const std::string& path, const AevaScanParams& params) {
  const AevaRecords records = read_aeva(path, params.layout);
  const int lines = params.grid.lines;
  for (std::size_t i = 0; lines > 0 && i < records.size(); ++i) {
    if (records.line_index[i] >= lines) {
      throw core::FileError(concat(path, ": record ", i, ": line_index ", static_cast<int>(records.line_index[i]),
                                   " is out of range [0, ", lines, ") (the sensor has ", lines, " lines)"));
    }
  }
  core::GridProjection projection;
  params.grid.validate();  // a bad option is the caller's error (InputError), not the file's
  try {
    projection = core::project_to_grid(aeva_points(records, params.negate_velocity), params.grid);
  } catch (const std::exception&) {
    core::rethrow_as_file_error(concat(path, ": "));  // a bad record is the file's
  }
  std::uint64_t stamp_ns = 0;
  if (stamp_from_name(path, stamp_ns)) projection.scan.stamp_s = static_cast<double>(stamp_ns) * 1e-9;
  return projection;
}

}  // namespace fmcw::io
