// SPDX-License-Identifier: Apache-2.0
// `import smoothforce`: the module, its version and the error mapping.
#include <filesystem>
#include <stdexcept>

#include <smoothforce/base/error.h>
#include <smoothforce/base/status.h>
#include <smoothforce/version.h>
#include "py_common.h"

PYBIND11_MODULE(smoothforce, m) {
  namespace pyb = pybind11;
  m.doc() =
      "SmoothForce: smooth haptic force on coarse polygon meshes through G1 Gregory patches\n"
      "(Wu et al., 'Smooth Force Rendering on Coarse Polygonal Meshes').\n\n"
      "Units: metres, newtons, N/m, seconds. Bad input (files, arrays, options) raises ValueError\n"
      "with a message naming the file and line, or the field and element. Status words carry the\n"
      "bits SF_ST_* (patch and point), SF_TRACK_* (step) and SF_PROBE_* (sweep probe), module constants.";
  m.attr("__version__") = SF_VERSION_STRING;
  // the status bits of patch points, steps and probes, by the C++ names (SF_ST_MODEL_POINT, ...)
  for (const sf::StatusBit& b : sf::kStatusBits) m.attr(b.name) = b.value;
  // messages as str with undecodable bytes escaped: PyErr_SetString would leave an empty message
  // for a file name that is not UTF-8
  pyb::register_exception_translator([](std::exception_ptr p) {
    try {
      if (p) std::rethrow_exception(p);
    } catch (const sf::InputError& e) {
      PyErr_SetObject(PyExc_ValueError, sf::py::messageStr(e.what()).ptr());
    } catch (const std::filesystem::filesystem_error& e) {  // an output path that cannot be made
      PyErr_SetObject(PyExc_ValueError, sf::py::messageStr(e.what()).ptr());
    } catch (const std::length_error& e) {  // a size no container can hold
      PyErr_SetObject(PyExc_MemoryError, sf::py::messageStr(e.what()).ptr());
    }
  });
  sf::py::bindCache(m);
  sf::py::bindForce(m);
  sf::py::bindSweep(m);
}
