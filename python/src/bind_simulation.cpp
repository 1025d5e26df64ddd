// fmcw.Frame (scan + ground truth as arrays and dicts) and fmcw.Scenario (a scenario YAML
// simulated frame by frame).

#include <pybind11/stl.h>

#include "bindings.hpp"
#include "fmcw/core/ground_truth.hpp"
#include "fmcw/eval/scenario_source.hpp"
#include "numpy_arrays.hpp"

namespace fmcw::python {

namespace {
py::object pixel_truth(const core::Frame& f) {
  if (!f.truth) return py::none();
  const core::PixelGroundTruth& t = *f.truth;
  const int rows = f.scan.rows, cols = f.scan.cols;
  py::array_t<float> velocity({rows, cols, 3});
  float* v = velocity.mutable_data();
  for (std::size_t i = 0; i < f.scan.size(); ++i) {
    v[3 * i] = t.vx_mps[i];
    v[3 * i + 1] = t.vy_mps[i];
    v[3 * i + 2] = t.vz_mps[i];
  }
  py::dict d;
  d["range"] = to_image(t.range_m, rows, cols);
  d["v"] = to_image(t.radial_velocity_mps, rows, cols);
  d["velocity"] = velocity;
  d["instance"] = to_image(t.instance, rows, cols);
  d["moving"] = to_image<std::uint8_t, bool>(t.moving, rows, cols);
  // The semantic class id per pixel (the dataset's class table maps ids to names); absent in
  // datasets written before classes were.
  if (!t.semantic_class.empty()) d["class"] = to_image(t.semantic_class, rows, cols);
  // The actors' boxes (frames of a Scenario; a PCD alone has none): one row per actor.
  if (f.frame_truth) {
    const auto& actors = f.frame_truth->actors;
    const auto n = static_cast<py::ssize_t>(actors.size());
    py::array_t<double> boxes({n, py::ssize_t{7}}), velocity({n, py::ssize_t{3}});
    py::array_t<double> visible(n);
    py::array_t<bool> truncated(n);
    py::array_t<std::uint32_t> ids(n);
    for (py::ssize_t k = 0; k < n; ++k) {
      const core::BoxTruth& b = actors[static_cast<std::size_t>(k)].box;
      const double row[7] = {b.center_m.x(), b.center_m.y(), b.center_m.z(), b.size_m.x(), b.size_m.y(), b.size_m.z(), b.yaw_rad};
      for (int c = 0; c < 7; ++c) boxes.mutable_at(k, c) = row[c];
      for (int c = 0; c < 3; ++c) velocity.mutable_at(k, c) = b.velocity_mps[c];
      visible.mutable_at(k) = b.visible_fraction;
      truncated.mutable_at(k) = b.truncated;
      ids.mutable_at(k) = actors[static_cast<std::size_t>(k)].id;
    }
    d["box_id"] = ids;
    d["boxes"] = boxes;
    d["box_velocity"] = velocity;
    d["visible_fraction"] = visible;
    d["truncated"] = truncated;
  }
  return d;
}

py::object ego_truth(const core::Frame& f) {
  if (!f.frame_truth) return py::none();
  const core::FrameTruth& t = *f.frame_truth;
  py::dict d;
  d["stamp"] = t.stamp_s;
  d["T_world_rig"] = to_array(t.ego.T_world_rig);
  d["velocity"] = to_array(t.ego.velocity_mps);
  d["angular_velocity"] = to_array(t.ego.angular_velocity_rps);
  return d;
}

py::object actors_truth(const core::Frame& f) {
  if (!f.frame_truth) return py::none();
  py::list out;
  for (const core::ActorTruth& a : f.frame_truth->actors) {
    py::dict d;
    d["id"] = a.id;
    d["class"] = a.class_name;
    d["T_world_actor"] = to_array(a.T_world_actor);
    d["position"] = to_array(a.position_rig_m);
    d["velocity"] = to_array(a.velocity_rig_mps);
    d["angular_velocity"] = to_array(a.angular_velocity_rig_rps);
    d["pixels"] = a.pixels;
    py::dict box;
    box["center"] = to_array(a.box.center_m);
    box["size"] = to_array(a.box.size_m);
    box["yaw"] = a.box.yaw_rad;
    box["velocity"] = to_array(a.box.velocity_mps);
    box["center_world"] = to_array(a.box.center_world_m);
    box["yaw_world"] = a.box.yaw_world_rad;
    box["visible_fraction"] = a.box.visible_fraction;
    box["truncated"] = a.box.truncated;
    d["box"] = box;
    out.append(d);
  }
  return out;
}
}  // namespace

void bind_simulation(py::module_& m) {
  py::class_<core::Frame>(m, "Frame",
                          "A scan and, for simulated data, its ground truth. truth: per-pixel arrays (range, v, "
                          "velocity (rows, cols, 3), instance, moving, class) and, for a Scenario's frames, the actors' "
                          "boxes (box_id, boxes (n, 7): x y z length width height yaw in the rig frame, box_velocity "
                          "(n, 3), visible_fraction, truncated); ego: the rig's pose and velocity (rig axes); "
                          "actors: one dict per actor (velocities absolute, in rig axes).")
      .def_property_readonly("scan", [](const core::Frame& f) { return f.scan; })
      .def_property_readonly("truth", &pixel_truth)
      .def_property_readonly("ego", &ego_truth)
      .def_property_readonly("actors", &actors_truth);

  py::class_<eval::ScenarioSource>(m, "Scenario", "A scenario YAML, simulated one frame at a time in memory.")
      .def(py::init([](const std::string& path, const py::object& frames, const py::object& seed) {
             return std::make_unique<eval::ScenarioSource>(path, frames.is_none() ? 0 : frames.cast<int>(),
                                                           !seed.is_none(),
                                                           seed.is_none() ? 0 : seed.cast<std::uint64_t>());
           }),
           py::arg("path"), py::kw_only(), py::arg("frames") = py::none(), py::arg("seed") = py::none(),
           "Loads and checks the scenario (ValueError naming file, line and key) and builds its scene. frames "
           "and seed override the scenario's.")
      .def("__len__", &eval::ScenarioSource::size)
      .def_property_readonly("name", [](const eval::ScenarioSource& s) { return s.info().scenario; })
      .def_property_readonly("rate_hz", [](const eval::ScenarioSource& s) { return s.info().rate_hz; })
      .def_property_readonly("seed", [](const eval::ScenarioSource& s) { return s.info().seed; })
      .def_property_readonly("config_yaml", [](const eval::ScenarioSource& s) { return s.info().config_yaml; })
      .def_property_readonly(
          "notices", [](const eval::ScenarioSource& s) { return s.info().notices; },
          "What the scenario's files hold that the simulation does not use (clips of actors that do not animate, "
          "morph targets, ...): one line each")
      .def(
          "frame",
          [](eval::ScenarioSource& s, std::size_t k) {
            if (k >= s.size()) {
              throw py::index_error("frame " + std::to_string(k) + " of a scenario with " + std::to_string(s.size()) +
                                    " frames");
            }
            return s.frame(k);  // GIL held: the simulator's buffers belong to this scenario
          },
          py::arg("k"), "Simulates frame k: the frame `fmcw simulate` writes as frames/k (same seed, same values).");
}

}  // namespace fmcw::python
