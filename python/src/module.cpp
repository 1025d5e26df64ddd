// The `fmcw` Python module: the motion-perception core on numpy arrays, the simulator, and the
// file formats. Errors arrive with the message the CLI would print, as the module's own
// exception types by their C++ kind (core/errors.hpp): fmcw.InputError (a ValueError) for bad
// input or parameters, fmcw.FileError (a ValueError and an OSError) for a file that is missing,
// unreadable or malformed, fmcw.LimitError (a RuntimeError) for a resource limit; any other
// std::invalid_argument as ValueError, std::runtime_error as RuntimeError.

#include "bindings.hpp"
#include "fmcw/core/errors.hpp"

namespace py = pybind11;

PYBIND11_MODULE(fmcw, m) {
  m.doc() = "FMCW LiDAR motion perception: Doppler segmentation, ego and object velocity, simulation";
  m.attr("__version__") = FMCW_VERSION;
  py::register_exception<fmcw::core::InputError>(m, "InputError", PyExc_ValueError);
  py::register_exception<fmcw::core::FileError>(m, "FileError",
                                                py::make_tuple(py::handle(PyExc_ValueError), py::handle(PyExc_OSError)));
  py::register_exception<fmcw::core::LimitError>(m, "LimitError", PyExc_RuntimeError);
  fmcw::python::bind_scan(m);
  fmcw::python::bind_pipeline(m);
  fmcw::python::bind_simulation(m);
  fmcw::python::bind_io(m);
}
