#include "fmcw/io/pcd.hpp"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <fstream>
#include <iomanip>
#include <limits>
#include <map>
#include <sstream>
#include <stdexcept>

#include "fmcw/core/check.hpp"
#include "fmcw/io/atomic_file.hpp"
#include "fmcw/io/input_file.hpp"
#include "pcd_values.hpp"

namespace fmcw::io {

using core::concat;
using detail::decode;
using detail::encode;
using detail::valid_type_size;

namespace {

std::vector<std::string> split_words(const std::string& line) {
  std::istringstream in(line);
  std::vector<std::string> words;
  std::string w;
  while (in >> w) words.push_back(w);
  return words;
}

int parse_int(const std::string& s, const std::string& where) {
  std::size_t used = 0;
  long long v = 0;
  try {
    v = std::stoll(s, &used);
  } catch (const std::exception&) {
    used = 0;
  }
  FMCW_CHECK_FILE(used == s.size() && v >= 0 && v <= std::numeric_limits<int>::max(), where,
                  ": expected a non-negative integer, got '", s, "'");
  return static_cast<int>(v);
}

struct RawField {
  std::string name;
  char type = 'F';
  int size = 4;
  int count = 1;
};

std::string fmt_double(double v) {
  std::ostringstream out;
  out << std::setprecision(17) << v;
  return out.str();
}

// Header lines are short; a longer one means the file is not a PCD (or has no newline at all).
constexpr std::size_t kMaxHeaderLineBytes = 4096;
// The whole header, comments included, is small too: a file of a billion comment lines is not.
constexpr std::size_t kMaxHeaderBytes = std::size_t{1} << 20;
// An ASCII value takes at most this many characters ("-1.2345678901234567e-308" takes 24).
constexpr std::size_t kMaxAsciiValueBytes = 64;

// The binary body read front to back through one block of memory, whatever the file's size:
// values are taken where they lie, fields that are not read are skipped.
class BlockReader {
 public:
  BlockReader(std::istream& in, const std::string& path, std::size_t body_bytes)
      : in_(in), path_(path), buf_(std::min(body_bytes, kBlockBytes)) {}

  // The next k bytes (k <= the block size), contiguous.
  const unsigned char* take(std::size_t k) {
    if (end_ - pos_ < k) refill(k);
    const unsigned char* p = buf_.data() + pos_;
    pos_ += k;
    return p;
  }

  void skip(std::size_t k) {
    const std::size_t held = end_ - pos_;
    if (k <= held) {
      pos_ += k;
      return;
    }
    pos_ = end_ = 0;
    in_.seekg(static_cast<std::streamoff>(k - held), std::ios::cur);
  }

 private:
  static constexpr std::size_t kBlockBytes = std::size_t{1} << 20;

  void refill(std::size_t k) {
    const std::size_t held = end_ - pos_;
    std::memmove(buf_.data(), buf_.data() + pos_, held);
    pos_ = 0;
    in_.read(reinterpret_cast<char*>(buf_.data() + held), static_cast<std::streamsize>(buf_.size() - held));
    end_ = held + static_cast<std::size_t>(in_.gcount());
    in_.clear(in_.rdstate() & ~(std::ios::eofbit | std::ios::failbit));  // a short last block is fine
    // The size was checked before the body was read: a shortfall is a file that changed meanwhile.
    if (end_ < k) throw core::FileError(concat(path_, ": read error in PCD data (did the file change while it was read?)"));
  }

