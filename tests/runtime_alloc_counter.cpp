// SPDX-License-Identifier: Apache-2.0
#include "runtime_alloc_counter.h"

#include <cstdlib>
#include <new>

namespace sf::test {
thread_local bool tCountAllocs = false;
thread_local long tAllocs = 0;
}  // namespace sf::test

#if SF_COUNT_ALLOCS
void* operator new(std::size_t n) {
  if (sf::test::tCountAllocs) ++sf::test::tAllocs;
  if (void* p = std::malloc(n ? n : 1)) return p;
  throw std::bad_alloc();
}
void operator delete(void* p) noexcept { std::free(p); }
void operator delete(void* p, std::size_t) noexcept { std::free(p); }
#endif
