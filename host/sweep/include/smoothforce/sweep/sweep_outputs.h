// SPDX-License-Identifier: Apache-2.0
// Viewer-ready per-HIP outputs of a sweep: VTK XML point clouds (.vtp) with
// real point arrays, PLY point clouds with a `quality` scalar, and NumPy arrays (.npy).
// writeSweepSummary (sweep_io.h) writes them next to summary.json; formats in docs/guide.md "Output formats".
#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <string>
#include <vector>

#include <smoothforce/base/status.h>
#include <smoothforce/sweep/sweep.h>

namespace sf {

struct SweepData;  // sweep_io.h

/// The `missed` flag of a probe: 1 when the sweep's inside test (probe_inside.h) says the HIP
/// lies inside the method's surface (SF_PROBE_INSIDE, not SF_PROBE_UNDECIDED) but the method
/// reported no contact. The single place every output reads it from.
inline uint8_t hipMissed(const HipResult& r) {
  return (r.status & (SF_PROBE_INSIDE | SF_PROBE_UNDECIDED)) == SF_PROBE_INSIDE && !r.contact ? 1 : 0;
}

/// The HIPs of one method and one depth (group) that were computed (done = 1), in HIP order,
/// with their local force-direction discontinuity.
struct HipCloud {
  const SweepData* data = nullptr;
  size_t method = 0;                  ///< index into config.methods / data->results
  std::vector<uint64_t> index;        ///< global HIP index of each point
  std::vector<double> discontinuity;  ///< rad/m per point (sweep_metrics.h); NaN where undefined
};

/// VTK XML PolyData (format 1.0, little-endian, raw appended data, UInt64 headers): one vertex
/// cell per HIP; points = HIP positions (Float64, m); point arrays `force` (Float32 x 3, N),
/// `force_magnitude` (Float32, N), `discontinuity` (Float64, rad/m, NaN without a value),
/// `contact`, `missed` (UInt8 0/1), `face` (Int32, -1 none), `status` (UInt32, SF_ST_* |
/// SF_TRACK_*), `iterations` (UInt16), `ref_distance` (Float32, m, NaN without a reference or
/// contact), `scp` (Float32 x 3, m), `hip_index` (UInt64, the HIP's index in hips.bin and the
/// .npy files). Throws InputError naming the file when it cannot be written.
void writeHipVtp(const std::string& path, const HipCloud& cloud);

/// Binary little-endian PLY: x y z (float, m), nx ny nz (the unit force direction, 0 without
/// contact), red green blue (red: discontinuity on a log scale, white at `colourRef` rad/m, full
/// red at 100 times it; blue: no contact), `quality` (float: the discontinuity in rad/m, -1
/// without a value, MeshLab's per-vertex scalar), then `element face 0` (VTK's reader needs a face
/// element). Throws InputError naming the file when it cannot be written.
void writeHipPly(const std::string& path, const HipCloud& cloud, double colourRef);

/// One field of a NumPy structured dtype: name, type string ('<f8', '|u1', ...), element count.
struct NpyField {
  std::string name, type;
  int count = 1;  ///< > 1: a sub-array of that shape, e.g. ('force', '<f4', (3,))
};
/// Writes a .npy file (format version 1.0) holding `rows` records of the packed structured dtype
/// `fields` (no padding) from `bytes` (rows * record size, little-endian). Throws InputError
/// naming the file when it cannot be written.
void writeNpy(const std::string& path, const std::vector<NpyField>& fields, uint64_t rows, const void* bytes);

/// The packed record of results_METHOD.npy (see sweepNpyFields).
size_t sweepNpyRecordSize();
/// The dtype of results_METHOD.npy: hip (<f8 x 3, m), depth (<f8, m), group (<u2, depth index),
/// force (<f4 x 3, N), force_magnitude (<f4, N), scp (<f4 x 3, m), ref_distance (<f4, m),
/// discontinuity (<f8, rad/m), face (<i4), status (<u4), iterations (<u2), contact, missed,
/// done (|u1).
std::vector<NpyField> sweepNpyFields();
/// Writes results_METHOD.npy into dir for every method: one record per HIP of the whole run in
/// hips.bin order (done = 0: not computed; its other fields are the stored zeros).
/// discontinuity[m] holds method m's per-HIP discontinuity (#HIPs, NaN where undefined).
void writeSweepNpy(const SweepData& data, const std::vector<std::vector<double>>& discontinuity,
                   const std::string& dir);

}  // namespace sf
