// SPDX-License-Identifier: Apache-2.0
// Shared pieces of the Python module: the cache wrapper and the binding entry points.
#pragma once

#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>

#include <initializer_list>
#include <memory>
#include <string>
#include <vector>

#include <smoothforce/patch/mesh_pipeline.h>
#include <smoothforce/patch/patch_cache.h>

namespace sf::py {

namespace pyb = pybind11;

/// A patch cache as Python sees it: shared, with how it was made.
struct PyCache {
  std::shared_ptr<const PatchCache> cache;
  std::string source;
  Backend backend = Backend::Tbb;
  int threads = 0;
  bool fromMesh = false;
  std::vector<std::string> meshReport, normalReport;
  bool flipped = false;
};

using Doubles = pyb::array_t<double, pyb::array::c_style | pyb::array::forcecast>;

/// h as a C-contiguous float64 array, from any float or integer array-like; InputError
/// (ValueError) naming `field` for any other dtype (strings, objects, None, complex, bool,
/// datetimes), which NumPy's casting would turn into numbers or NaN.
Doubles numericArray(const pyb::handle& h, const std::string& field);

/// The message of `what` as a Python str: UTF-8, bytes that are not kept as \xNN escapes (a
/// file name in another encoding must not empty the message).
pyb::str messageStr(const char* what);

/// A read-only NumPy view of `count` x `cols` values at `data`, keeping `owner` alive.
template <class T>
pyb::array_t<T> view(const T* data, size_t count, size_t cols, pyb::handle owner) {
  std::vector<ssize_t> shape{static_cast<ssize_t>(count)}, strides{static_cast<ssize_t>(cols * sizeof(T))};
  if (cols > 1) {
    shape.push_back(static_cast<ssize_t>(cols));
    strides.push_back(sizeof(T));
  }
  pyb::array_t<T> a(shape, strides, data, owner);
  reinterpret_cast<pyb::detail::PyArray_Proxy*>(a.ptr())->flags &= ~pyb::detail::npy_api::NPY_ARRAY_WRITEABLE_;
  return a;
}

/// One field of a NumPy structured dtype: name, NumPy format ("f8", "(3,)<f4", ...), byte offset.
struct DtypeField {
  const char* name;
  const char* format;
  size_t offset;
};

/// The structured dtype of a C++ record of `itemsize` bytes with these fields (offsetof).
inline pyb::dtype structDtype(std::initializer_list<DtypeField> fields, size_t itemsize) {
  pyb::list names, formats, offsets;
  for (const DtypeField& f : fields) {
    names.append(f.name);
    formats.append(f.format);
    offsets.append(f.offset);
  }
  pyb::dict d;
  d["names"] = names;
  d["formats"] = formats;
  d["offsets"] = offsets;
  d["itemsize"] = itemsize;
  return pyb::dtype::from_args(d);
}

void bindCache(pyb::module_& m);
void bindForce(pyb::module_& m);
void bindSweep(pyb::module_& m);

}  // namespace sf::py
