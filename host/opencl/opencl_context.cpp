// SPDX-License-Identifier: Apache-2.0
#include <smoothforce/opencl/opencl_context.h>

#include <unistd.h>
#include <xxhash.h>

#include <algorithm>
#include <cctype>
#include <chrono>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <mutex>
#include <sstream>

#include <smoothforce/base/hash.h>

namespace sf {

const char* clErrorName(int code) {
  switch (code) {
#define SF_CL_ERR(name) \
  case name:            \
    return #name;
    SF_CL_ERR(CL_SUCCESS)
    SF_CL_ERR(CL_DEVICE_NOT_FOUND)
    SF_CL_ERR(CL_DEVICE_NOT_AVAILABLE)
    SF_CL_ERR(CL_COMPILER_NOT_AVAILABLE)
    SF_CL_ERR(CL_MEM_OBJECT_ALLOCATION_FAILURE)
    SF_CL_ERR(CL_OUT_OF_RESOURCES)
    SF_CL_ERR(CL_OUT_OF_HOST_MEMORY)
    SF_CL_ERR(CL_PROFILING_INFO_NOT_AVAILABLE)
    SF_CL_ERR(CL_MEM_COPY_OVERLAP)
    SF_CL_ERR(CL_IMAGE_FORMAT_MISMATCH)
    SF_CL_ERR(CL_IMAGE_FORMAT_NOT_SUPPORTED)
    SF_CL_ERR(CL_BUILD_PROGRAM_FAILURE)
    SF_CL_ERR(CL_MAP_FAILURE)
    SF_CL_ERR(CL_MISALIGNED_SUB_BUFFER_OFFSET)
    SF_CL_ERR(CL_EXEC_STATUS_ERROR_FOR_EVENTS_IN_WAIT_LIST)
    SF_CL_ERR(CL_COMPILE_PROGRAM_FAILURE)
    SF_CL_ERR(CL_LINKER_NOT_AVAILABLE)
    SF_CL_ERR(CL_LINK_PROGRAM_FAILURE)
    SF_CL_ERR(CL_DEVICE_PARTITION_FAILED)
    SF_CL_ERR(CL_KERNEL_ARG_INFO_NOT_AVAILABLE)
    SF_CL_ERR(CL_INVALID_VALUE)
    SF_CL_ERR(CL_INVALID_DEVICE_TYPE)
    SF_CL_ERR(CL_INVALID_PLATFORM)
    SF_CL_ERR(CL_INVALID_DEVICE)
    SF_CL_ERR(CL_INVALID_CONTEXT)
    SF_CL_ERR(CL_INVALID_QUEUE_PROPERTIES)
    SF_CL_ERR(CL_INVALID_COMMAND_QUEUE)
    SF_CL_ERR(CL_INVALID_HOST_PTR)
    SF_CL_ERR(CL_INVALID_MEM_OBJECT)
    SF_CL_ERR(CL_INVALID_IMAGE_FORMAT_DESCRIPTOR)
    SF_CL_ERR(CL_INVALID_IMAGE_SIZE)
    SF_CL_ERR(CL_INVALID_SAMPLER)
    SF_CL_ERR(CL_INVALID_BINARY)
    SF_CL_ERR(CL_INVALID_BUILD_OPTIONS)
    SF_CL_ERR(CL_INVALID_PROGRAM)
    SF_CL_ERR(CL_INVALID_PROGRAM_EXECUTABLE)
    SF_CL_ERR(CL_INVALID_KERNEL_NAME)
    SF_CL_ERR(CL_INVALID_KERNEL_DEFINITION)
    SF_CL_ERR(CL_INVALID_KERNEL)
    SF_CL_ERR(CL_INVALID_ARG_INDEX)
    SF_CL_ERR(CL_INVALID_ARG_VALUE)
    SF_CL_ERR(CL_INVALID_ARG_SIZE)
    SF_CL_ERR(CL_INVALID_KERNEL_ARGS)
    SF_CL_ERR(CL_INVALID_WORK_DIMENSION)
    SF_CL_ERR(CL_INVALID_WORK_GROUP_SIZE)
    SF_CL_ERR(CL_INVALID_WORK_ITEM_SIZE)
    SF_CL_ERR(CL_INVALID_GLOBAL_OFFSET)
    SF_CL_ERR(CL_INVALID_EVENT_WAIT_LIST)
    SF_CL_ERR(CL_INVALID_EVENT)
    SF_CL_ERR(CL_INVALID_OPERATION)
    SF_CL_ERR(CL_INVALID_GL_OBJECT)
    SF_CL_ERR(CL_INVALID_BUFFER_SIZE)
    SF_CL_ERR(CL_INVALID_MIP_LEVEL)
    SF_CL_ERR(CL_INVALID_GLOBAL_WORK_SIZE)
    SF_CL_ERR(CL_INVALID_PROPERTY)
    SF_CL_ERR(CL_INVALID_IMAGE_DESCRIPTOR)
    SF_CL_ERR(CL_INVALID_COMPILER_OPTIONS)
    SF_CL_ERR(CL_INVALID_LINKER_OPTIONS)
    SF_CL_ERR(CL_INVALID_DEVICE_PARTITION_COUNT)
#undef SF_CL_ERR
    case -1001:
      return "CL_PLATFORM_NOT_FOUND_KHR";
    default:
      return "CL_UNKNOWN_ERROR";
  }
}

void throwOpenCL(const std::string& where, const std::string& call, int code, const std::string& detail) {
  std::ostringstream os;
  os << where << ": " << call << " failed: " << clErrorName(code) << " (" << code << ")" << detail;
  throw OpenCLError(os.str(), code);
}

void rethrowOpenCL(const std::string& where, const cl::Error& e) {
  throwOpenCL(where, e.what() ? e.what() : "OpenCL call", e.err());
}

namespace {

std::string lower(std::string s) {
  std::transform(s.begin(), s.end(), s.begin(), [](unsigned char c) { return std::tolower(c); });
  return s;
}

std::string trim(std::string s) {
  while (!s.empty() && (s.back() == '\0' || std::isspace(static_cast<unsigned char>(s.back())))) s.pop_back();
  return s;
}

/// The devices on one line (an error message is one line): "0: name [platform]; 1: ...".
std::string describe(const std::vector<OpenCLDeviceInfo>& all) {
  std::ostringstream os;
  for (const auto& d : all)
    os << (d.index > 0 ? "; " : "") << d.index << ": " << d.name << " [" << d.platformName << "]";
  return os.str();
}

}  // namespace

std::vector<OpenCLDeviceInfo> listOpenCLDevices(std::string* why) {
  std::vector<OpenCLDeviceInfo> all;
  std::vector<cl::Platform> platforms;
  try {
    cl::Platform::get(&platforms);
  } catch (const cl::Error& e) {
    if (why) *why = std::string(e.what()) + ": " + clErrorName(e.err()) + " (" + std::to_string(e.err()) + ")";
    return all;
  }
  for (const auto& p : platforms) {
    std::vector<cl::Device> devs;
    try {
      p.getDevices(CL_DEVICE_TYPE_ALL, &devs);
    } catch (const cl::Error&) {
      continue;  // a platform without devices (CL_DEVICE_NOT_FOUND)
    }
    for (const auto& d : devs) {
      OpenCLDeviceInfo info;
      try {
        info.index = static_cast<int>(all.size());
        info.name = trim(d.getInfo<CL_DEVICE_NAME>());
        info.platformName = trim(p.getInfo<CL_PLATFORM_NAME>());
        info.version = trim(d.getInfo<CL_DEVICE_VERSION>());
        info.driverVersion = trim(d.getInfo<CL_DRIVER_VERSION>());
        info.extensions = trim(d.getInfo<CL_DEVICE_EXTENSIONS>());
        info.type = d.getInfo<CL_DEVICE_TYPE>();
      } catch (const cl::Error&) {
        continue;
      }
      info.device = d;
      info.platform = p;
      all.push_back(std::move(info));
    }
  }
  if (all.empty() && why) *why = "no OpenCL device on any of " + std::to_string(platforms.size()) + " platform(s)";
  return all;
}

OpenCLDeviceInfo selectOpenCLDevice(const std::string& device) {
  std::string why;
  const auto all = listOpenCLDevices(&why);
  if (all.empty()) throw OpenCLError("no OpenCL device: " + why, CL_DEVICE_NOT_FOUND);
  if (device.empty()) {
    for (cl_device_type t : {cl_device_type(CL_DEVICE_TYPE_GPU), cl_device_type(CL_DEVICE_TYPE_CPU)})
      for (const auto& d : all)
        if (d.type & t) return d;
    return all.front();
  }
  if (std::all_of(device.begin(), device.end(), [](unsigned char c) { return std::isdigit(c); })) {
    const long k = std::strtol(device.c_str(), nullptr, 10);
    if (device.size() < 6 && k < static_cast<long>(all.size())) return all[k];
  } else {
    const std::string want = lower(device);
    for (const auto& d : all)
      if (lower(d.name).find(want) != std::string::npos) return d;
    for (const auto& d : all)
      if (lower(d.platformName).find(want) != std::string::npos) return d;
  }
  throw OpenCLError("OpenCL device '" + device + "' not found (devices: " + describe(all) + ")", CL_DEVICE_NOT_FOUND);
}

std::string defaultProgramCacheDir() {
  if (const char* x = std::getenv("XDG_CACHE_HOME"); x && *x) return std::string(x) + "/smoothforce/cl";
  if (const char* h = std::getenv("HOME"); h && *h) return std::string(h) + "/.cache/smoothforce/cl";
  return "";
}

double eventSeconds(const cl::Event& e) {
  const cl_ulong a = e.getProfilingInfo<CL_PROFILING_COMMAND_START>();
  const cl_ulong b = e.getProfilingInfo<CL_PROFILING_COMMAND_END>();
  return b > a ? static_cast<double>(b - a) * 1e-9 : 0.0;
}

namespace {
/// One context per device for the whole process: creating one is slow on some drivers (a CUDA
/// context behind each on NVIDIA's), and a sweep's constructor, refiner and candidate search each
/// hold an OpenCLContext. Kept until the process exits (never released: drivers may unload before
/// static destructors run).
cl::Context sharedContext(const cl::Device& device) {
  static std::mutex mutex;
  static auto* contexts = new std::vector<std::pair<cl_device_id, cl::Context>>();
  const std::lock_guard<std::mutex> lock(mutex);
  for (const auto& [id, c] : *contexts)
    if (id == device()) return c;
  contexts->emplace_back(device(), cl::Context(device));
  return contexts->back().second;
}
}  // namespace

OpenCLContext::OpenCLContext(const std::string& device) : info_(selectOpenCLDevice(device)) {
  try {
    context_ = sharedContext(info_.device);
    queue_ = cl::CommandQueue(context_, info_.device, CL_QUEUE_PROFILING_ENABLE);
  } catch (const cl::Error& e) {
    rethrowOpenCL("OpenCL context on " + info_.name, e);
  }
}

bool OpenCLContext::hasExtension(const std::string& ext) const {
  std::istringstream is(info_.extensions);
  std::string w;
  while (is >> w)
    if (w == ext) return true;
  return false;
}

bool OpenCLContext::hasCorrectlyRoundedDivSqrt() const {
  try {
    return (info_.device.getInfo<CL_DEVICE_SINGLE_FP_CONFIG>() & CL_FP_CORRECTLY_ROUNDED_DIVIDE_SQRT) != 0;
  } catch (const cl::Error&) {
    return false;
  }
}

std::string OpenCLContext::programKey(const std::vector<std::string>& sources, const std::string& options) const {
  XXH64_state_t* st = XXH64_createState();
  XXH64_reset(st, 0);
  auto add = [&](const std::string& s) {  // length-prefixed, so fields cannot run together
    const uint64_t n = s.size();
    XXH64_update(st, &n, sizeof n);
    XXH64_update(st, s.data(), s.size());
  };
  add(info_.name);
  add(info_.version);
  add(info_.driverVersion);
  add(info_.platformName);
  for (const auto& s : sources) add(s);
  add(options);
  const uint64_t h = XXH64_digest(st);
  XXH64_freeState(st);
  return hexHash(h);
}

namespace {

/// Tries the cached binary; returns an empty program (and a note) when it cannot be used.
cl::Program loadCached(cl::Context& ctx, const cl::Device& dev, const std::string& file, const std::string& options,
                       std::string& note) {
  std::ifstream in(file, std::ios::binary);
  if (!in) return {};  // not cached yet: no note
  std::vector<unsigned char> bin((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  if (bin.empty()) {
    note = "empty cache file " + file;
    return {};
  }
  try {
    cl::Program p(ctx, {dev}, cl::Program::Binaries{bin});
    p.build({dev}, options.c_str());
    return p;
  } catch (const cl::Error& e) {
    note = "cached binary " + file + " rejected (" + e.what() + ": " + clErrorName(e.err()) + "); rebuilt";
    return {};
  }
}

void storeCached(const cl::Program& p, const std::string& dir, const std::string& file, std::string& note) {
  try {
    const auto bins = p.getInfo<CL_PROGRAM_BINARIES>();
    if (bins.size() != 1 || bins[0].empty()) {
      note = "device returned no program binary; not cached";
      return;
    }
    std::error_code ec;
    std::filesystem::create_directories(dir, ec);
    // write to a unique temporary, then rename: concurrent readers never see a partial file
    const std::string tmp = file + ".tmp" + std::to_string(::getpid());
    {
      std::ofstream out(tmp, std::ios::binary | std::ios::trunc);
      out.write(reinterpret_cast<const char*>(bins[0].data()), static_cast<std::streamsize>(bins[0].size()));
      if (!out) {
        note = "cannot write " + tmp;
        std::filesystem::remove(tmp, ec);
        return;
      }
    }
    std::filesystem::rename(tmp, file, ec);
    if (ec) {
      note = "cannot rename " + tmp + ": " + ec.message();
      std::filesystem::remove(tmp, ec);
    }
  } catch (const cl::Error& e) {
    note = std::string("reading the program binary failed: ") + e.what() + ": " + clErrorName(e.err());
  }
}

}  // namespace

BuiltProgram OpenCLContext::buildProgram(const std::vector<std::string>& sources, const std::string& options,
                                         const ProgramCacheOptions& cache) {
  using Clock = std::chrono::steady_clock;
  const auto t0 = Clock::now();
  BuiltProgram out;
  std::string dir;
  if (cache.enabled) {
    dir = cache.dir.empty() ? defaultProgramCacheDir() : cache.dir;
    if (dir.empty())
      out.cacheNote = "no cache directory ($XDG_CACHE_HOME and $HOME unset)";
    else
      out.cacheFile = dir + "/" + programKey(sources, options) + ".bin";
  }
  if (!out.cacheFile.empty()) {
    out.program = loadCached(context_, info_.device, out.cacheFile, options, out.cacheNote);
    out.fromCache = out.program() != nullptr;
  }
  if (!out.fromCache) {
    try {
      out.program = cl::Program(context_, cl::Program::Sources(sources.begin(), sources.end()));
    } catch (const cl::Error& e) {
      rethrowOpenCL("OpenCL program for " + info_.name, e);
    }
    try {
      out.program.build({info_.device}, options.c_str());
    } catch (const cl::BuildError& e) {
      std::string log;
      for (const auto& [dev, text] : e.getBuildLog()) log += text;
      throwOpenCL("OpenCL program build for " + info_.name, e.what(), e.err(),
                  "\nbuild options: " + options + "\nbuild log:\n" + log);
    } catch (const cl::Error& e) {
      std::string log;
      try {
        log = out.program.getBuildInfo<CL_PROGRAM_BUILD_LOG>(info_.device);
      } catch (const cl::Error&) {
      }
      throwOpenCL("OpenCL program build for " + info_.name, e.what(), e.err(),
                  "\nbuild options: " + options + "\nbuild log:\n" + log);
    }
    if (!out.cacheFile.empty()) {
      std::string note;
      storeCached(out.program, dir, out.cacheFile, note);
      if (!note.empty()) out.cacheNote += (out.cacheNote.empty() ? "" : "; ") + note;
    }
  }
  out.buildSeconds = std::chrono::duration<double>(Clock::now() - t0).count();
  return out;
}

}  // namespace sf
