// SPDX-License-Identifier: Apache-2.0
// Counts operator new calls made on a thread while it has counting switched on (the runtime
// tests' real-time checks). The replacement operator new lives in runtime_alloc_counter.cpp;
// the other forms of new in libstdc++ (array, nothrow) call it. Off under sanitizers, which
// bring their own operator new and delete.
#pragma once

#if defined(__SANITIZE_ADDRESS__) || defined(__SANITIZE_THREAD__)
#define SF_COUNT_ALLOCS 0
#elif defined(__has_feature)
#if __has_feature(address_sanitizer) || __has_feature(thread_sanitizer) || __has_feature(memory_sanitizer)
#define SF_COUNT_ALLOCS 0
#endif
#endif
#ifndef SF_COUNT_ALLOCS
#define SF_COUNT_ALLOCS 1
#endif

namespace sf::test {
extern thread_local bool tCountAllocs;  ///< count this thread's operator new calls while true
extern thread_local long tAllocs;       ///< this thread's count
}  // namespace sf::test
