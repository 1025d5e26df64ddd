#pragma once
// The parts of the `fmcw` Python module, each defined in its own file.

#include <pybind11/pybind11.h>

namespace fmcw::core {
struct GridProjection;
}

namespace fmcw::python {

/// A projection as the dict project_points and read_aeva_scan return: scan, counts, and the
/// pixel <-> point maps as arrays.
pybind11::dict projection_to_dict(core::GridProjection&& projection);

void bind_scan(pybind11::module_& m);        // Head, Scan, project_points
void bind_pipeline(pybind11::module_& m);    // MotionPipelineParams, MotionPipeline, MotionResult
void bind_simulation(pybind11::module_& m);  // Frame, Scenario
void bind_io(pybind11::module_& m);          // read_frame, write_frame, read_aeva, read_aeva_scan

}  // namespace fmcw::python
