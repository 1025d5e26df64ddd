#pragma once
// The Aeva Aeries II packed point layout of public FMCW datasets (HeLiPR, HeRCULES): one file
// per scan, no header, fixed-size little-endian records
//
//   offset  0  x              float32 [m]    sensor frame
//   offset  4  y              float32 [m]
//   offset  8  z              float32 [m]
//   offset 12  reflectivity   float32
//   offset 16  velocity       float32 [m/s]  radial (Doppler)
//   offset 20  time_offset_ns int32   [ns]   after the scan stamp
//   offset 24  line_index     uint8          scan line
//   offset 25  intensity      float32        29-byte records only
//
// and the organized Scan made from it: rows by line index, columns by azimuth
// (core::project_to_grid).

#include <cstdint>
#include <string>
#include <vector>

#include "fmcw/core/grid_projection.hpp"

namespace fmcw::io {

constexpr std::size_t kAevaRecordBytes = 25;
constexpr std::size_t kAevaRecordWithIntensityBytes = 29;

/// 25 or 29 bytes per record, or kAuto: from the file.
enum class AevaLayout { kAuto, k25, k29 };

/// "auto", "25" or "29"; std::invalid_argument otherwise.
AevaLayout parse_aeva_layout(const std::string& text);

/// The records of one file, as columns.
struct AevaRecords {
  std::vector<float> x_m, y_m, z_m, reflectivity, velocity_mps;
  std::vector<std::int32_t> time_offset_ns;
  std::vector<std::uint8_t> line_index;
  std::vector<float> intensity;  ///< 29-byte records only; empty for 25-byte records

  std::size_t size() const { return x_m.size(); }
  bool has_intensity() const { return !intensity.empty(); }
};

/// Which layout a file of this name and size holds, for kAuto: the one whose record size
/// divides the file size. A size both divide (a multiple of 725 bytes) is decided by the file
/// name when it is a nanosecond time stamp, as the datasets name their scans: the datasets'
/// own tools read 29-byte records for scans stamped after 1691936557946849179 ns. Otherwise
/// std::invalid_argument asks for the layout.
AevaLayout detect_aeva_layout(const std::string& path, std::uintmax_t size_bytes);

/// Reads every record. core::FileError naming the file (and the record and field) for a
/// directory or a file that is not regular (a FIFO, a device), an empty file, a size that is not
/// a whole number of records (known from the size alone, before anything is read), a NaN or
/// Inf in x, y, z, reflectivity, velocity or intensity, or a file that cannot be opened or
/// read. Records are read in blocks: memory for the columns, not for a copy of the file.
AevaRecords read_aeva(const std::string& path, AevaLayout layout = AevaLayout::kAuto);

/// Writes records in the layout above, 29 bytes each when they carry intensity, atomically.
void write_aeva(const std::string& path, const AevaRecords& records);

/// The valid pixels of a one-head scan as records in the head's own frame (the sensor frame
/// of an Aeva file): reflectivity from intensity, line_index from Scan::line_index (else the
/// row), time_offset_ns from the time offsets (else 0), no intensity column (25-byte records).
/// core::InputError for a scan of several heads (export each head on its own) or a row beyond
/// the 255 lines a record holds.
AevaRecords aeva_records_from_scan(const core::Scan& scan);

/// "0000000000100000000.bin": a stamp [s] as the 19-digit nanosecond name the datasets give
/// their scans, which read_aeva_scan reads back as the stamp.
std::string aeva_file_name(double stamp_s);

/// How an Aeva file becomes a Scan.
struct AevaScanParams {
  AevaLayout layout = AevaLayout::kAuto;
  /// Azimuth binning (fov_horizontal_deg, resolution_horizontal_deg) and the line count
  /// (lines: 0 = largest line index + 1). The defaults span the Aeries II's 120 deg at 0.2 deg.
  core::GridProjectionParams grid;
  /// The reader takes velocity with the project's sign (positive moving away, Eq. 6). A log
  /// recorded with the opposite convention shows a static world approaching at negative ego
  /// speed; this flips it.
  bool negate_velocity = false;
};

/// Records -> point list: Doppler from velocity, intensity from intensity when the records
/// carry it, else from reflectivity; time offsets in seconds; line index as the row.
core::PointList aeva_points(const AevaRecords& records, bool negate_velocity = false);

/// read_aeva + aeva_points + project_to_grid. The scan's stamp is the file name read as a
/// nanosecond time stamp when it is 16 to 19 digits, else 0. Errors name the file.
core::GridProjection read_aeva_scan(const std::string& path, const AevaScanParams& params = {});

}  // namespace fmcw::io
