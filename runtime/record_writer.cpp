// SPDX-License-Identifier: Apache-2.0
#include <smoothforce/runtime/record_writer.h>

#include <chrono>

#include <smoothforce/base/staged_output.h>
#include <smoothforce/mesh/mesh.h>

namespace sf::rt {

RecordWriter::RecordWriter(const std::string& path, SpscRing<StepRecord>& ring, double pollSeconds)
    : path_(path), tmp_(stagingPath(path)), ring_(ring), poll_(pollSeconds > 0 ? pollSeconds : 0.002) {
  file_ = std::fopen(tmp_.c_str(), "w");
  if (!file_) throw InputError(path_ + ": cannot open for writing");
  std::fprintf(file_, "%s\n", kRecordCsvHeader);
  thread_ = std::thread([this] { threadMain(); });
}

RecordWriter::~RecordWriter() {
  if (thread_.joinable()) {
    done_.store(true, std::memory_order_release);
    thread_.join();
  }
  if (file_) {
    std::fclose(file_);
    discardStaging(tmp_, path_);
  }
}

void RecordWriter::drain() noexcept {
  StepRecord r;
  int64_t n = 0;
  while (ring_.tryPop(r)) {
    if (std::fprintf(file_, "%lld,%.9f,%.9g,%.9g,%.9g,%.6g,%.6g,%.6g,%.6g,%.6g,%.6g,%d,%.3f,%.3f,%u,%llu,%.3f\n",
                     static_cast<long long>(r.tick), r.t, r.hip[0], r.hip[1], r.hip[2], r.force[0], r.force[1],
                     r.force[2], r.rendered[0], r.rendered[1], r.rendered[2], r.contact, r.compute * 1e6,
                     r.lateness * 1e6, r.flags, static_cast<unsigned long long>(r.sample), r.age * 1e6) < 0)
      failed_ = true;
    ++n;
  }
  if (n) written_.fetch_add(n, std::memory_order_relaxed);
}

void RecordWriter::threadMain() noexcept {
  const auto nap = std::chrono::duration<double>(poll_);
  while (!done_.load(std::memory_order_acquire)) {
    drain();
    std::this_thread::sleep_for(nap);
  }
  drain();  // whatever was pushed before done_ was set
}

void RecordWriter::finish() {
  if (thread_.joinable()) {
    done_.store(true, std::memory_order_release);
    thread_.join();
  }
  if (!file_) return;
  const bool bad = failed_ || std::ferror(file_) != 0;
  const bool closeFailed = std::fclose(file_) != 0;
  file_ = nullptr;
  if (bad || closeFailed || std::rename(tmp_.c_str(), path_.c_str()) != 0) {
    discardStaging(tmp_, path_);
    throw InputError(path_ + ": write failed");
  }
}

}  // namespace sf::rt
