// SPDX-License-Identifier: Apache-2.0
// Status bits of SmoothForce, in one place: the SF_ST_* bits of patch construction and
// evaluation (PatchCache::faceStatus, PatchPoint::status), the SF_TRACK_* bits that
// refinement and every force method add (RefineResult::status, ForceSample::status), and the
// SF_PROBE_* bits of a sweep's probe record (HipResult::status).
// The shared patch math (kernels/gp_config.h) spells the first two GP_ST_* and GP_TRACK_*;
// status.cpp asserts at compile time that the values are equal.
//
// Why base holds bits that upper modules set (SF_TRACK_PROXY_LIMIT: the god-object, force/;
// SF_PROBE_*: the sweep's inside test, sweep/): all of them share one 32-bit word (a probe
// record carries its force sample's bits), so they are allocated in one table, where their
// ranges are seen to be disjoint; and kStatusBits, the registry that the Python module and the
// C API publish, must name every bit, while the C API may not include sweep/ (layer table,
// docs/design.md). Only the values live here; what each bit means is documented beside the code
// that sets it (god_object.h, probe_inside.h).
#pragma once

#include <cstdint>

namespace sf {

/// SF_ST_* bits (= GP_ST_*): per patch (construction, quality) and per evaluated point.
inline constexpr uint32_t SF_ST_GUARD = 0x1u;             ///< a backward end tangent was replaced (guard 1)
inline constexpr uint32_t SF_ST_ZERO_EDGE = 0x2u;         ///< an edge of (near) zero length
inline constexpr uint32_t SF_ST_EDGE_NORMAL = 0x4u;       ///< n_c or an end tangent undefined; fallback used
inline constexpr uint32_t SF_ST_CROSS_TANGENT = 0x8u;     ///< cross tangent undefined; fallback used
inline constexpr uint32_t SF_ST_FOLD = 0x10u;             ///< patch normal opposite to n_c near an edge
inline constexpr uint32_t SF_ST_BULGE = 0x20u;            ///< surface leaves the face box by > 0.5 face diameters
inline constexpr uint32_t SF_ST_OUTSIDE = 0x40u;          ///< evaluation point outside the domain
inline constexpr uint32_t SF_ST_SINGULAR = 0x80u;         ///< dG/dxi x dG/deta vanishes; normal is a fallback
inline constexpr uint32_t SF_ST_TOO_MANY_SIDES = 0x100u;  ///< n > 64 or n < 3: not built
inline constexpr uint32_t SF_ST_NONFINITE = 0x200u;       ///< non-finite input
/// the SCP, derivatives and normal come from the refinement's quadratic model at the SCP's domain
/// point, not from an evaluation of the patch (RefineOptions::finalStep = FinalStep::Model)
inline constexpr uint32_t SF_ST_MODEL_POINT = 0x400u;
/// the patch is its flat triangle's affine map plus its curved edges' deviations from their chords:
/// every corner normal the plane's, the edge curves in it, the map proven regular (the default
/// construction, markAffineTriangles: the same boundary, never folded)
inline constexpr uint32_t SF_ST_AFFINE = 0x800u;
/// The most sides a polygon's patch can have (GP_MAX_N); larger faces get no patch.
inline constexpr int SF_MAX_PATCH_SIDES = 64;
/// The bits that make a patch degenerate (its surface is a fallback or missing).
inline constexpr uint32_t SF_ST_DEGENERATE_MASK =
    SF_ST_ZERO_EDGE | SF_ST_EDGE_NORMAL | SF_ST_CROSS_TANGENT | SF_ST_TOO_MANY_SIDES | SF_ST_NONFINITE;

/// SF_TRACK_* bits: 0x10000 .. 0x10000000, above the SF_ST_* bits (0x1 .. 0x800), which
/// ForceSample::status also carries (the patch's construction and evaluation bits).
/// CONVERGED .. DEGENERATE and FOLD_EDGE equal the refinement's GP_TRACK_* (kernels/gp_config.h).
inline constexpr uint32_t SF_TRACK_CONVERGED = 0x10000u;  ///< refinement met the tolerances
inline constexpr uint32_t SF_TRACK_MAX_ITER = 0x20000u;   ///< refinement hit maxIterations
inline constexpr uint32_t SF_TRACK_STALLED = 0x40000u;    ///< no step could decrease the distance before the tolerance
inline constexpr uint32_t SF_TRACK_BOUNDARY = 0x80000u;   ///< iterate held on a boundary / non-manifold edge
inline constexpr uint32_t SF_TRACK_DEGENERATE = 0x100000u;    ///< patch not evaluable: polygon used instead
inline constexpr uint32_t SF_TRACK_GLOBAL = 0x200000u;        ///< a global query ran this step
inline constexpr uint32_t SF_TRACK_ENTER = 0x400000u;         ///< contact began this step
inline constexpr uint32_t SF_TRACK_LEAVE = 0x800000u;         ///< contact ended this step
inline constexpr uint32_t SF_TRACK_NO_POLYGON = 0x1000000u;   ///< the mesh has no polygon
/// a HIP not finite or beyond the coordinate range (coordinate_range.h): ignored, state reset
inline constexpr uint32_t SF_TRACK_BAD_HIP = 0x2000000u;
inline constexpr uint32_t SF_TRACK_PROXY_LIMIT = 0x4000000u;  ///< god-object: > 3 constraints or pass limit
inline constexpr uint32_t SF_TRACK_INSIDE = 0x8000000u;       ///< contact started: the HIP is inside the surface
/// the SCP is held on a patch edge where the surface turns back on the HIP's side: a fold of the
/// surface, or a crease edge at a valley whose curve is the nearest point of a wedge of HIPs;
/// stationary along the edge, and no nearer point lies into the face
inline constexpr uint32_t SF_TRACK_FOLD_EDGE = 0x10000000u;
inline constexpr uint32_t SF_TRACK_MASK = 0x1FFF0000u;

/// SF_PROBE_* bits: set by sweeps in a probe's record (HipResult::status), never by a force
/// method: the verdict of the sweep's own inside test on the HIP (sweep/probe_inside.h), independent of
/// the method's tracking. A probe is a missed contact when INSIDE is set and it has no contact.
inline constexpr uint32_t SF_PROBE_INSIDE = 0x20000000u;  ///< the HIP is inside the method's surface
inline constexpr uint32_t SF_PROBE_UNDECIDED =
    0x40000000u;  ///< the inside test cannot decide (open surface, error band)
/// a missed contact within reach of a surface fault of the method's surface: patch surface that
/// folds or overlaps itself (surface_faults.h) lies no farther from the HIP than its depth (its
/// distance to the surface point it was pressed in from), where no nearest-point rule renders a
/// consistent force; set on missed contacts of the patch method only
inline constexpr uint32_t SF_PROBE_ON_FAULT = 0x80000000u;
inline constexpr uint32_t SF_PROBE_MASK = 0xE0000000u;

/// A status bit's name and value: kStatusBits lists every SF_ST_*, SF_TRACK_* and SF_PROBE_* bit
/// above (the names Python's module and the C API's sf_status_bits give them).
struct StatusBit {
  const char* name;
  uint32_t value;
};
#define SF_STATUS_BIT(name) \
  StatusBit { #name, name }  // the name spelled once
inline constexpr StatusBit kStatusBits[] = {
    SF_STATUS_BIT(SF_ST_GUARD),         SF_STATUS_BIT(SF_ST_ZERO_EDGE),      SF_STATUS_BIT(SF_ST_EDGE_NORMAL),
    SF_STATUS_BIT(SF_ST_CROSS_TANGENT), SF_STATUS_BIT(SF_ST_FOLD),           SF_STATUS_BIT(SF_ST_BULGE),
    SF_STATUS_BIT(SF_ST_OUTSIDE),       SF_STATUS_BIT(SF_ST_SINGULAR),       SF_STATUS_BIT(SF_ST_TOO_MANY_SIDES),
    SF_STATUS_BIT(SF_ST_NONFINITE),     SF_STATUS_BIT(SF_ST_MODEL_POINT),    SF_STATUS_BIT(SF_ST_AFFINE),
    SF_STATUS_BIT(SF_TRACK_CONVERGED),  SF_STATUS_BIT(SF_TRACK_MAX_ITER),    SF_STATUS_BIT(SF_TRACK_STALLED),
    SF_STATUS_BIT(SF_TRACK_BOUNDARY),   SF_STATUS_BIT(SF_TRACK_DEGENERATE),  SF_STATUS_BIT(SF_TRACK_GLOBAL),
    SF_STATUS_BIT(SF_TRACK_ENTER),      SF_STATUS_BIT(SF_TRACK_LEAVE),       SF_STATUS_BIT(SF_TRACK_NO_POLYGON),
    SF_STATUS_BIT(SF_TRACK_BAD_HIP),    SF_STATUS_BIT(SF_TRACK_PROXY_LIMIT), SF_STATUS_BIT(SF_TRACK_INSIDE),
    SF_STATUS_BIT(SF_TRACK_FOLD_EDGE),  SF_STATUS_BIT(SF_PROBE_INSIDE),      SF_STATUS_BIT(SF_PROBE_UNDECIDED),
    SF_STATUS_BIT(SF_PROBE_ON_FAULT),
};
#undef SF_STATUS_BIT

}  // namespace sf
