// SPDX-License-Identifier: Apache-2.0
// Bytes that containers hold, for the memory reports of the runtime structures.
#pragma once

#include <cstddef>

namespace sf {

/// The bytes the vectors (or other containers with capacity() and value_type) hold on the heap:
/// capacity x element size, summed; the objects themselves and their elements' own heap memory
/// are not counted.
template <class... V>
size_t vectorBytes(const V&... v) noexcept {
  return (size_t(0) + ... + (v.capacity() * sizeof(typename V::value_type)));
}

}  // namespace sf
