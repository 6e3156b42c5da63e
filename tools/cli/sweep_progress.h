// SPDX-License-Identifier: Apache-2.0
// Progress of long sweeps on stderr: a bar redrawn in place (count, rate, time left) when
// stderr is a terminal, else one line every `lineInterval` seconds, so that job logs (Slurm,
// CI, nohup) show how far a run is. Debian packages no progress-bar library (apt-cache
// search indicators progress: none for C++), so this is ours.
#pragma once

#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cstdint>
#include <cstdio>
#include <mutex>
#include <string>

namespace sf::cli {

class ProgressBar {
 public:
  /// total: units to do; lineInterval: s between lines when stderr is not a terminal (<= 0: no lines).
  ProgressBar(uint64_t total, std::string unit, double lineInterval = 10, std::string prefix = "sweep")
      : total_(total),
        unit_(std::move(unit)),
        prefix_(std::move(prefix)),
        tty_(::isatty(STDERR_FILENO) == 1),
        lineInterval_(lineInterval),
        t0_(clock::now()),
        last_(t0_) {}
  ~ProgressBar() { finish(); }
  /// Thread-safe; draws at most every 0.1 s (terminal) or every lineInterval (otherwise).
  void add(uint64_t n) {
    const uint64_t done = done_.fetch_add(n) + n;
    if (!tty_ && !(lineInterval_ > 0)) return;
    std::unique_lock lock(mutex_, std::try_to_lock);
    if (!lock.owns_lock()) return;
    const auto now = clock::now();
    const double secs = std::chrono::duration<double>(now - t0_).count();
    if (tty_) {
      if (done < total_ && (now - last_ < std::chrono::milliseconds(100) || secs < 0.25))
        return;  // no rate from the first chunk alone
      last_ = now;
      draw(done, secs);
    } else if (std::chrono::duration<double>(now - last_).count() >= lineInterval_) {
      last_ = now;
      line(done, secs);
    }
  }
  void finish() {
    if (finished_) return;
    finished_ = true;
    std::lock_guard lock(mutex_);
    const double secs = std::chrono::duration<double>(clock::now() - t0_).count();
    if (tty_) {
      draw(done_.load(), secs);
      std::fputc('\n', stderr);
    } else if (lineInterval_ > 0) {
      line(done_.load(), secs);
    }
  }

 private:
  using clock = std::chrono::steady_clock;
  double rate(uint64_t done, double secs) const { return secs > 0 ? static_cast<double>(done) / secs : 0; }
  std::string left(uint64_t done, double secs) const {
    const double r = rate(done, secs);
    const int s = r > 0 ? static_cast<int>(static_cast<double>(total_ - std::min(done, total_)) / r) : 0;
    char b[32];
    std::snprintf(b, sizeof b, "%d:%02d", s / 60, s % 60);
    return b;
  }
  void draw(uint64_t done, double secs) {
    const double frac = total_ ? static_cast<double>(done) / static_cast<double>(total_) : 1.0;
    const int width = 30, fill = static_cast<int>(frac * width);
    std::string bar(static_cast<size_t>(fill), '#');
    bar.resize(width, '.');
    std::fprintf(stderr, "\r[%s] %3.0f%% %llu/%llu  %.3g %s/s  left %s  ", bar.c_str(), 100 * frac,
                 static_cast<unsigned long long>(done), static_cast<unsigned long long>(total_), rate(done, secs),
                 unit_.c_str(), left(done, secs).c_str());
    std::fflush(stderr);
  }
  void line(uint64_t done, double secs) {
    const double frac = total_ ? static_cast<double>(done) / static_cast<double>(total_) : 1.0;
    std::fprintf(stderr, "%s: progress %llu/%llu %ss (%.1f%%), %.3g/s, %.1f s, left %s\n", prefix_.c_str(),
                 static_cast<unsigned long long>(done), static_cast<unsigned long long>(total_), unit_.c_str(),
                 100 * frac, rate(done, secs), secs, left(done, secs).c_str());
    std::fflush(stderr);
  }
  uint64_t total_;
  std::string unit_, prefix_;
  bool tty_, finished_ = false;
  double lineInterval_;
  std::atomic<uint64_t> done_{0};
  std::mutex mutex_;
  clock::time_point t0_, last_;
};

}  // namespace sf::cli
