// SPDX-License-Identifier: Apache-2.0
#include "cli_exit.h"

#include <unistd.h>

#include <csignal>
#include <cstdint>
#include <ctime>

namespace sf::cli {

namespace {

std::atomic<bool> gStop{false};
std::atomic<int> gSignal{0};
int gExitStatus = kExitOk;
static_assert(std::atomic<bool>::is_always_lock_free && std::atomic<int>::is_always_lock_free &&
              std::atomic<int64_t>::is_always_lock_free);

std::atomic<int64_t> gFirstNs{0};  ///< CLOCK_MONOTONIC time of the first signal

int64_t monotonicNs() {
  timespec t{};
  ::clock_gettime(CLOCK_MONOTONIC, &t);  // async-signal-safe
  return static_cast<int64_t>(t.tv_sec) * 1000000000 + t.tv_nsec;
}

extern "C" void onStopSignal(int sig) {
  const int64_t now = monotonicNs();
  int none = 0;
  if (gSignal.compare_exchange_strong(none, sig)) {
    gFirstNs.store(now);
    gStop.store(true);
    return;
  }
  // One kill often arrives twice (to the process and to its group: timeout, shells, job
  // launchers): a repeat within a second is that, not a user insisting. The two copies can
  // be handled at the same moment on two threads, so a first handler that has not yet
  // stored its time (0) also makes this one a repeat.
  const int64_t first = gFirstNs.load();
  if (first == 0 || now - first < 1000000000) return;
  static const char msg[] = "smoothforce: second signal: exiting at once\n";
  [[maybe_unused]] const ssize_t n = ::write(STDERR_FILENO, msg, sizeof msg - 1);
  ::_exit(128 + sig);
}

}  // namespace

void installSignalHandlers() {
  struct sigaction sa {};
  sa.sa_handler = onStopSignal;
  sigemptyset(&sa.sa_mask);
  sa.sa_flags = SA_RESTART;
  for (int sig : {SIGINT, SIGTERM}) {
    struct sigaction old {};
    sigaction(sig, nullptr, &old);
    if (old.sa_handler == SIG_IGN) continue;  // ignored by the parent (nohup, a shell's background job): stays so
    sigaction(sig, &sa, nullptr);
  }
}

int exitStatus() { return gExitStatus; }
void setExitStatus(int status) { gExitStatus = status; }

const std::atomic<bool>& stopFlag() { return gStop; }

int receivedSignal() { return gSignal.load(); }

const char* signalName(int signal) { return signal == SIGINT ? "SIGINT" : signal == SIGTERM ? "SIGTERM" : "a signal"; }

void throwIfInterrupted(const std::string& where, const std::string& kept) {
  if (const int s = receivedSignal()) throw Interrupted(s, where + ": interrupted by " + signalName(s) + "; " + kept);
}

}  // namespace sf::cli
