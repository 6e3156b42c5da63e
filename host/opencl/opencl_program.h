// SPDX-License-Identifier: Apache-2.0
// Internal to the OpenCL backends (opencl_backend.cpp, opencl_refine.cpp): program sources
// from the embedded kernel text, a device with the float and double programs of one kernel
// file, and buffer helpers. Not part of the public API.
#pragma once

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <string>
#include <vector>

#include <smoothforce/opencl/opencl_backend.h>
#include <smoothforce/opencl/opencl_context.h>

namespace sf::opencl_detail {

/// Program source = fp64 pragma + gp_config.h, gp_vec.h, gp_tables.h, gp_edge.h, gp_eval.h (+ gp_refine.h
/// when withRefine) + the kernel file, each with a #line so that build logs name the file.
/// withClosest: the program needs gp_closest.h (the candidate search; double only).
std::vector<std::string> programSources(const char* kernelFile, const char* kernelText, bool withRefine = false,
                                        bool withClosest = false);

inline size_t roundUp(size_t n, size_t m) { return (n + m - 1) / m * m; }

/// f(i) for i in [0, n) in oneTBB tasks of at least `grain` items: a batch's packing into the
/// device's layout and its unpacking, memory-bound copies as long as their transfers.
template <class F>
void parallelRange(size_t n, const F& f, size_t grain = 4096) {
  tbb::parallel_for(tbb::blocked_range<size_t>(0, n, grain), [&](const tbb::blocked_range<size_t>& r) {
    for (size_t i = r.begin(); i < r.end(); ++i) f(i);
  });
}

/// A context plus the float and double programs of one kernel file, built on first use.
struct Device {
  /// file, text: the kernel file's name and embedded text; kernelName: its __kernel.
  /// withRefine: the program needs gp_refine.h. Throws OpenCLError (no device).
  Device(const OpenCLOptions& o, const char* file, const char* text, const char* kernelName, bool withRefine = false,
         bool withClosest = false)
      : opt(o),
        ctx(o.device),
        file(file),
        text(text),
        kernelName(kernelName),
        withRefine(withRefine),
        withClosest(withClosest) {}

  OpenCLOptions opt;
  OpenCLContext ctx;
  const char* file;
  const char* text;
  const char* kernelName;
  bool withRefine;
  bool withClosest;
  BuiltProgram prog[2];
  cl::Kernel kernel[2];
  cl::Buffer domains[2];  ///< the host's domain table in each precision, uploaded on first use
  size_t local[2] = {1, 1};
  int last = 0;

  /// Work-group size for the last kernel obtained (see OpenCLOptions::workGroupSize).
  size_t groupSize() const { return local[last]; }
  /// Work-group size for k on this device (OpenCLOptions::workGroupSize, or automatic).
  size_t chooseGroupSize(const cl::Kernel& k) const;
  /// The kernel for precision p, building its program on first use. Throws OpenCLError
  /// (build log included; double on a device without cl_khr_fp64).
  cl::Kernel& get(Precision p);
  /// The host's domain constants (gp_tables.h, GP_DOMAIN_FLAT_OFFSET) in precision p on the
  /// device, uploaded on first use: every kernel reads them there instead of computing its own
  /// cos and sin. Throws OpenCLError.
  const cl::Buffer& domainTable(Precision p);
};

/// A read-only device buffer holding v (at least one element), written without blocking;
/// the write's event is appended to ev. v must stay alive until the queue is finished.
template <class T>
cl::Buffer upload(OpenCLContext& c, const std::vector<T>& v, std::vector<cl::Event>& ev) {
  cl::Buffer b(c.context(), CL_MEM_READ_ONLY, std::max<size_t>(1, v.size()) * sizeof(T));
  if (!v.empty()) {
    ev.emplace_back();
    c.queue().enqueueWriteBuffer(b, CL_FALSE, 0, v.size() * sizeof(T), v.data(), nullptr, &ev.back());
  }
  return b;
}

/// Waits for e to complete, sleeping between checks of its status: a blocking wait spins a core
/// in some drivers (NVIDIA's), and the OpenCL sweep's CPU stages run on every core meanwhile.
/// Flushes q first. Throws cl::Error for a failed command.
void waitSleeping(cl::CommandQueue& q, const cl::Event& e);
/// Sum of the profiled durations of completed events, s.
double sumSeconds(const std::vector<cl::Event>& ev);

/// Throws std::invalid_argument "<what> exceeds INT_MAX" when n does not fit a kernel int.
void checkInt(size_t n, const char* what);

}  // namespace sf::opencl_detail
