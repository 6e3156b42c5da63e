// SPDX-License-Identifier: Apache-2.0
// Thin RAII layer over the Khronos C++ bindings (CL/opencl.hpp): device selection, context,
// in-order profiling queue, program build with an on-disk binary cache, and errors that
// name the call, the error code and (for builds) the full build log.
//
// The bindings are configured here, once, for OpenCL 1.2 (what PoCL's OpenCL C offers) and
// with exceptions on; every cl::Error that leaves this layer or the backend is turned into
// sf::OpenCLError.
#pragma once

#ifndef CL_HPP_ENABLE_EXCEPTIONS
#define CL_HPP_ENABLE_EXCEPTIONS
#endif
#ifndef CL_HPP_TARGET_OPENCL_VERSION
#define CL_HPP_TARGET_OPENCL_VERSION 120
#endif
#ifndef CL_HPP_MINIMUM_OPENCL_VERSION
#define CL_HPP_MINIMUM_OPENCL_VERSION 120
#endif
#include <CL/opencl.hpp>

#include <cstdint>
#include <stdexcept>
#include <string>
#include <vector>

namespace sf {

/// An OpenCL failure. what() = "<where>: <call> failed: <CL_NAME> (<code>)" followed, for
/// program builds, by the build options and the full build log.
class OpenCLError : public std::runtime_error {
 public:
  OpenCLError(const std::string& message, int code) : std::runtime_error(message), code_(code) {}
  /// The OpenCL error code (CL_*), or 0 when the failure is not an OpenCL call's.
  int code() const { return code_; }

 private:
  int code_;
};

/// Name of an OpenCL error code ("CL_OUT_OF_RESOURCES"), "CL_UNKNOWN_ERROR" if unknown.
const char* clErrorName(int code);

/// Throws OpenCLError for a failed call: "<where>: <call> failed: <CL_NAME> (<code>)<detail>".
[[noreturn]] void throwOpenCL(const std::string& where, const std::string& call, int code,
                              const std::string& detail = "");
/// Throws OpenCLError for a cl::Error raised by the bindings (its what() is the call name).
[[noreturn]] void rethrowOpenCL(const std::string& where, const cl::Error& e);

/// One device of one platform. index counts all devices of all platforms in order.
struct OpenCLDeviceInfo {
  int index = 0;
  std::string name, platformName, version, driverVersion, extensions;
  cl_device_type type = 0;
  cl::Device device;
  cl::Platform platform;
};

/// All devices of all platforms, in platform order then device order. Never throws: an empty
/// list comes with the reason in *why (e.g. "clGetPlatformIDs: CL_PLATFORM_NOT_FOUND_KHR (-1001)").
std::vector<OpenCLDeviceInfo> listOpenCLDevices(std::string* why = nullptr);

/// Picks a device: "" = first GPU, else first CPU, else the first device; "<k>" (digits) =
/// device k of listOpenCLDevices; anything else = the first device whose name (or platform
/// name) contains the string, ignoring case. Throws OpenCLError listing the devices when
/// nothing matches or no device exists.
OpenCLDeviceInfo selectOpenCLDevice(const std::string& device);

/// On-disk cache of program binaries. dir "" = $XDG_CACHE_HOME/smoothforce/cl, else
/// ~/.cache/smoothforce/cl. Read and write failures are not fatal (they are noted in
/// BuiltProgram::cacheNote and the source build is used).
struct ProgramCacheOptions {
  bool enabled = true;
  std::string dir;
};
/// The directory ProgramCacheOptions{.dir = ""} resolves to; "" when neither
/// $XDG_CACHE_HOME nor $HOME is set.
std::string defaultProgramCacheDir();

/// A built program and how it was obtained.
struct BuiltProgram {
  cl::Program program;
  double buildSeconds = 0;  ///< wall time of create + build (from binary or source), s
  bool fromCache = false;   ///< loaded from the binary cache
  std::string cacheFile;    ///< cache file used or written ("" when the cache is off)
  std::string cacheNote;    ///< why the cache was not used or not written ("" when fine)
};

/// A device, its context and one in-order queue with profiling enabled. Every OpenCLContext of
/// one device in a process shares that device's context (created on first use, kept until the
/// process exits); each has its own queue.
class OpenCLContext {
 public:
  /// device: see selectOpenCLDevice. Throws OpenCLError.
  explicit OpenCLContext(const std::string& device = "");

  const OpenCLDeviceInfo& info() const { return info_; }
  const cl::Device& device() const { return info_.device; }
  cl::Context& context() { return context_; }
  cl::CommandQueue& queue() { return queue_; }
  /// True when the device's extension string lists ext (e.g. "cl_khr_fp64").
  bool hasExtension(const std::string& ext) const;
  /// True when single-precision divide and sqrt are correctly rounded on request
  /// (CL_FP_CORRECTLY_ROUNDED_DIVIDE_SQRT, enables -cl-fp32-correctly-rounded-divide-sqrt).
  bool hasCorrectlyRoundedDivSqrt() const;

  /// Builds a program from the concatenation of `sources` with `options`, or loads it from
  /// the binary cache under the XXH64 key of (device name, device version, driver version,
  /// platform name, sources, options). Throws OpenCLError with the full build log when the
  /// build fails.
  BuiltProgram buildProgram(const std::vector<std::string>& sources, const std::string& options,
                            const ProgramCacheOptions& cache = {});

  /// The cache key of buildProgram, 16 hex digits.
  std::string programKey(const std::vector<std::string>& sources, const std::string& options) const;

 private:
  OpenCLDeviceInfo info_;
  cl::Context context_;
  cl::CommandQueue queue_;
};

/// Seconds between the start and end of a completed command (profiling queue).
double eventSeconds(const cl::Event& e);

}  // namespace sf
