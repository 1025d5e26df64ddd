#include "fmcw/io/ros2_messages.hpp"

#include <cmath>

#include "fmcw/core/check.hpp"
#include "fmcw/io/cdr.hpp"
#include "pcd_values.hpp"

namespace fmcw::io::ros2 {

using core::concat;

namespace {

// The ros2msg text of the types below: field lists and constants of the ROS 2 (Humble and
// later) definitions, without their comments.
const char* const kSeparator = "================================================================================\n";

std::string with_dependencies(const std::string& top, const std::vector<std::pair<const char*, const char*>>& deps) {
  std::string text = top;
  for (const auto& [name, body] : deps) text += std::string(kSeparator) + "MSG: " + name + "\n" + body;
  return text;
}

const char* const kHeader = "builtin_interfaces/Time stamp\nstring frame_id\n";
const char* const kTime = "int32 sec\nuint32 nanosec\n";
const char* const kVector3 = "float64 x\nfloat64 y\nfloat64 z\n";
const char* const kPoint = "float64 x\nfloat64 y\nfloat64 z\n";
const char* const kQuaternion = "float64 x 0\nfloat64 y 0\nfloat64 z 0\nfloat64 w 1\n";

void put_time(CdrWriter& w, Time t) {
  w.i32(t.sec);
  w.u32(t.nanosec);
}

void put_header(CdrWriter& w, Time t, const std::string& frame_id) {
  put_time(w, t);
  w.string(frame_id);
}

void put_vector(CdrWriter& w, const Eigen::Vector3d& v) {
  w.f64(v.x());
  w.f64(v.y());
  w.f64(v.z());
}

void put_pose(CdrWriter& w, const Eigen::Isometry3d& T) {
  put_vector(w, T.translation());
  const Eigen::Quaterniond q(T.linear());
  w.f64(q.x());
  w.f64(q.y());
  w.f64(q.z());
  w.f64(q.w());
}

// PCD (type, size) <-> PointField datatype.
std::uint8_t datatype_of(const std::string& name, char type, int size) {
  const int t = type == 'F' ? 0 : (type == 'U' ? 1 : 2);
  if (t == 0 && size == 4) return kFloat32;
  if (t == 0 && size == 8) return kFloat64;
  switch (size * 10 + t) {
    case 11: return kUint8;
    case 12: return kInt8;
    case 21: return kUint16;
    case 22: return kInt16;
    case 41: return kUint32;
    case 42: return kInt32;
    default: break;
  }
  throw core::InputError(concat("PointCloud2: field '", name, "' of PCD TYPE ", type, " SIZE ", size,
                                " has no PointField datatype (8-byte integers have none)"));
}

bool pcd_type_of(std::uint8_t datatype, char& type, int& size) {
  static const char types[] = {'I', 'U', 'I', 'U', 'I', 'U', 'F', 'F'};
  static const int sizes[] = {1, 1, 2, 2, 4, 4, 4, 8};
  if (datatype < 1 || datatype > 8) return false;
  type = types[datatype - 1];
  size = sizes[datatype - 1];
  return true;
}

}  // namespace

Time Time::from_seconds(double stamp_s) {
  FMCW_CHECK_ARG(std::isfinite(stamp_s) && stamp_s >= 0.0 && stamp_s < 2147483647.0, "ROS time: stamp ", stamp_s,
                 " s is not a finite time in [0, 2^31) s");
  const auto ns = static_cast<std::uint64_t>(std::llround(stamp_s * 1e9));
  Time t;
  t.sec = static_cast<std::int32_t>(ns / 1000000000ull);
  t.nanosec = static_cast<std::uint32_t>(ns % 1000000000ull);
  return t;
}

const std::string& point_cloud2_definition() {
  static const std::string text = with_dependencies(
      "std_msgs/Header header\nuint32 height\nuint32 width\nPointField[] fields\nbool is_bigendian\n"
      "uint32 point_step\nuint32 row_step\nuint8[] data\nbool is_dense\n",
      {{"std_msgs/Header", kHeader},
       {"builtin_interfaces/Time", kTime},
       {"sensor_msgs/PointField",
        "uint8 INT8    = 1\nuint8 UINT8   = 2\nuint8 INT16   = 3\nuint8 UINT16  = 4\nuint8 INT32   = 5\n"
        "uint8 UINT32  = 6\nuint8 FLOAT32 = 7\nuint8 FLOAT64 = 8\nstring name\nuint32 offset\nuint8 datatype\n"
        "uint32 count\n"}});
  return text;
}

const std::string& tf_message_definition() {
  static const std::string text = with_dependencies(
      "geometry_msgs/TransformStamped[] transforms\n",
      {{"geometry_msgs/TransformStamped", "std_msgs/Header header\nstring child_frame_id\nTransform transform\n"},
       {"std_msgs/Header", kHeader},
       {"builtin_interfaces/Time", kTime},
       {"geometry_msgs/Transform", "Vector3 translation\nQuaternion rotation\n"},
       {"geometry_msgs/Vector3", kVector3},
       {"geometry_msgs/Quaternion", kQuaternion}});
  return text;
}

const std::string& marker_array_definition() {
  static const std::string text = with_dependencies(
      "Marker[] markers\n",
      {{"visualization_msgs/Marker",
        "int32 ARROW=0\nint32 CUBE=1\nint32 SPHERE=2\nint32 CYLINDER=3\nint32 LINE_STRIP=4\nint32 LINE_LIST=5\n"
        "int32 CUBE_LIST=6\nint32 SPHERE_LIST=7\nint32 POINTS=8\nint32 TEXT_VIEW_FACING=9\nint32 MESH_RESOURCE=10\n"
        "int32 TRIANGLE_LIST=11\nint32 ADD=0\nint32 MODIFY=0\nint32 DELETE=2\nint32 DELETEALL=3\n"
        "std_msgs/Header header\nstring ns\nint32 id\nint32 type\nint32 action\ngeometry_msgs/Pose pose\n"
        "geometry_msgs/Vector3 scale\nstd_msgs/ColorRGBA color\nbuiltin_interfaces/Duration lifetime\n"
        "bool frame_locked\ngeometry_msgs/Point[] points\nstd_msgs/ColorRGBA[] colors\nstring texture_resource\n"
        "sensor_msgs/CompressedImage texture\nUVCoordinate[] uv_coordinates\nstring text\nstring mesh_resource\n"
        "MeshFile mesh_file\nbool mesh_use_embedded_materials\n"},
       {"std_msgs/Header", kHeader},
       {"builtin_interfaces/Time", kTime},
       {"geometry_msgs/Pose", "Point position\nQuaternion orientation\n"},
       {"geometry_msgs/Point", kPoint},
       {"geometry_msgs/Quaternion", kQuaternion},
       {"geometry_msgs/Vector3", kVector3},
       {"std_msgs/ColorRGBA", "float32 r\nfloat32 g\nfloat32 b\nfloat32 a\n"},
       {"builtin_interfaces/Duration", kTime},
       {"sensor_msgs/CompressedImage", "std_msgs/Header header\nstring format\nuint8[] data\n"},
       {"visualization_msgs/UVCoordinate", "float32 u\nfloat32 v\n"},
       {"visualization_msgs/MeshFile", "string filename\nuint8[] data\n"}});
  return text;
}

std::vector<std::uint8_t> encode(const PointCloud2& c) {
  std::vector<std::uint8_t> out;
  encode(c, out);
  return out;
}

void encode(const PointCloud2& c, std::vector<std::uint8_t>& out) {
  CdrWriter w(out);
  w.reserve(c.data.size() + 64 + 32 * c.fields.size() + c.frame_id.size());
  put_header(w, c.stamp, c.frame_id);
  w.u32(c.height);
  w.u32(c.width);
  w.count(c.fields.size());
  for (const PointField& f : c.fields) {
    w.string(f.name);
    w.u32(f.offset);
    w.u8(f.datatype);
    w.u32(f.count);
  }
  w.boolean(c.is_bigendian);
  w.u32(c.point_step);
  w.u32(c.row_step);
  w.bytes(c.data.data(), c.data.size());
  w.boolean(c.is_dense);
}

PointCloud2 decode_point_cloud2(const std::uint8_t* data, std::size_t size, const std::string& where) {
  CdrReader r(data, size, where);
  PointCloud2 c;
  c.stamp.sec = r.i32();
  c.stamp.nanosec = r.u32();
  c.frame_id = r.string("header.frame_id");
  c.height = r.u32();
  c.width = r.u32();
  const std::size_t n = r.count("fields", 17);  // a field takes at least 17 bytes
  c.fields.resize(n);
  for (PointField& f : c.fields) {
    f.name = r.string("fields[].name");
    f.offset = r.u32();
    f.datatype = r.u8();
    f.count = r.u32();
  }
  c.is_bigendian = r.boolean();
  c.point_step = r.u32();
  c.row_step = r.u32();
  std::size_t bytes = 0;
  const std::uint8_t* p = r.bytes("data", bytes);
  c.data.assign(p, p + bytes);
  c.is_dense = r.boolean();
  return c;
}

PointCloud2 point_cloud2_from_pcd(const PcdCloud& cloud, Time stamp, const std::string& frame_id) {
  PointCloud2 c;
  c.stamp = stamp;
  c.frame_id = frame_id;
  FMCW_CHECK_ARG(cloud.width >= 0 && cloud.height >= 0, "PointCloud2: negative WIDTH or HEIGHT");
  c.width = static_cast<std::uint32_t>(cloud.width);
  c.height = static_cast<std::uint32_t>(cloud.height);
  std::size_t step = 0;
  for (const PcdField& f : cloud.fields) {
    c.fields.push_back({f.name, static_cast<std::uint32_t>(step), datatype_of(f.name, f.type, f.size), 1});
    step += static_cast<std::size_t>(f.size);
  }
  const std::size_t n = cloud.points();
  FMCW_CHECK_LIMIT(step * cloud.width <= 0xffffffffu, "PointCloud2: a row of ", cloud.width, " points of ", step,
                   " bytes exceeds uint32 row_step");
  c.point_step = static_cast<std::uint32_t>(step);
  c.row_step = static_cast<std::uint32_t>(step * cloud.width);
  c.data.resize(n * step);
  std::size_t offset = 0;
  for (const PcdField& f : cloud.fields) {
    FMCW_CHECK_ARG(f.values.size() == n, "PointCloud2: field '", f.name, "' has ", f.values.size(), " values, expected ", n);
    std::uint8_t* out = c.data.data() + offset;
    for (std::size_t i = 0; i < n; ++i, out += step) detail::encode(f.values[i], f.type, f.size, out);
    offset += static_cast<std::size_t>(f.size);
  }
  c.is_dense = false;
  return c;
}

PointCloud2 point_cloud2_from_packed(const PcdCloud& cloud, PcdPackedData&& packed, Time stamp,
                                     const std::string& frame_id) {
  PointCloud2 c;
  c.stamp = stamp;
  c.frame_id = frame_id;
  c.width = static_cast<std::uint32_t>(cloud.width);
  c.height = static_cast<std::uint32_t>(cloud.height);
  for (const PcdPackedData::Field& f : packed.layout) {
    if (f.name == "_") continue;  // PCD padding: bytes in the point, no field
    c.fields.push_back({f.name, static_cast<std::uint32_t>(f.offset), datatype_of(f.name, f.type, f.size),
                        static_cast<std::uint32_t>(f.count)});
  }
  FMCW_CHECK_LIMIT(packed.stride * c.width <= 0xffffffffu, "PointCloud2: a row of ", c.width, " points of ",
                   packed.stride, " bytes exceeds uint32 row_step");
  FMCW_CHECK_ARG(packed.data.size() == packed.stride * cloud.points(), "PointCloud2: packed data of ",
                 packed.data.size(), " bytes for ", cloud.points(), " points of ", packed.stride);
  c.point_step = static_cast<std::uint32_t>(packed.stride);
  c.row_step = static_cast<std::uint32_t>(packed.stride * c.width);
  c.data = std::move(packed.data);
  return c;
}

PcdCloud pcd_from_point_cloud2(const PointCloud2& c, const std::string& where) {
  FMCW_CHECK_FILE(!c.is_bigendian, where, ": a big-endian PointCloud2 is not supported");
  const std::uint64_t n = static_cast<std::uint64_t>(c.width) * c.height;
  FMCW_CHECK_LIMIT(n <= (1ull << 31), where, ": ", c.width, " x ", c.height, " points are more than 2^31");
  FMCW_CHECK_FILE(c.width <= 0x7fffffffu && c.height <= 0x7fffffffu, where, ": width ", c.width, " or height ", c.height,
                  " too large");
  FMCW_CHECK_FILE(static_cast<std::uint64_t>(c.point_step) * c.width <= c.row_step, where, ": row_step ", c.row_step,
                  " is shorter than width ", c.width, " x point_step ", c.point_step);
  FMCW_CHECK_FILE(static_cast<std::uint64_t>(c.row_step) * c.height == c.data.size(), where, ": data holds ",
                  c.data.size(), " bytes, row_step x height is ",
                  static_cast<std::uint64_t>(c.row_step) * c.height);
  PcdCloud cloud;
  cloud.width = static_cast<int>(c.width);
  cloud.height = static_cast<int>(c.height);
  for (const PointField& f : c.fields) {
    char type = 'F';
    int size = 4;
    FMCW_CHECK_FILE(pcd_type_of(f.datatype, type, size), where, ": field '", f.name, "' has datatype ",
                    int(f.datatype), " (PointField knows 1..8)");
    if (f.count != 1) {
      cloud.multi_count_fields.emplace_back(f.name, static_cast<int>(std::min<std::uint32_t>(f.count, 1u << 30)));
      continue;
    }
    FMCW_CHECK_FILE(static_cast<std::uint64_t>(f.offset) + static_cast<std::uint64_t>(size) <= c.point_step, where,
                    ": field '", f.name, "' at offset ", f.offset, " does not fit point_step ", c.point_step);
    FMCW_CHECK_FILE(cloud.find(f.name) == nullptr, where, ": field '", f.name, "' appears twice");
    PcdField out{f.name, type, size, std::vector<double>(static_cast<std::size_t>(n))};
    std::size_t i = 0;
    for (std::uint32_t row = 0; row < c.height; ++row) {
      const std::uint8_t* p = c.data.data() + static_cast<std::size_t>(row) * c.row_step + f.offset;
      for (std::uint32_t col = 0; col < c.width; ++col, p += c.point_step) out.values[i++] = detail::decode(p, type, size);
    }
    cloud.fields.push_back(std::move(out));
  }
  return cloud;
}

std::vector<std::uint8_t> encode_tf(const std::vector<TransformStamped>& transforms) {
  CdrWriter w;
  w.count(transforms.size());
  for (const TransformStamped& t : transforms) {
    put_header(w, t.stamp, t.parent_frame);
    w.string(t.child_frame);
    put_pose(w, t.T_parent_child);  // Transform: Vector3 translation, Quaternion rotation
  }
  return w.take();
}

std::vector<std::uint8_t> encode_markers(const std::vector<Marker>& markers, Time stamp, const std::string& frame_id) {
  CdrWriter w;
  w.count(markers.size());
  for (const Marker& m : markers) {
    put_header(w, stamp, frame_id);
    w.string(m.ns);
    w.i32(m.id);
    w.i32(m.type);
    w.i32(m.action);
    put_pose(w, m.pose);
    put_vector(w, m.scale);
    for (float c : m.rgba) w.f32(c);
    put_time(w, Time{});  // lifetime 0: until the next frame's DELETEALL
    w.boolean(false);     // frame_locked
    w.count(m.points.size());
    for (const Eigen::Vector3d& p : m.points) put_vector(w, p);
    w.count(0);       // colors
    w.string("");     // texture_resource
    put_header(w, Time{}, "");  // texture: sensor_msgs/CompressedImage header
    w.string("");     // texture.format
    w.count(0);       // texture.data
    w.count(0);       // uv_coordinates
    w.string(m.text);
    w.string("");     // mesh_resource
    w.string("");     // mesh_file.filename
    w.count(0);       // mesh_file.data
    w.boolean(false); // mesh_use_embedded_materials
  }
  return w.take();
}

}  // namespace fmcw::io::ros2
