// SPDX-License-Identifier: Apache-2.0
// Where the closed patch surface itself is at fault: the area of folded and of
// overlapping patch surface, where no nearest-point rule can render a consistent force.
#pragma once

#include <Eigen/Core>
#include <array>
#include <cstddef>
#include <cstdint>
#include <vector>

namespace sf {

class PatchSurface;

/// What the winding number says on either side of one triangle of the uniform tessellation.
enum class SurfaceVerdict : uint8_t {
  Consistent = 0,  ///< 0 in front (along the normal), 1 behind: the sheet separates outside from inside
  Folded,          ///< more winding in front than behind: the sheet faces into the solid (turned over)
  Overlapping,     ///< one less in front, but not 0 / 1: a sheet inside the solid or outside it
  Thin,            ///< the same on both sides: another sheet lies within the probe offset (a fold
                   ///< thinner than the offset), or a ray miscounted
  Degenerate,      ///< zero or non-finite area: not probed
};

/// Surface faults of a closed patch surface, measured on PatchSurface's uniform tessellation.
/// Areas in m^2 (of tessellation triangles), per verdict; the faces' arrays are #F.
struct SurfaceFaults {
  bool closed = false;    ///< false: not closed (a boundary edge or a face without patch): no inside, nothing measured
  int level = 0;          ///< level of the uniform tessellation probed
  double offset = 0;      ///< m: probe distance either side of a triangle (1e-5 x the diagonal)
  int64_t triangles = 0;  ///< probed (non-degenerate) triangles
  int64_t count[5] = {0, 0, 0, 0, 0};  ///< triangles per SurfaceVerdict
  double area[5] = {0, 0, 0, 0, 0};    ///< m^2 per SurfaceVerdict (Degenerate: 0)
  double totalArea = 0;                ///< m^2, of the probed triangles
  std::vector<double> faceFault;       ///< #F: m^2 of each face's triangles that are not Consistent
  std::vector<SurfaceVerdict> verdict;  ///< per uniform triangle (PatchSurface::uniform().tri order)

  /// m^2 of every triangle that is not Consistent (Folded + Overlapping + Thin).
  double faultArea() const { return area[1] + area[2] + area[3]; }
  /// Faces with fault area, largest first.
  std::vector<int> faultFaces() const;
};

/// Probes every triangle t of surface.uniform() (closed surfaces only): with c its centroid, n
/// its unit normal (the patch's outward side) and h = offset, w+ = winding(c + h n) and w- =
/// winding(c - h n) (PatchSurface::winding: the tessellation's winding number, majority of
/// three rays) give t's verdict (Consistent iff w+ = 0 and w- = 1). The fault area approximates
/// the folded and overlapping patch surface within the tessellation's error: the region where
/// the side of the nearest patch point and the winding number disagree, so where a HIP's contact
/// is decided by the winding number, not by the nearest sheet (insidePatchSurface). Runs in
/// parallel (oneTBB); sums in triangle order (the same result for any thread count).
SurfaceFaults measureSurfaceFaults(const PatchSurface& surface);

/// The probe distance of measureSurfaceFaults, m: 1e-5 x the bounding-box diagonal of the
/// surface's cache (scans every vertex: take it once).
double surfaceProbeOffset(const PatchSurface& surface);

/// The verdict of triangle t of surface.uniform() as measureSurfaceFaults gives it, probed at
/// offset h (surfaceProbeOffset), and twice the triangle's area (m^2) in *area2. Closed
/// surfaces only; t < surface.uniform().tri.size().
SurfaceVerdict triangleVerdict(const PatchSurface& surface, size_t t, double h, double* area2) noexcept;

/// The corners (m) of the triangles of surface.uniform() that faults (measured on that surface)
/// found neither Consistent nor Degenerate, in triangle order.
std::vector<std::array<Eigen::Vector3d, 3>> faultTriangles(const PatchSurface& surface, const SurfaceFaults& faults);

/// The fault area split by cause. The input's own: fault triangles on faces within reach of
/// intersecting polygons (`nearIntersections`, #F, from facesNearIntersections in
/// mesh_intersect.h: a face of an intersecting pair or one sharing a vertex with it), where no
/// surface through the mesh's vertices can be free of faults. The construction's: the rest.
/// Areas in m^2 (sums of SurfaceFaults::faceFault; together faultArea() up to rounding); faces
/// with fault area, largest first. Faults on self-crossing polygons count as the construction's
/// unless within reach of an intersection (a split of such a polygon can remove them).
struct FaultAttribution {
  double inputArea = 0, constructionArea = 0;
  std::vector<int> inputFaces, constructionFaces;
};

/// Splits `faults` by `nearIntersections` (#F; an empty vector: every fault is the
/// construction's). Throws std::invalid_argument when its size is neither 0 nor #F.
FaultAttribution attributeFaults(const SurfaceFaults& faults, const std::vector<char>& nearIntersections);

/// "consistent", "folded", "overlapping", "thin", "degenerate".
const char* toString(SurfaceVerdict v);

}  // namespace sf
