// The `fmcw` Python module: the motion-perception core on numpy arrays, the simulator, and the
// file formats. Every C++ std::invalid_argument arrives as ValueError, std::runtime_error as
// RuntimeError, with the message the CLI would print.

#include "bindings.hpp"

PYBIND11_MODULE(fmcw, m) {
  m.doc() = "FMCW LiDAR motion perception: Doppler segmentation, ego and object velocity, simulation";
  m.attr("__version__") = FMCW_VERSION;
  fmcw::python::bind_scan(m);
  fmcw::python::bind_pipeline(m);
  fmcw::python::bind_simulation(m);
  fmcw::python::bind_io(m);
}
