// fmcw.Head, fmcw.Scan (from and to numpy arrays of shape (rows, cols)), fmcw.project_points.

#include <pybind11/stl.h>

#include <cmath>

#include "bindings.hpp"
#include "fmcw/core/grid_projection.hpp"
#include "fmcw/core/scan.hpp"
#include "numpy_arrays.hpp"

namespace fmcw::python {

namespace {
core::HeadInfo make_head(const std::string& name, int col_begin, int col_end, const py::object& T_rig_head,
                         bool stitched_to_next) {
  core::HeadInfo h;
  h.name = name;
  h.col_begin = col_begin;
  h.col_end = col_end;
  if (!T_rig_head.is_none()) h.T_rig_head = to_isometry(T_rig_head, "T_rig_head");
  h.stitched_to_next = stitched_to_next;
  return h;
}

// Scan from arrays of shape (rows, cols). valid defaults to finite x, y, z; range to the
// distance from each pixel's head origin; intensity to 0; one head at the origin by default.
core::Scan make_scan(const py::handle& x, const py::handle& y, const py::handle& z, const py::handle& v,
                     const py::object& range, const py::object& intensity, const py::object& valid,
                     const py::object& time_offset, const py::object& heads, double stamp) {
  core::Scan s;
  int rows = -1, cols = -1;
  s.x_m = from_image<float>(x, rows, cols, "x");
  s.y_m = from_image<float>(y, rows, cols, "y");
  s.z_m = from_image<float>(z, rows, cols, "z");
  s.radial_velocity_mps = from_image<float>(v, rows, cols, "v");
  s.rows = rows;
  s.cols = cols;
  s.stamp_s = stamp;
  const std::size_t n = s.size();
  if (heads.is_none()) {
    s.heads = core::Scan::make_empty(0, cols).heads;
  } else {
    s.heads = heads.cast<std::vector<core::HeadInfo>>();
  }
  if (valid.is_none()) {
    s.valid.resize(n);
    for (std::size_t i = 0; i < n; ++i) {
      s.valid[i] = std::isfinite(s.x_m[i]) && std::isfinite(s.y_m[i]) && std::isfinite(s.z_m[i]) ? 1 : 0;
    }
  } else {
    s.valid = from_image<std::uint8_t>(valid, rows, cols, "valid");
  }
  s.intensity = intensity.is_none() ? std::vector<float>(n, 0.0f) : from_image<float>(intensity, rows, cols, "intensity");
  if (!time_offset.is_none()) s.time_offset_s = from_image<float>(time_offset, rows, cols, "time_offset");
  if (range.is_none()) {
    s.range_m.assign(n, std::nanf(""));
    s.validate_layout();  // the heads, before their origins are looked up
    for (std::size_t i = 0; i < n; ++i) {
      if (s.valid[i]) s.range_m[i] = static_cast<float>((s.position(i) - s.beam_origin(i)).norm());
    }
  } else {
    s.range_m = from_image<float>(range, rows, cols, "range");
  }
  s.validate();
  return s;
}

}  // namespace

py::dict projection_to_dict(core::GridProjection&& p) {
  py::dict d;
  d["placed"] = p.stats.placed;
  d["collisions"] = p.stats.collisions;
  d["outside_fov"] = p.stats.outside_fov;
  d["points"] = p.stats.points;
  d["rows_by_line"] = p.stats.rows_by_line;
  d["point_of_pixel"] = to_image(p.point_of_pixel, p.scan.rows, p.scan.cols);
  py::array_t<std::int64_t> pixel_of_point(static_cast<py::ssize_t>(p.pixel_of_point.size()));
  std::copy(p.pixel_of_point.begin(), p.pixel_of_point.end(), pixel_of_point.mutable_data());
  d["pixel_of_point"] = pixel_of_point;
  d["scan"] = std::move(p.scan);
  return d;
}

void bind_scan(py::module_& m) {
  py::class_<core::HeadInfo>(m, "Head", "One sensor head: its mount pose and the image columns it owns.")
      .def(py::init(&make_head), py::arg("name"), py::arg("col_begin"), py::arg("col_end"),
           py::arg("T_rig_head") = py::none(), py::arg("stitched_to_next") = false)
      .def_readwrite("name", &core::HeadInfo::name)
      .def_readwrite("col_begin", &core::HeadInfo::col_begin)
      .def_readwrite("col_end", &core::HeadInfo::col_end)
      .def_readwrite("stitched_to_next", &core::HeadInfo::stitched_to_next)
      .def_property(
          "T_rig_head", [](const core::HeadInfo& h) { return to_array(h.T_rig_head); },
          [](core::HeadInfo& h, const py::object& T) { h.T_rig_head = to_isometry(T, "T_rig_head"); },
          "mount pose, head -> rig, as a 4x4 matrix")
      .def_property_readonly("origin", [](const core::HeadInfo& h) { return to_array(h.origin_m()); })
      .def("__repr__", [](const core::HeadInfo& h) {
        return "fmcw.Head('" + h.name + "', cols " + std::to_string(h.col_begin) + ".." + std::to_string(h.col_end) + ")";
      });

  py::class_<core::Scan>(m, "Scan",
                         "Organized FMCW scan, rig frame (x forward, y left, z up). Arrays have shape (rows, cols); "
                         "v > 0 moves away. Properties return copies.")
      .def(py::init(&make_scan), py::arg("x"), py::arg("y"), py::arg("z"), py::arg("v"), py::kw_only(),
           py::arg("range") = py::none(), py::arg("intensity") = py::none(), py::arg("valid") = py::none(),
           py::arg("time_offset") = py::none(), py::arg("heads") = py::none(), py::arg("stamp") = 0.0,
           "Builds and validates a scan. valid defaults to finite x, y, z; range to the distance from the "
           "pixel's head origin; intensity to 0; heads to one head at the origin over every column.")
      .def_readonly("rows", &core::Scan::rows)
      .def_readonly("cols", &core::Scan::cols)
      .def_property_readonly("shape", [](const core::Scan& s) { return py::make_tuple(s.rows, s.cols); })
      .def_property(
          "stamp", [](const core::Scan& s) { return s.stamp_s; },
          [](core::Scan& s, double stamp_s) {
            const double before = s.stamp_s;
            s.stamp_s = stamp_s;
            try {
              s.validate_layout();  // names a stamp that is not finite
            } catch (...) {
              s.stamp_s = before;
              throw;
            }
          },
          "the scan's time [s]; finite")
      .def_property_readonly("x", [](const core::Scan& s) { return to_image(s.x_m, s.rows, s.cols); })
      .def_property_readonly("y", [](const core::Scan& s) { return to_image(s.y_m, s.rows, s.cols); })
      .def_property_readonly("z", [](const core::Scan& s) { return to_image(s.z_m, s.rows, s.cols); })
      .def_property_readonly("range", [](const core::Scan& s) { return to_image(s.range_m, s.rows, s.cols); })
      .def_property_readonly("v", [](const core::Scan& s) { return to_image(s.radial_velocity_mps, s.rows, s.cols); })
      .def_property_readonly("intensity", [](const core::Scan& s) { return to_image(s.intensity, s.rows, s.cols); })
      .def_property_readonly("valid", [](const core::Scan& s) { return to_image<std::uint8_t, bool>(s.valid, s.rows, s.cols); })
      .def_property_readonly("time_offset",
                             [](const core::Scan& s) -> py::object {
                               if (s.time_offset_s.empty()) return py::none();
                               return to_image(s.time_offset_s, s.rows, s.cols);
                             })
      .def_readonly("heads", &core::Scan::heads)
      .def_property_readonly("num_valid", &core::Scan::num_valid)
      .def("validate", &core::Scan::validate, "Raises ValueError naming the field or pixel at fault.")
      .def("__repr__", [](const core::Scan& s) {
        return "fmcw.Scan(" + std::to_string(s.rows) + " x " + std::to_string(s.cols) + ", " +
               std::to_string(s.num_valid()) + " valid, " + std::to_string(s.heads.size()) + " head(s))";
      });

  m.def(
      "project_points",
      [](const py::handle& x, const py::handle& y, const py::handle& z, const py::handle& v, const py::object& intensity,
         const py::object& time_offset, const py::object& line_index, double fov_h, double res_h, double fov_v,
         double res_v, int lines) {
        core::PointList p;
        p.x_m = from_vector<float>(x, -1, "x");
        const auto n = static_cast<py::ssize_t>(p.x_m.size());
        p.y_m = from_vector<float>(y, n, "y");
        p.z_m = from_vector<float>(z, n, "z");
        p.radial_velocity_mps = from_vector<float>(v, n, "v");
        if (!intensity.is_none()) p.intensity = from_vector<float>(intensity, n, "intensity");
        if (!time_offset.is_none()) p.time_offset_s = from_vector<float>(time_offset, n, "time_offset");
        if (!line_index.is_none()) p.line_index = from_vector<std::int32_t>(line_index, n, "line_index");
        core::GridProjectionParams g;
        g.fov_horizontal_deg = fov_h;
        g.resolution_horizontal_deg = res_h;
        g.fov_vertical_deg = fov_v;
        g.resolution_vertical_deg = res_v;
        g.lines = lines;
        return projection_to_dict(core::project_to_grid(p, g));
      },
      py::arg("x"), py::arg("y"), py::arg("z"), py::arg("v"), py::kw_only(), py::arg("intensity") = py::none(),
      py::arg("time_offset") = py::none(), py::arg("line_index") = py::none(), py::arg("fov_h") = 120.0,
      py::arg("res_h") = 0.2, py::arg("fov_v") = 30.0, py::arg("res_v") = 0.2, py::arg("lines") = 0,
      "Unorganized points (1-D arrays, sensor frame) onto a grid: columns by azimuth (res_h degrees over fov_h), "
      "rows by line_index when given, else by elevation (res_v over fov_v). The nearest return wins a pixel. "
      "Returns a dict: scan, placed, collisions, outside_fov, points, rows_by_line, point_of_pixel (rows, cols), "
      "pixel_of_point (n,).");
}

}  // namespace fmcw::python
