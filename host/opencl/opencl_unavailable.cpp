// SPDX-License-Identifier: Apache-2.0
// The OpenCL backend's public API in a CPU-only build (SF_WITH_OPENCL=OFF, or no OpenCL
// found at configure time): openclAvailable() is false and says why; every other entry
// point throws InputError, so that `--backend opencl` fails with one clear line instead of a
// link error or a crash. The classes can never be constructed, so their other members are
// unreachable and throw the same error.
#include <smoothforce/base/error.h>
#include <smoothforce/opencl/opencl_backend.h>
#include <smoothforce/opencl/opencl_candidates.h>
#include <smoothforce/opencl/opencl_refine.h>

namespace sf {

namespace {

constexpr const char* kWhy =
    "SmoothForce was built without OpenCL (CPU-only: SF_WITH_OPENCL=OFF or no OpenCL at configure time)";

[[noreturn]] void unavailable(const char* what) { throw InputError(std::string(what) + ": " + kWhy); }

}  // namespace

bool openclAvailable(std::string* why) {
  if (why) *why = kWhy;
  return false;
}

struct OpenCLConstructor::Impl {};
OpenCLConstructor::OpenCLConstructor(const OpenCLOptions&) { unavailable("OpenCL construction"); }
OpenCLConstructor::~OpenCLConstructor() = default;
OpenCLConstructor::OpenCLConstructor(OpenCLConstructor&&) noexcept = default;
OpenCLConstructor& OpenCLConstructor::operator=(OpenCLConstructor&&) noexcept = default;
void OpenCLConstructor::construct(PatchCache&) { unavailable("OpenCL construction"); }
std::string OpenCLConstructor::deviceName() const { unavailable("OpenCL construction"); }
double OpenCLConstructor::buildSeconds() const { unavailable("OpenCL construction"); }
bool OpenCLConstructor::programFromCache() const { unavailable("OpenCL construction"); }
double OpenCLConstructor::lastKernelSeconds() const { unavailable("OpenCL construction"); }
double OpenCLConstructor::lastTransferSeconds() const { unavailable("OpenCL construction"); }
size_t OpenCLConstructor::workGroupSize() const { unavailable("OpenCL construction"); }

void constructPatchesOpenCL(PatchCache&, const OpenCLOptions&) { unavailable("OpenCL construction"); }

struct OpenCLEvaluator::Impl {};
OpenCLEvaluator::OpenCLEvaluator(const PatchCache&, const OpenCLOptions&) { unavailable("OpenCL evaluation"); }
OpenCLEvaluator::~OpenCLEvaluator() = default;
OpenCLEvaluator::OpenCLEvaluator(OpenCLEvaluator&&) noexcept = default;
OpenCLEvaluator& OpenCLEvaluator::operator=(OpenCLEvaluator&&) noexcept = default;
void OpenCLEvaluator::setCache(const PatchCache&) { unavailable("OpenCL evaluation"); }
void OpenCLEvaluator::evaluate(const int32_t*, const double*, const double*, size_t, PatchPoint*) {
  unavailable("OpenCL evaluation");
}
void OpenCLEvaluator::evaluate(const int32_t*, const float*, const float*, size_t, PatchPoint*) {
  unavailable("OpenCL evaluation");
}
Precision OpenCLEvaluator::precision() const { unavailable("OpenCL evaluation"); }
std::string OpenCLEvaluator::deviceName() const { unavailable("OpenCL evaluation"); }
size_t OpenCLEvaluator::capacity() const { unavailable("OpenCL evaluation"); }
size_t OpenCLEvaluator::allocations() const { unavailable("OpenCL evaluation"); }
double OpenCLEvaluator::buildSeconds() const { unavailable("OpenCL evaluation"); }
bool OpenCLEvaluator::programFromCache() const { unavailable("OpenCL evaluation"); }
double OpenCLEvaluator::uploadSeconds() const { unavailable("OpenCL evaluation"); }
double OpenCLEvaluator::lastKernelSeconds() const { unavailable("OpenCL evaluation"); }
double OpenCLEvaluator::lastTransferSeconds() const { unavailable("OpenCL evaluation"); }
double OpenCLEvaluator::lastHostSeconds() const { unavailable("OpenCL evaluation"); }
size_t OpenCLEvaluator::workGroupSize() const { unavailable("OpenCL evaluation"); }

void evaluatePatchesOpenCL(const PatchCache&, const int32_t*, const double*, const double*, size_t, PatchPoint*,
                           const OpenCLOptions&) {
  unavailable("OpenCL evaluation");
}

struct OpenCLRefiner::Impl {};
OpenCLRefiner::OpenCLRefiner(const PatchCache&, const OpenCLOptions&) { unavailable("OpenCL refinement"); }
OpenCLRefiner::~OpenCLRefiner() = default;
OpenCLRefiner::OpenCLRefiner(OpenCLRefiner&&) noexcept = default;
OpenCLRefiner& OpenCLRefiner::operator=(OpenCLRefiner&&) noexcept = default;
void OpenCLRefiner::refine(const RefineQuery*, size_t, const RefineOptions&, RefineResult*) {
  unavailable("OpenCL refinement");
}
Precision OpenCLRefiner::precision() const { unavailable("OpenCL refinement"); }
std::string OpenCLRefiner::deviceName() const { unavailable("OpenCL refinement"); }
double OpenCLRefiner::buildSeconds() const { unavailable("OpenCL refinement"); }
double OpenCLRefiner::uploadSeconds() const { unavailable("OpenCL refinement"); }
double OpenCLRefiner::lastKernelSeconds() const { unavailable("OpenCL refinement"); }
double OpenCLRefiner::lastTransferSeconds() const { unavailable("OpenCL refinement"); }
size_t OpenCLRefiner::workGroupSize() const { unavailable("OpenCL refinement"); }

void refineNearestPointsOpenCL(const PatchCache&, const RefineQuery*, size_t, const RefineOptions&, RefineResult*,
                               const OpenCLOptions&) {
  unavailable("OpenCL refinement");
}

struct OpenCLCandidateSearch::Impl {};
OpenCLCandidateSearch::OpenCLCandidateSearch(const PatchSurface&, const OpenCLOptions&) {
  unavailable("OpenCL candidate search");
}
OpenCLCandidateSearch::~OpenCLCandidateSearch() = default;
bool OpenCLCandidateSearch::usable() const { unavailable("OpenCL candidate search"); }
void OpenCLCandidateSearch::search(const Eigen::Vector3d*, size_t, int, int32_t*, uint32_t*, std::vector<int32_t>&) {
  unavailable("OpenCL candidate search");
}
std::string OpenCLCandidateSearch::deviceName() const { unavailable("OpenCL candidate search"); }
size_t OpenCLCandidateSearch::numNodes() const { unavailable("OpenCL candidate search"); }
size_t OpenCLCandidateSearch::numTriangles() const { unavailable("OpenCL candidate search"); }
double OpenCLCandidateSearch::lastKernelSeconds() const { unavailable("OpenCL candidate search"); }
double OpenCLCandidateSearch::lastTransferSeconds() const { unavailable("OpenCL candidate search"); }

}  // namespace sf
