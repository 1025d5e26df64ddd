// Files: organized PCD frames, Aeva Aeries II scans.

#include <pybind11/stl.h>

#include "bindings.hpp"
#include "fmcw/core/grid_projection.hpp"
#include "fmcw/io/aeva.hpp"
#include "fmcw/io/pcd.hpp"
#include "numpy_arrays.hpp"

namespace fmcw::python {

namespace {
template <typename T>
py::array_t<T> to_column(const std::vector<T>& v) {
  py::array_t<T> out(static_cast<py::ssize_t>(v.size()));
  std::copy(v.begin(), v.end(), out.mutable_data());
  return out;
}
}  // namespace

void bind_io(py::module_& m) {
  m.def("read_frame", &io::read_frame, py::arg("path"),
        "Reads an organized PCD frame (with its ground truth when the file has it). ValueError naming the file "
        "and line or pixel for a malformed file.");
  m.def(
      "write_frame",
      [](const std::string& path, const py::object& frame_or_scan) {
        core::Frame frame;
        if (py::isinstance<core::Frame>(frame_or_scan)) {
          frame = frame_or_scan.cast<core::Frame>();
        } else {
          frame.scan = frame_or_scan.cast<core::Scan>();
        }
        io::write_frame(path, frame, frame.truth.has_value());
      },
      py::arg("path"), py::arg("frame"), "Writes a Frame (with its truth) or a Scan as binary organized PCD.");
  m.def(
      "read_aeva",
      [](const std::string& path, const std::string& layout) {
        const io::AevaRecords r = io::read_aeva(path, io::parse_aeva_layout(layout));
        py::dict d;
        d["x"] = to_column(r.x_m);
        d["y"] = to_column(r.y_m);
        d["z"] = to_column(r.z_m);
        d["reflectivity"] = to_column(r.reflectivity);
        d["velocity"] = to_column(r.velocity_mps);
        d["time_offset_ns"] = to_column(r.time_offset_ns);
        d["line_index"] = to_column(r.line_index);
        if (r.has_intensity()) d["intensity"] = to_column(r.intensity);
        return d;
      },
      py::arg("path"), py::arg("layout") = "auto",
      "The records of an Aeva Aeries II .bin scan as 1-D arrays (intensity only for 29-byte records). layout: "
      "auto, 25 or 29.");
  m.def(
      "read_aeva_scan",
      [](const std::string& path, const std::string& layout, double fov_h, double res_h, int lines,
         bool negate_velocity) {
        io::AevaScanParams p;
        p.layout = io::parse_aeva_layout(layout);
        p.grid.fov_horizontal_deg = fov_h;
        p.grid.resolution_horizontal_deg = res_h;
        p.grid.lines = lines;
        p.negate_velocity = negate_velocity;
        return projection_to_dict(io::read_aeva_scan(path, p));
      },
      py::arg("path"), py::kw_only(), py::arg("layout") = "auto", py::arg("fov_h") = 120.0, py::arg("res_h") = 0.2,
      py::arg("lines") = 0, py::arg("negate_velocity") = false,
      "An Aeva scan organized into a Scan: row = line index, column = azimuth bin of res_h degrees over fov_h. "
      "Returns the dict of project_points.");
}

}  // namespace fmcw::python
