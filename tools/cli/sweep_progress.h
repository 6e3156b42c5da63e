// A minimal terminal progress bar (count, rate, time left) for long sweeps. Debian packages
// no progress-bar library (apt-cache search indicators progress: none for C++), so this is ours.
// Draws on stderr only when stderr is a terminal; silent otherwise.
#pragma once

#include <unistd.h>

#include <atomic>
#include <chrono>
#include <cstdint>
#include <cstdio>
#include <mutex>
#include <string>

namespace sf::cli {

class ProgressBar {
 public:
  ProgressBar(uint64_t total, std::string unit)
      : total_(total), unit_(std::move(unit)), enabled_(::isatty(STDERR_FILENO) == 1), t0_(clock::now()) {}
  ~ProgressBar() { finish(); }
  /// Thread-safe; redraws at most every 0.1 s.
  void add(uint64_t n) {
    const uint64_t done = done_.fetch_add(n) + n;
    if (!enabled_) return;
    std::unique_lock lock(mutex_, std::try_to_lock);
    if (!lock.owns_lock()) return;
    const auto now = clock::now();
    if (done < total_ && (now - last_ < std::chrono::milliseconds(100) || now - t0_ < std::chrono::milliseconds(250)))
      return;  // no rate from the first chunk alone
    last_ = now;
    draw(done, std::chrono::duration<double>(now - t0_).count());
  }
  void finish() {
    if (!enabled_ || finished_) return;
    finished_ = true;
    std::lock_guard lock(mutex_);
    draw(done_.load(), std::chrono::duration<double>(clock::now() - t0_).count());
    std::fputc('\n', stderr);
  }

 private:
  using clock = std::chrono::steady_clock;
  void draw(uint64_t done, double secs) {
    const double frac = total_ ? static_cast<double>(done) / static_cast<double>(total_) : 1.0;
    const int width = 30, fill = static_cast<int>(frac * width);
    const double rate = secs > 0 ? static_cast<double>(done) / secs : 0;
    const double left = rate > 0 ? static_cast<double>(total_ - done) / rate : 0;
    std::string bar(static_cast<size_t>(fill), '#');
    bar.resize(width, '.');
    std::fprintf(stderr, "\r[%s] %3.0f%% %llu/%llu  %.3g %s/s  left %d:%02d  ", bar.c_str(), 100 * frac,
                 static_cast<unsigned long long>(done), static_cast<unsigned long long>(total_), rate, unit_.c_str(),
                 static_cast<int>(left) / 60, static_cast<int>(left) % 60);
    std::fflush(stderr);
  }
  uint64_t total_;
  std::string unit_;
  bool enabled_, finished_ = false;
  std::atomic<uint64_t> done_{0};
  std::mutex mutex_;
  clock::time_point t0_, last_{};
};

}  // namespace sf::cli
