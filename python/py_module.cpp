// `import smoothforce`: the module, its version and the error mapping.
#include <smoothforce/base/error.h>
#include <smoothforce/version.h>
#include "py_common.h"

PYBIND11_MODULE(smoothforce, m) {
  namespace pyb = pybind11;
  m.doc() =
      "SmoothForce: smooth haptic force on coarse polygon meshes through G1 Gregory patches\n"
      "(Wu et al., 'Smooth Force Rendering on Coarse Polygonal Meshes').\n\n"
      "Units: metres, newtons, N/m, seconds. Bad input (files, arrays, options) raises ValueError\n"
      "with a message naming the file and line, or the field and element.";
  m.attr("__version__") = SF_VERSION_STRING;
  pyb::register_exception_translator([](std::exception_ptr p) {
    try {
      if (p) std::rethrow_exception(p);
    } catch (const sf::InputError& e) {
      PyErr_SetString(PyExc_ValueError, e.what());
    }
  });
  sf::py::bindCache(m);
  sf::py::bindForce(m);
  sf::py::bindSweep(m);
}