  std::istream& in_;
  const std::string& path_;
  std::vector<unsigned char> buf_;
  std::size_t pos_ = 0;
  std::size_t end_ = 0;
};

}  // namespace

const PcdField* PcdCloud::find(const std::string& name) const {
  for (const auto& f : fields) {
    if (f.name == name) return &f;
  }
  return nullptr;
}

namespace {
// packed: a binary file's data is copied as it lies into it instead of decoded into the fields.
PcdCloud read_pcd_impl(const std::string& path, PcdPackedData* packed) {
  regular_file_size(path, "PCD file");  // before opening: a FIFO would block, /dev/zero never ends
  std::ifstream in(path, std::ios::binary);
  if (!in) throw core::FileError(concat(path, ": cannot open PCD file: ", std::strerror(errno)));

  PcdCloud cloud;
  std::vector<RawField> raw;
  std::map<std::string, std::vector<std::string>> header;
  std::map<std::string, int> header_line;
  std::string line;
  int line_no = 0;
  std::string data_kind;
  const char* required[] = {"FIELDS", "SIZE", "TYPE", "WIDTH", "HEIGHT", "POINTS", "DATA"};
  std::size_t header_bytes = 0;
  for (LineRead got; (got = read_bounded_line(in, line, kMaxHeaderLineBytes)) != LineRead::kEnd;) {
    ++line_no;
    if (got == LineRead::kTooLong) {
      throw core::FileError(concat(path, ":", line_no, ": header line too long; not a PCD file?"));
    }
    header_bytes += line.size() + 1;
    FMCW_CHECK_FILE(header_bytes <= kMaxHeaderBytes, path, ":", line_no, ": header longer than ", kMaxHeaderBytes,
                    " bytes without a DATA line; not a PCD file?");
    if (!line.empty() && line.back() == '\r') line.pop_back();
    if (line.empty()) continue;
    if (line[0] == '#') {
      cloud.comments.push_back(line.size() > 1 && line[1] == ' ' ? line.substr(2) : line.substr(1));
      continue;
    }
    auto words = split_words(line);
    if (words.empty()) continue;
    const std::string key = words[0];
    words.erase(words.begin());
    static const char* known[] = {"VERSION", "FIELDS", "SIZE", "TYPE", "COUNT", "WIDTH", "HEIGHT", "VIEWPOINT", "POINTS", "DATA"};
    if (std::find_if(std::begin(known), std::end(known), [&](const char* k) { return key == k; }) == std::end(known)) {
      throw core::FileError(concat(path, ":", line_no, ": unknown PCD header key '", key, "'"));
    }
    if (header.count(key)) throw core::FileError(concat(path, ":", line_no, ": header key '", key, "' given twice"));
    header[key] = words;
    header_line[key] = line_no;
    if (key == "DATA") {
      FMCW_CHECK_FILE(words.size() == 1, path, ":", line_no, ": DATA takes one word");
      data_kind = words[0];
      break;
    }
  }
  for (const char* key : required) {
    if (!header.count(key)) throw core::FileError(concat(path, ": PCD header has no ", key, " line (read ", line_no, " lines)"));
  }
  const auto where = [&](const std::string& key) { return concat(path, ":", header_line[key], ": ", key); };
  const auto& names = header["FIELDS"];
  FMCW_CHECK_FILE(!names.empty(), where("FIELDS"), " lists no fields");
  const auto expect_len = [&](const std::string& key) {
    FMCW_CHECK_FILE(header[key].size() == names.size(), where(key), " has ", header[key].size(),
                    " entries but FIELDS has ", names.size());
  };
  expect_len("SIZE");
  expect_len("TYPE");
  if (header.count("COUNT")) expect_len("COUNT");
  for (std::size_t f = 0; f < names.size(); ++f) {
    RawField rf;
    rf.name = names[f];
    rf.size = parse_int(header["SIZE"][f], where("SIZE"));
    FMCW_CHECK_FILE(header["TYPE"][f].size() == 1, where("TYPE"), ": type '", header["TYPE"][f], "' of field '", rf.name,
                    "' is not one of F, U, I");
    rf.type = header["TYPE"][f][0];
    rf.count = header.count("COUNT") ? parse_int(header["COUNT"][f], where("COUNT")) : 1;
    FMCW_CHECK_FILE(valid_type_size(rf.type, rf.size), where("TYPE"), ": field '", rf.name, "' has TYPE ", rf.type,
                    " with SIZE ", rf.size, " (F takes 4 or 8; U and I take 1, 2, 4 or 8)");
    FMCW_CHECK_FILE(rf.count >= 1, where("COUNT"), ": field '", rf.name, "' has COUNT 0");
    for (const auto& other : raw) {
      FMCW_CHECK_FILE(other.name != rf.name || rf.name == "_", where("FIELDS"), ": field '", rf.name, "' appears twice");
    }
    raw.push_back(rf);
  }
  FMCW_CHECK_FILE(header["WIDTH"].size() == 1 && header["HEIGHT"].size() == 1 && header["POINTS"].size() == 1,
                  path, ": WIDTH, HEIGHT and POINTS take one number each");
  cloud.width = parse_int(header["WIDTH"][0], where("WIDTH"));
  cloud.height = parse_int(header["HEIGHT"][0], where("HEIGHT"));
  const int points = parse_int(header["POINTS"][0], where("POINTS"));
  FMCW_CHECK_FILE(static_cast<std::size_t>(points) == cloud.points(), where("POINTS"), " is ", points,
                  " but WIDTH x HEIGHT is ", cloud.width, " x ", cloud.height, " = ", cloud.points());
  FMCW_CHECK_LIMIT(cloud.points() <= (std::size_t{1} << 31), where("POINTS"), " is too large: ", cloud.points());

  std::size_t stride = 0;
  std::size_t tokens_per_point = 0;
  for (const auto& rf : raw) {
    stride += static_cast<std::size_t>(rf.size) * static_cast<std::size_t>(rf.count);
    tokens_per_point += static_cast<std::size_t>(rf.count);
  }
  const std::size_t n = cloud.points();
  // COUNT may be up to 2^31 per field: sizes are bounded before they are multiplied.
  const std::size_t limit = static_cast<std::size_t>(std::numeric_limits<std::int64_t>::max() / 4);
  FMCW_CHECK_LIMIT(n == 0 || (stride <= limit / n && tokens_per_point <= limit / n), where("POINTS"), ": ", n,
                   " points of ", stride, " bytes is more data than a file can hold");
  const std::streampos data_begin = in.tellg();
  in.seekg(0, std::ios::end);
  const std::streamoff available = in.tellg() - data_begin;
  in.seekg(data_begin);
  // The header is checked against the bytes that follow it before anything is allocated, so a
  // header that lies about its size costs an error, not gigabytes.
  constexpr std::streamoff kMaxPclPadding = 65536;
  if (data_kind == "binary") {
    const auto needed = static_cast<std::streamoff>(n * stride);
    FMCW_CHECK_FILE(available >= needed, path, ": truncated PCD: header promises ", n, " points of ", stride,
                    " bytes (", needed, " bytes) but the file holds ", available, " bytes of data");
    // PCL's own writer pads binary files with zeros to a memory page past the data; any other
    // surplus means the header does not describe the data (the zeros are checked once read).
    FMCW_CHECK_FILE(available - needed < kMaxPclPadding, path, ": PCD data is ", available,
                    " bytes but the header describes ", needed, " (", n, " points of ", stride,
                    " bytes); the header does not match the data");
  } else if (data_kind == "ascii") {
    // Every value takes at least one character and one separator.
    const auto needed = static_cast<std::streamoff>(n * tokens_per_point * 2);
    FMCW_CHECK_FILE(available + 1 >= needed, path, ": truncated PCD: header promises ", n, " points of ", tokens_per_point,
                    " values but only ", available, " bytes follow the header");
  } else {
    throw core::FileError(concat(where("DATA"), " '", data_kind, "' is not supported (use binary or ascii)"));
  }
  const bool copy_packed = packed != nullptr && data_kind == "binary";
  // Per raw field: the cloud field it fills, -1 where it is skipped (padding "_", COUNT > 1);
  // decided once here, not per point.
  std::vector<std::ptrdiff_t> target(raw.size(), -1);
  for (std::size_t f = 0; f < raw.size(); ++f) {
    const RawField& rf = raw[f];
    if (rf.name == "_") continue;
    if (rf.count == 1) {
      target[f] = static_cast<std::ptrdiff_t>(cloud.fields.size());
      cloud.fields.push_back(PcdField{rf.name, rf.type, rf.size, std::vector<double>(copy_packed ? 0 : n)});
    } else {
      cloud.multi_count_fields.emplace_back(rf.name, rf.count);
    }
  }

  if (copy_packed) {
    packed->stride = stride;
    packed->layout.clear();
    std::size_t offset = 0;
    for (const auto& rf : raw) {
      packed->layout.push_back({rf.name, rf.type, rf.size, rf.count, offset});
      offset += static_cast<std::size_t>(rf.size) * static_cast<std::size_t>(rf.count);
    }
    const auto needed = static_cast<std::size_t>(n * stride);
    packed->data.resize(static_cast<std::size_t>(available));
    in.read(reinterpret_cast<char*>(packed->data.data()), available);
    FMCW_CHECK_FILE(in.gcount() == available, path, ": read error in PCD data (did the file change while it was read?)");
    FMCW_CHECK_FILE(std::all_of(packed->data.begin() + static_cast<std::ptrdiff_t>(needed), packed->data.end(),
                                [](std::uint8_t b) { return b == 0; }),
                    path, ": PCD data is ", available, " bytes but the header describes ", needed, " (", n,
                    " points of ", stride, " bytes); the header does not match the data");
    packed->data.resize(needed);
  } else if (data_kind == "binary") {
    const auto needed = static_cast<std::size_t>(n * stride);
    BlockReader body(in, path, static_cast<std::size_t>(available));
    for (std::size_t i = 0; i < n; ++i) {
      for (std::size_t f = 0; f < raw.size(); ++f) {
        const RawField& rf = raw[f];
        const auto bytes = static_cast<std::size_t>(rf.size) * static_cast<std::size_t>(rf.count);
        if (target[f] >= 0) {
          cloud.fields[static_cast<std::size_t>(target[f])].values[i] = decode(body.take(bytes), rf.type, rf.size);
        } else {
          body.skip(bytes);
        }
      }
    }
    const auto padding = static_cast<std::size_t>(available) - needed;  // under kMaxPclPadding
    const unsigned char* pad = body.take(padding);
    FMCW_CHECK_FILE(std::all_of(pad, pad + padding, [](unsigned char b) { return b == 0; }), path, ": PCD data is ",
                    available, " bytes but the header describes ", needed, " (", n, " points of ", stride,
                    " bytes); the header does not match the data");
  } else {  // ascii
    const std::size_t max_line = kMaxHeaderLineBytes + kMaxAsciiValueBytes * tokens_per_point;
    for (std::size_t i = 0; i < n; ++i) {
      const LineRead got = read_bounded_line(in, line, max_line);
      if (got == LineRead::kEnd) {
        throw core::FileError(concat(path, ": truncated PCD: header promises ", n, " points, file ends after ", i));
      }
      ++line_no;
      FMCW_CHECK_FILE(got == LineRead::kLine, path, ":", line_no, ": point ", i, ": line longer than ", max_line,
                      " bytes for ", tokens_per_point, " values; the data does not match the header");
      const auto words = split_words(line);
      FMCW_CHECK_FILE(words.size() == tokens_per_point, path, ":", line_no, ": point ", i, " has ", words.size(),
                      " values, expected ", tokens_per_point);
      std::size_t t = 0;
      for (std::size_t f = 0; f < raw.size(); ++f) {
        const RawField& rf = raw[f];
        if (target[f] >= 0) {
          const std::string& w = words[t];
          char* end = nullptr;
          const double v = std::strtod(w.c_str(), &end);
          FMCW_CHECK_FILE(end != nullptr && *end == '\0', path, ":", line_no, ": field '", rf.name, "' of point ", i,
                          " is not a number: '", w, "'");
          cloud.fields[static_cast<std::size_t>(target[f])].values[i] = v;
        }
        t += static_cast<std::size_t>(rf.count);
      }
    }
  }
  return cloud;
}
}  // namespace

PcdCloud read_pcd(const std::string& path) { return read_pcd_impl(path, nullptr); }

bool read_pcd_packed(const std::string& path, PcdCloud& cloud, PcdPackedData& packed) {
  packed.layout.clear();  // packed.data keeps its memory: resizing to the same size costs nothing
  packed.stride = 0;
  cloud = read_pcd_impl(path, &packed);
  return !packed.layout.empty();  // filled for a binary file only
}

void write_pcd(const std::string& path, const PcdCloud& cloud) {
  const std::size_t n = cloud.points();
  std::size_t stride = 0;
  for (const auto& f : cloud.fields) {
    FMCW_CHECK_ARG(valid_type_size(f.type, f.size), "write_pcd: field '", f.name, "' has bad type/size");
    FMCW_CHECK_ARG(f.values.size() == n, "write_pcd: field '", f.name, "' has ", f.values.size(), " values, expected ", n);
    stride += static_cast<std::size_t>(f.size);
  }
  std::ostringstream h;
  h << "# .PCD v0.7 - Point Cloud Data file format\n";
  for (const auto& c : cloud.comments) h << "# " << c << "\n";
  h << "VERSION 0.7\nFIELDS";
  for (const auto& f : cloud.fields) h << ' ' << f.name;
  h << "\nSIZE";
  for (const auto& f : cloud.fields) h << ' ' << f.size;
  h << "\nTYPE";
  for (const auto& f : cloud.fields) h << ' ' << f.type;
  h << "\nCOUNT";
  for (std::size_t k = 0; k < cloud.fields.size(); ++k) h << " 1";
  h << "\nWIDTH " << cloud.width << "\nHEIGHT " << cloud.height << "\nVIEWPOINT 0 0 0 1 0 0 0\nPOINTS " << n
    << "\nDATA binary\n";
  std::vector<unsigned char> buf(n * stride);
  std::size_t offset = 0;
  for (const auto& f : cloud.fields) {
    for (std::size_t i = 0; i < n; ++i) encode(f.values[i], f.type, f.size, &buf[i * stride + offset]);
    offset += static_cast<std::size_t>(f.size);
  }
  const std::string header = h.str();
  write_file_atomically(path, [&](std::ostream& out) {
    out.write(header.data(), static_cast<std::streamsize>(header.size()));
    out.write(reinterpret_cast<const char*>(buf.data()), static_cast<std::streamsize>(buf.size()));
  });
}

void check_single_count(const PcdCloud& cloud, const std::vector<std::string>& names, const std::string& source,
                        const std::string& reader) {
  for (const auto& [name, count] : cloud.multi_count_fields) {
    if (std::find(names.begin(), names.end(), name) != names.end()) {
      throw core::FileError(concat(source, ": field '", name, "' has COUNT ", count, "; ", reader, " COUNT 1"));
    }
  }
}

double stamp_from_comments(const PcdCloud& cloud, const std::string& source) {
  double stamp_s = 0.0;
  for (const auto& c : cloud.comments) {
    const auto w = split_words(c);
    if (w.empty() || w[0] != "fmcw_stamp") continue;
    char* end = nullptr;
    stamp_s = w.size() == 2 ? std::strtod(w[1].c_str(), &end) : 0.0;
    // A NaN or Inf stamp would make every frame interval NaN and start tracking over quietly.
    if (end == nullptr || *end != '\0' || !std::isfinite(stamp_s)) {
      throw core::FileError(concat(source, ": comment '# ", c, "': the stamp must be a finite number of seconds"));
    }
  }
  return stamp_s;
}

core::VelocityFrame velocity_frame_from_comments(const PcdCloud& cloud, const std::string& source) {
  core::VelocityFrame frame = core::VelocityFrame::kSensor;
  for (const auto& c : cloud.comments) {
    const auto w = split_words(c);
    if (w.empty() || w[0] != "fmcw_velocity_frame") continue;
    FMCW_CHECK_FILE(w.size() == 2 && (w[1] == "sensor" || w[1] == "ego_compensated"), source, ": comment '# ", c,
                    "': expected fmcw_velocity_frame sensor or fmcw_velocity_frame ego_compensated");
    frame = core::velocity_frame_from_string(w[1]);
  }
  return frame;
}

namespace {
// line_index and time_offset_ns, as Aeva sensors report them; time_offset_ns fills the time
// offsets when the frame has no t.
void read_line_fields(const PcdCloud& cloud, const std::string& source, core::Scan& scan) {
  if (const PcdField* line = cloud.find("line_index")) {
    scan.line_index.resize(scan.size());
    for (std::size_t i = 0; i < scan.size(); ++i) {
      FMCW_CHECK_FILE(line->values[i] >= 0 && line->values[i] <= 65535.0, source, ": point ", i, " has line_index ",
                      line->values[i], " out of range (0..65535)");
      scan.line_index[i] = static_cast<std::uint16_t>(line->values[i]);
    }
  }
  const PcdField* ns = cloud.find("time_offset_ns");
  if (ns == nullptr || cloud.find("t") != nullptr) return;
  scan.time_offset_s.resize(scan.size());
  for (std::size_t i = 0; i < scan.size(); ++i) {
    FMCW_CHECK_FILE(std::isfinite(ns->values[i]), source, ": point ", i, " has a NaN or Inf time_offset_ns");
    scan.time_offset_s[i] = static_cast<float>(ns->values[i] * 1e-9);
  }
}
}  // namespace

const std::vector<std::string>& known_frame_fields() {
  static const std::vector<std::string> names = {"x", "y", "z", "range", "v", "intensity", "t", "line_index",
                                                 "time_offset_ns", "gt_range", "gt_v", "gt_vx", "gt_vy", "gt_vz",
                                                 "instance", "moving", "class", "label"};
  return names;
}

std::vector<core::HeadInfo> heads_from_comments(const PcdCloud& cloud, const std::string& source) {
  std::vector<core::HeadInfo> heads;
  for (const auto& c : cloud.comments) {
    const auto w = split_words(c);
    if (!w.empty() && w[0] == "fmcw_head") {
      FMCW_CHECK_FILE(w.size() == 12, source, ": comment '# ", c,
                      "': expected fmcw_head NAME COL_BEGIN COL_END STITCHED TX TY TZ QW QX QY QZ");
      core::HeadInfo head;
      head.name = w[1];
      head.col_begin = parse_int(w[2], source + ": fmcw_head col_begin");
      head.col_end = parse_int(w[3], source + ": fmcw_head col_end");
      head.stitched_to_next = w[4] == "1";
      double v[7];
      for (int k = 0; k < 7; ++k) {
        char* end = nullptr;
        v[k] = std::strtod(w[5 + static_cast<std::size_t>(k)].c_str(), &end);
        FMCW_CHECK_FILE(end && *end == '\0' && std::isfinite(v[k]), source, ": comment '# ", c, "': value ", k + 5,
                        " is not a finite number");
      }
      head.T_rig_head = Eigen::Isometry3d::Identity();
      head.T_rig_head.translation() = Eigen::Vector3d(v[0], v[1], v[2]);
      const Eigen::Quaterniond q(v[3], v[4], v[5], v[6]);
      FMCW_CHECK_FILE(std::abs(q.norm() - 1.0) < 1e-6, source, ": fmcw_head '", head.name, "' rotation is not a unit quaternion");
      head.T_rig_head.linear() = q.toRotationMatrix();
      heads.push_back(head);
    }
  }
  return heads;
}

core::Frame frame_from_pcd(const PcdCloud& cloud, const std::string& source) {
  for (const auto& f : cloud.fields) {
    const auto& known = known_frame_fields();
    if (std::find(known.begin(), known.end(), f.name) == known.end()) {
      std::string list;
      for (const auto& k : known) list += (list.empty() ? "" : " ") + k;
      throw core::FileError(concat(source, ": unknown field '", f.name, "' (known: ", list, ")"));
    }
  }
  check_single_count(cloud, known_frame_fields(), source, "a frame's fields must have");
  for (const char* required : {"x", "y", "z", "v"}) {
    FMCW_CHECK_FILE(cloud.find(required) != nullptr, source, ": missing field '", required,
                    "' (a frame needs at least x y z v)");
  }
  FMCW_CHECK_FILE(cloud.points() > 0, source, ": the cloud has no points (WIDTH ", cloud.width, ", HEIGHT ", cloud.height, ")");
  FMCW_CHECK_FILE(cloud.height > 1, source, ": the cloud is not organized (HEIGHT 1, WIDTH ", cloud.width,
                  "); Doppler region growing needs a range image: project it onto a grid first");

  core::Frame frame;
  core::Scan& scan = frame.scan;
  scan = core::Scan::make_empty(cloud.height, cloud.width);
  scan.heads.clear();
  scan.stamp_s = stamp_from_comments(cloud, source);
  scan.velocity_frame = velocity_frame_from_comments(cloud, source);
  scan.heads = heads_from_comments(cloud, source);
  if (scan.heads.empty()) {
    core::HeadInfo head;
    head.name = "sensor";
    head.col_end = cloud.width;
    scan.heads.push_back(head);
  }
  try {
    // Head spans must tile the columns; reuse the scan's own check on an all-invalid scan.
    scan.validate();
  } catch (const std::invalid_argument& e) {
    throw core::FileError(concat(source, ": ", e.what()));
  }
  const std::vector<double>& x = cloud.find("x")->values;
  const std::vector<double>& y = cloud.find("y")->values;
  const std::vector<double>& z = cloud.find("z")->values;
  const std::vector<double>& v = cloud.find("v")->values;
  const PcdField* range = cloud.find("range");
  const PcdField* intensity = cloud.find("intensity");
  if (const PcdField* t = cloud.find("t")) {
    scan.time_offset_s.resize(scan.size());
    for (std::size_t i = 0; i < scan.size(); ++i) {
      FMCW_CHECK_FILE(std::isfinite(t->values[i]), source, ": point ", i, " has a NaN or Inf time offset 't'");
      scan.time_offset_s[i] = static_cast<float>(t->values[i]);
    }
  }
  read_line_fields(cloud, source, scan);
  const char* gt_names[] = {"gt_range", "gt_v", "gt_vx", "gt_vy", "gt_vz", "instance", "moving"};
  int gt_present = 0;
  for (const char* g : gt_names) gt_present += cloud.find(g) ? 1 : 0;
  if (gt_present > 0 && gt_present < 7) {
    std::string missing;
    for (const char* g : gt_names) {
      if (!cloud.find(g)) missing += (missing.empty() ? "" : " ") + std::string(g);
    }
    throw core::FileError(concat(source, ": ground truth is incomplete, missing field(s): ", missing));
  }
  std::vector<Eigen::Vector3d> origin(static_cast<std::size_t>(scan.cols));
  for (const auto& head : scan.heads) {
    for (int c = head.col_begin; c < head.col_end; ++c) origin[static_cast<std::size_t>(c)] = head.origin_m();
  }
  for (int r = 0; r < scan.rows; ++r) {
    for (int c = 0; c < scan.cols; ++c) {
      const std::size_t i = scan.index(r, c);
      const bool any_nan = std::isnan(x[i]) || std::isnan(y[i]) || std::isnan(z[i]);
      if (any_nan) continue;  // no return
      const auto bad = [&](const char* field) {
        return core::FileError(concat(source, ": point (row ", r, ", col ", c, ") has finite x y z but a NaN or Inf '",
                                      field, "'"));
      };
      if (!std::isfinite(x[i]) || !std::isfinite(y[i]) || !std::isfinite(z[i])) {
        throw core::FileError(concat(source, ": point (row ", r, ", col ", c, ") has an infinite coordinate"));
      }
      if (!std::isfinite(v[i])) throw bad("v");
      scan.x_m[i] = static_cast<float>(x[i]);
      scan.y_m[i] = static_cast<float>(y[i]);
      scan.z_m[i] = static_cast<float>(z[i]);
      scan.radial_velocity_mps[i] = static_cast<float>(v[i]);
      if (range) {
        if (!std::isfinite(range->values[i])) throw bad("range");
        scan.range_m[i] = static_cast<float>(range->values[i]);
      } else {
        scan.range_m[i] = static_cast<float>((Eigen::Vector3d(x[i], y[i], z[i]) - origin[static_cast<std::size_t>(c)]).norm());
      }
      if (intensity) {
        if (!std::isfinite(intensity->values[i])) throw bad("intensity");
        scan.intensity[i] = static_cast<float>(intensity->values[i]);
      }
      FMCW_CHECK_FILE(scan.range_m[i] > 0.0f, source, ": point (row ", r, ", col ", c, ") has range ", scan.range_m[i],
                      " <= 0");
      scan.valid[i] = 1;
    }
  }
  if (gt_present == 7) {
    core::PixelGroundTruth gt = core::PixelGroundTruth::make_empty(scan.size());
    const auto copy_f = [&](const char* name, std::vector<float>& dst) {
      const auto& src = cloud.find(name)->values;
      for (std::size_t i = 0; i < dst.size(); ++i) dst[i] = static_cast<float>(src[i]);
    };
    copy_f("gt_range", gt.range_m);
    copy_f("gt_v", gt.radial_velocity_mps);
    copy_f("gt_vx", gt.vx_mps);
    copy_f("gt_vy", gt.vy_mps);
    copy_f("gt_vz", gt.vz_mps);
    const auto& inst = cloud.find("instance")->values;
    const auto& mov = cloud.find("moving")->values;
    for (std::size_t i = 0; i < scan.size(); ++i) {
      FMCW_CHECK_FILE(inst[i] >= 0 && inst[i] <= 4294967295.0 && mov[i] >= 0 && mov[i] <= 1, source, ": point ", i,
                      " has instance ", inst[i], " / moving ", mov[i], " out of range");
      gt.instance[i] = static_cast<std::uint32_t>(inst[i]);
      gt.moving[i] = static_cast<std::uint8_t>(mov[i]);
    }
    // The semantic class: datasets written before it have none.
    if (const PcdField* cls = cloud.find("class")) {
      for (std::size_t i = 0; i < scan.size(); ++i) {
        FMCW_CHECK_FILE(cls->values[i] >= 0 && cls->values[i] <= 65535.0, source, ": point ", i, " has class ", cls->values[i],
                        " out of range (0..65535)");
        gt.semantic_class[i] = static_cast<std::uint16_t>(cls->values[i]);
      }
    } else {
      gt.semantic_class.clear();
    }
    frame.truth = std::move(gt);
  }
  return frame;
}

PcdCloud pcd_from_frame(const core::Frame& frame, bool with_truth) {
  const core::Scan& scan = frame.scan;
  scan.validate();
  PcdCloud cloud;
  cloud.width = scan.cols;
  cloud.height = scan.rows;
  cloud.comments.push_back("fmcw_stamp " + fmt_double(scan.stamp_s));
  // Only a compensated scan says so: sensor-frame files keep the bytes they always had.
  if (scan.velocity_frame != core::VelocityFrame::kSensor) {
    cloud.comments.push_back(std::string("fmcw_velocity_frame ") + core::to_string(scan.velocity_frame));
  }
  for (const auto& head : scan.heads) {
    FMCW_CHECK_ARG(!head.name.empty() && head.name.find_first_of(" \t\r\n") == std::string::npos,
                   "write PCD: head name '", head.name, "' must be one word");
    const Eigen::Quaterniond q(head.T_rig_head.linear());
    const Eigen::Vector3d t = head.T_rig_head.translation();
    cloud.comments.push_back(concat("fmcw_head ", head.name, " ", head.col_begin, " ", head.col_end, " ",
                                    head.stitched_to_next ? 1 : 0, " ", fmt_double(t.x()), " ", fmt_double(t.y()), " ",
                                    fmt_double(t.z()), " ", fmt_double(q.w()), " ", fmt_double(q.x()), " ",
                                    fmt_double(q.y()), " ", fmt_double(q.z())));
  }
  const std::size_t n = scan.size();
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const auto add_float = [&](const char* name, const std::vector<float>& src, bool mask_invalid) {
    PcdField f{name, 'F', 4, std::vector<double>(n)};
    for (std::size_t i = 0; i < n; ++i) f.values[i] = (mask_invalid && !scan.valid[i]) ? nan : src[i];
    cloud.fields.push_back(std::move(f));
  };
  add_float("x", scan.x_m, true);
  add_float("y", scan.y_m, true);
  add_float("z", scan.z_m, true);
  add_float("range", scan.range_m, true);
  add_float("v", scan.radial_velocity_mps, true);
  add_float("intensity", scan.intensity, true);
  if (!scan.time_offset_s.empty()) add_float("t", scan.time_offset_s, false);
  if (!scan.line_index.empty()) {
    // As the Aeva sensors report them: the scan line and the time after the stamp [ns].
    PcdField line{"line_index", 'U', 2, std::vector<double>(n)};
    PcdField ns{"time_offset_ns", 'I', 4, std::vector<double>(n, 0.0)};
    for (std::size_t i = 0; i < n; ++i) {
      line.values[i] = scan.line_index[i];
      if (!scan.time_offset_s.empty()) ns.values[i] = std::round(static_cast<double>(scan.time_offset_s[i]) * 1e9);
    }
    cloud.fields.push_back(std::move(line));
    cloud.fields.push_back(std::move(ns));
  }
  if (with_truth) {
    FMCW_CHECK_ARG(frame.truth.has_value(), "write PCD: ground truth requested but the frame has none");
    const core::PixelGroundTruth& gt = *frame.truth;
    gt.validate(n);
    add_float("gt_range", gt.range_m, false);
    add_float("gt_v", gt.radial_velocity_mps, false);
    add_float("gt_vx", gt.vx_mps, false);
    add_float("gt_vy", gt.vy_mps, false);
    add_float("gt_vz", gt.vz_mps, false);
    PcdField inst{"instance", 'U', 4, std::vector<double>(n)};
    PcdField mov{"moving", 'U', 1, std::vector<double>(n)};
    for (std::size_t i = 0; i < n; ++i) {
      inst.values[i] = gt.instance[i];
      mov.values[i] = gt.moving[i];
    }
    cloud.fields.push_back(std::move(inst));
    cloud.fields.push_back(std::move(mov));
    if (!gt.semantic_class.empty()) {
      PcdField cls{"class", 'U', 2, std::vector<double>(n)};
      for (std::size_t i = 0; i < n; ++i) cls.values[i] = gt.semantic_class[i];
      cloud.fields.push_back(std::move(cls));
    }
  }
  return cloud;
}

core::Frame read_frame(const std::string& path) { return frame_from_pcd(read_pcd(path), path); }

void write_frame(const std::string& path, const core::Frame& frame, bool with_truth) {
  write_pcd(path, pcd_from_frame(frame, with_truth && frame.truth.has_value()));
}

}  // namespace fmcw::io
