// fmcw.MotionPipelineParams, fmcw.MotionPipeline, fmcw.MotionResult: the core's motion methods
// on a Scan, results as numpy arrays and dicts.

#include <pybind11/stl.h>

#include "bindings.hpp"
#include "fmcw/core/motion_pipeline.hpp"
#include "numpy_arrays.hpp"

namespace fmcw::python {

namespace {
py::dict velocity_dict(const core::VelocityEstimate& e) {
  py::dict d;
  d["velocity"] = to_array(e.velocity_mps);
  d["std"] = to_array(e.axis_std_mps());
  d["covariance"] = to_array(e.covariance);
  d["condition_number"] = e.condition_number;
  d["residual_rms"] = e.residual_rms_mps;
  d["points_used"] = e.num_points;
  d["valid"] = e.valid;
  return d;
}

py::dict ego_dict(const core::MotionEstimate& e) {
  py::dict d = velocity_dict(e.ego);
  d["angular_velocity"] = to_array(e.ego_angular_velocity_rps);
  d["yaw_rate_estimated"] = e.ego_yaw_rate_estimated;
  d["standing"] = e.ego_standing;
  return d;
}

py::list objects_list(const core::MotionEstimate& e) {
  py::list out;
  for (const core::ClusterEstimate& c : e.clusters) {
    py::dict d = velocity_dict(c.velocity);
    d["id"] = c.id;
    d["pixels"] = c.num_pixels;
    d["centroid"] = to_array(c.centroid_m);
    d["track_id"] = c.track_id;  // 0: untracked (methods without tracking, or a track not yet born)
    d["track_hits"] = c.track_hits;
    d["carried_pixels"] = c.carried_pixels;
    d["centre"] = to_array(c.centre_m);
    d["yaw_rate"] = c.yaw_rate_rps;
    out.append(d);
  }
  return out;
}

core::MotionPipelineParams with_overrides(core::MotionPipelineParams p, const py::object& seed,
                                          const py::object& num_threads) {
  if (!seed.is_none()) p.seed = seed.cast<std::uint64_t>();
  if (!num_threads.is_none()) p.num_threads = num_threads.cast<int>();
  return p;
}
}  // namespace

void bind_pipeline(py::module_& m) {
  py::class_<core::SegmentationParams>(m, "SegmentationParams", "Algorithm 1 (methods paper and fast).")
      .def_readwrite("velocity_threshold_mps", &core::SegmentationParams::velocity_threshold_mps)
      .def_readwrite("min_cluster_pixels", &core::SegmentationParams::min_cluster_pixels);
  py::class_<core::VelocityParams>(m, "VelocityParams", "Least-squares velocity (Eq. 20-22).")
      .def_readwrite("ego_max_points", &core::VelocityParams::ego_max_points)
      .def_readwrite("object_max_points", &core::VelocityParams::object_max_points);
  py::class_<core::EgoTwistParams>(m, "EgoTwistParams", "Robust ego twist (method robust).")
      .def_readwrite("noise_sigma_mps", &core::EgoTwistParams::noise_sigma_mps)
      .def_readwrite("inlier_threshold_mps", &core::EgoTwistParams::inlier_threshold_mps)
      .def_readwrite("ransac_iterations", &core::EgoTwistParams::ransac_iterations)
      .def_readwrite("estimate_yaw_rate", &core::EgoTwistParams::estimate_yaw_rate)
      .def_readwrite("lateral_velocity_sigma_mps", &core::EgoTwistParams::lateral_velocity_sigma_mps);
  py::class_<core::InstanceParams>(m, "InstanceParams", "Moving instances by range and Doppler (method robust).")
      .def_readwrite("max_range_gap_m", &core::InstanceParams::max_range_gap_m)
      .def_readwrite("max_doppler_step_mps", &core::InstanceParams::max_doppler_step_mps)
      .def_readwrite("min_cluster_pixels", &core::InstanceParams::min_cluster_pixels);

  py::class_<core::MotionPipelineParams>(m, "MotionPipelineParams",
                                         "A method preset and its parameters; attributes may be changed.")
      .def(py::init([](const std::string& method) { return core::MotionPipelineParams::preset(method); }),
           py::arg("method") = core::MotionPipelineParams::default_method())
      .def_readonly("method", &core::MotionPipelineParams::method)
      .def_readwrite("segmentation", &core::MotionPipelineParams::segmentation)
      .def_readwrite("velocity", &core::MotionPipelineParams::velocity)
      .def_readwrite("ego", &core::MotionPipelineParams::ego)
      .def_readwrite("instances", &core::MotionPipelineParams::instances)
      .def_readwrite("moving_sigma", &core::MotionPipelineParams::moving_sigma)
      .def_readwrite("planar_objects", &core::MotionPipelineParams::planar_objects)
      .def_readwrite("max_weak_sigma_mps", &core::MotionPipelineParams::max_weak_sigma_mps)
      .def_readwrite("seed", &core::MotionPipelineParams::seed)
      .def_readwrite("num_threads", &core::MotionPipelineParams::num_threads)
      .def("validate", &core::MotionPipelineParams::validate)
      .def_static("methods", &core::MotionPipelineParams::preset_names)
      .def_static("default_method", &core::MotionPipelineParams::default_method);

  py::class_<core::MotionEstimate>(m, "MotionResult",
                                   "labels: int32 (rows, cols): -1 no return, -2 unassigned, 0 static, k moving "
                                   "cluster k. Velocities in the rig frame [m/s].")
      .def_property_readonly("status", [](const core::MotionEstimate& e) { return core::to_string(e.status); })
      .def_readonly("message", &core::MotionEstimate::message)
      .def_readonly("method", &core::MotionEstimate::method)
      .def_property_readonly("ok", &core::MotionEstimate::ok)
      .def_property_readonly("labels", [](const core::MotionEstimate& e) { return to_image(e.labels, e.rows, e.cols); })
      .def_property_readonly("moving",
                             [](const core::MotionEstimate& e) {
                               py::array_t<bool> out({e.rows, e.cols});
                               bool* p = out.mutable_data();
                               for (std::size_t i = 0; i < e.labels.size(); ++i) p[i] = e.labels[i] > 0;
                               return out;
                             })
      .def_property_readonly("instances",
                             [](const core::MotionEstimate& e) {
                               std::vector<std::int32_t> ids(e.labels);
                               for (auto& id : ids) id = id > 0 ? id : 0;
                               return to_image(ids, e.rows, e.cols);
                             },
                             "moving cluster id per pixel, 0 elsewhere")
      .def_readonly("num_static_pixels", &core::MotionEstimate::num_static_pixels)
      .def_property_readonly("ego_velocity", [](const core::MotionEstimate& e) { return to_array(e.ego.velocity_mps); })
      .def_property_readonly("ego", &ego_dict)
      .def_property_readonly("objects", &objects_list)
      .def_property_readonly("timing", [](const core::MotionEstimate& e) {
        py::dict d;
        d["clustering_ms"] = e.timing.clustering_ms;
        d["ego_ms"] = e.timing.ego_ms;
        d["objects_ms"] = e.timing.objects_ms;
        d["total_ms"] = e.timing.total_ms;
        return d;
      });

  py::class_<core::MotionPipeline>(m, "MotionPipeline", "Scan -> MotionResult with one of the core's methods.")
      .def(py::init([](const std::string& method, const py::object& seed, const py::object& num_threads) {
             return core::MotionPipeline(with_overrides(core::MotionPipelineParams::preset(method), seed, num_threads));
           }),
           py::arg("method") = core::MotionPipelineParams::default_method(), py::kw_only(), py::arg("seed") = py::none(),
           py::arg("num_threads") = py::none())
      .def(py::init([](const core::MotionPipelineParams& params, const py::object& seed, const py::object& num_threads) {
             return core::MotionPipeline(with_overrides(params, seed, num_threads));
           }),
           py::arg("params"), py::kw_only(), py::arg("seed") = py::none(), py::arg("num_threads") = py::none())
      .def_property_readonly("params", [](const core::MotionPipeline& p) { return p.params(); }, "a copy")
      // The GIL stays held: a pipeline keeps working buffers, so two threads must not share one.
      .def("process", &core::MotionPipeline::process, py::arg("scan"), py::arg("frame_index") = 0,
           "Runs the method. ValueError for a malformed scan; a scan with nothing to estimate gives "
           "ok == False and a status.");
}

}  // namespace fmcw::python
