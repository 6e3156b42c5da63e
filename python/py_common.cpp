// SPDX-License-Identifier: Apache-2.0
// Shared pieces of the Python module: numeric array conversion and error messages.
#include "py_common.h"

#include <cstring>

#include <smoothforce/base/error.h>

namespace sf::py {

Doubles numericArray(const pyb::handle& h, const std::string& field) {
  const pyb::array a = pyb::array::ensure(h);
  if (!a) throw InputError(field + ": not convertible to an array");
  const char kind = a.dtype().kind();
  if (kind != 'f' && kind != 'i' && kind != 'u')
    throw InputError(field + ": expected a numeric array, got dtype " + std::string(pyb::str(a.dtype())));
  return Doubles::ensure(a);
}

pyb::str messageStr(const char* what) {
  PyObject* s = PyUnicode_DecodeUTF8(what, static_cast<Py_ssize_t>(std::strlen(what)), "backslashreplace");
  if (!s) throw pyb::error_already_set();
  return pyb::reinterpret_steal<pyb::str>(s);
}

}  // namespace sf::py
