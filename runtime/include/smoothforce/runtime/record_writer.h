// SPDX-License-Identifier: Apache-2.0
// The writer thread that drains the loop's step records into a CSV file.
#pragma once

#include <atomic>
#include <cstdio>
#include <string>
#include <thread>

#include <smoothforce/runtime/servo_loop.h>

namespace sf::rt {

/// CSV header of the record file.
inline constexpr const char* kRecordCsvHeader =
    "tick,t,x,y,z,fx,fy,fz,rfx,rfy,rfz,contact,compute_us,lateness_us,flags,sample,age_us";

/// Consumes a SpscRing<StepRecord> on its own thread and writes one CSV row per record
/// (header kRecordCsvHeader; t in s, positions (world frame) in m, forces (world frame) in N,
/// times in us, flags as SafetyFlag | StepFlag bits, sample = the device's sample number,
/// age_us = the sample's age at the read). It polls the ring every `pollSeconds` when it is empty, so the loop
/// never waits for it. Writes to PATH.tmp and renames it to PATH in finish().
class RecordWriter {
 public:
  /// Opens PATH.tmp and starts the thread. Throws InputError when the file cannot be opened.
  RecordWriter(const std::string& path, SpscRing<StepRecord>& ring, double pollSeconds = 0.002);
  RecordWriter(const RecordWriter&) = delete;
  RecordWriter& operator=(const RecordWriter&) = delete;
  /// Stops the thread if finish() was not called (the partial file is removed).
  ~RecordWriter();
  /// Drains the ring, stops the thread, closes and renames the file. Call after the loop
  /// has ended. Throws InputError when writing failed.
  void finish();
  int64_t written() const noexcept { return written_.load(std::memory_order_relaxed); }

 private:
  void drain() noexcept;
  void threadMain() noexcept;

  std::string path_, tmp_;
  SpscRing<StepRecord>& ring_;
  double poll_;
  std::FILE* file_ = nullptr;
  std::atomic<bool> done_{false};
  std::atomic<int64_t> written_{0};
  bool failed_ = false;
  std::thread thread_;
};

}  // namespace sf::rt
