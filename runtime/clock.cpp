// SPDX-License-Identifier: Apache-2.0
#include <smoothforce/runtime/clock.h>

#include <cerrno>
#include <ctime>

#if defined(__x86_64__) || defined(__i386__)
#include <immintrin.h>
#define SF_CPU_RELAX() _mm_pause()
#elif defined(__aarch64__)
#define SF_CPU_RELAX() asm volatile("yield")
#else
#define SF_CPU_RELAX() ((void)0)
#endif

namespace sf::rt {
namespace {

long long monotonicNs() noexcept {
  timespec ts;
  clock_gettime(CLOCK_MONOTONIC, &ts);
  return static_cast<long long>(ts.tv_sec) * 1000000000LL + ts.tv_nsec;
}

}  // namespace

SteadyClock::SteadyClock(double spin) : spin_(spin > 0 ? spin : 0), originNs_(monotonicNs()) {}

double SteadyClock::now() noexcept { return static_cast<double>(monotonicNs() - originNs_) * 1e-9; }

void SteadyClock::sleepUntil(double deadline) noexcept {
  const double wake = deadline - spin_;
  if (wake > now()) {
    const long long ns = originNs_ + static_cast<long long>(wake * 1e9);
    timespec ts;
    ts.tv_sec = static_cast<time_t>(ns / 1000000000LL);
    ts.tv_nsec = static_cast<long>(ns % 1000000000LL);
    // Absolute sleep: an interrupted call simply sleeps again to the same instant.
    while (clock_nanosleep(CLOCK_MONOTONIC, TIMER_ABSTIME, &ts, nullptr) == EINTR) {
    }
  }
  while (now() < deadline) SF_CPU_RELAX();
}

void FakeClock::sleepUntil(double deadline) noexcept {
  if (deadline > t_) t_ = deadline;
  if (wakeLatency) t_ += wakeLatency(deadline);
}

void FastForwardClock::sleepUntil(double deadline) noexcept {
  const double t = now();
  if (deadline > t) offset_ += deadline - t;
}

}  // namespace sf::rt
