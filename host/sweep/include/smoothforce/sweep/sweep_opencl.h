// Sweep probes of the patch method with the refinement on an OpenCL device (issue 5):
// `smoothforce sweep --backend opencl`.
#pragma once

#include <memory>

#include <smoothforce/opencl/opencl_backend.h>
#include <smoothforce/sweep/sweep.h>

namespace sf {

/// runProbes for the patch method with every refinement of a chunk of HIPs in one kernel run
/// (OpenCLRefiner); the global queries (Embree nearest polygon point + mean value
/// coordinates) and the contact decisions run on the CPU in oneTBB tasks, through the same
/// beginPatchStep / finishPatchStep as the CPU tracker. Per HIP, as runProbes: reset,
/// step(approach), step(hip); out[g - begin] gets the second step. Chunks of `chunk` HIPs;
/// control.stop is checked and control.progress called per chunk. Returns the HIPs done.
/// Throws InputError for invalid options or RefineMethod::PaperDescent (Newton only on the
/// device), OpenCLError for device failures.
size_t runPatchProbesOpenCL(const HipSet& set, size_t begin, size_t end, std::shared_ptr<const PatchCache> cache,
                            const ForceOptions& options, const ReferenceSurface* ref, HipResult* out,
                            const SweepControl& control, const OpenCLOptions& opencl = {}, size_t chunk = 1 << 16);

}  // namespace sf
