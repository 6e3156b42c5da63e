// SPDX-License-Identifier: Apache-2.0
// The command line's contract for scripts: exit statuses, usage errors, and SIGINT/SIGTERM,
// handled alike by every subcommand (docs/guide.md "Scripts: exit status, output, JSON").
#pragma once

#include <atomic>
#include <stdexcept>
#include <string>

#include <smoothforce/base/error.h>  // InputError

namespace sf::cli {

/// Exit statuses of `smoothforce`.
enum ExitStatus : int {
  kExitOk = 0,
  kExitInput = 1,  ///< bad input: a file unreadable or malformed, values out of range, a failed write
  kExitUsage = 2,  ///< the command line: unknown or missing options, conflicting or out-of-range option values
  kExitFault = 3,  ///< `loop`: the safety layer latched a fault
  // 128 + signal number when interrupted: 130 (SIGINT), 143 (SIGTERM)
};

/// A mistake on the command line found after parsing (conflicting options, an option value
/// out of range): exit 2, one line on stderr.
class UsageError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// Thrown by a command that stopped on SIGINT or SIGTERM after writing what it keeps (its
/// message says what that is): exit 128 + signal.
class Interrupted : public std::runtime_error {
 public:
  Interrupted(int signal, const std::string& what) : std::runtime_error(what), signal_(signal) {}
  int signal() const { return signal_; }

 private:
  int signal_;
};

/// Runs f (option checks that throw InputError) and turns an InputError into a UsageError.
template <class F>
void checkOptions(F&& f) {
  try {
    f();
  } catch (const InputError& e) {
    throw UsageError(e.what());
  }
}

/// The status main returns when the command ends without an exception (kExitOk unless a
/// command set another, e.g. `loop` after a safety fault).
int exitStatus();
void setExitStatus(int status);

/// Installs the SIGINT and SIGTERM handlers (once, from main; a signal the parent ignored,
/// e.g. under nohup, stays ignored). The first signal sets stopFlag() and records the signal:
/// commands stop at their next check (a chunk of a sweep, a servo tick, a trace step, a phase
/// of the others) and exit 128 + signal. A second signal at least 1 s after the first exits at
/// once with 128 + its number (a repeat within 1 s is the same kill delivered twice).
void installSignalHandlers();
/// True once SIGINT or SIGTERM arrived (polled by the servo loop and sweeps).
const std::atomic<bool>& stopFlag();
/// SIGINT or SIGTERM when one arrived, else 0.
int receivedSignal();
/// "SIGINT", "SIGTERM".
const char* signalName(int signal);
/// Throws Interrupted("<where>: interrupted by SIG..; <kept>") when a signal arrived.
void throwIfInterrupted(const std::string& where, const std::string& kept = "nothing written");

}  // namespace sf::cli
