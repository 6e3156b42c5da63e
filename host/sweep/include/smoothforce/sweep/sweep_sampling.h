// SPDX-License-Identifier: Apache-2.0
// Haptic interface points (HIPs) for force sweeps: surface samples uniform by area, depths,
// HIP files, and the nearest patch point of arbitrary points (trajectories, HIP files).
#pragma once

#include <Eigen/Core>
#include <array>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include <smoothforce/patch/patch_cache.h>
#include <smoothforce/sweep/sweep_reference.h>

namespace sf {

/// A point on the surface and its unit outward normal; face/xi/eta locate it on a patch
/// (face -1 when it comes from a triangle mesh).
struct SurfaceSample {
  Eigen::Vector3d point{0, 0, 0}, normal{0, 0, 0};
  int face = -1;
  double xi = 0, eta = 0;
};

/// A depth as given: metres ("0.002") or percent of the bounding-box diagonal ("2%").
struct DepthSpec {
  std::string label;  ///< as typed, e.g. "2%"
  double value = 0;   ///< metres, or percent when relative
  bool relative = false;
  double metres(double diagonal) const { return relative ? value * 0.01 * diagonal : value; }
};
/// Parses "2%,4%" or "0.002,0.004" (decimal or exponent numbers, an optional '+'); throws
/// InputError for an empty list, a malformed (hex included) or non-positive value, and a depth
/// listed twice, naming `option` (the command-line option or field the text came from).
std::vector<DepthSpec> parseDepthList(const std::string& text, const std::string& option = "--depth");
/// A file-name-safe form of a depth label: "2%" -> "2pct", "0.002" -> "0.002m".
std::string depthTag(const std::string& label);

/// The patches split into small triangles (each polygon edge in `level`), the triangles'
/// 3-D areas as sampling weights. Samples: a triangle by area, then a uniform barycentric point
/// in that triangle's DOMAIN coordinates, evaluated exactly on the patch (point and normal).
/// Memory: 8 bytes per small triangle (the cumulative areas; n L^2 per n-gon), the domain
/// triangles kept once per polygon size.
class PatchSurfaceSampler {
 public:
  /// Throws InputError when no patch can be evaluated or level is outside [1, 64].
  PatchSurfaceSampler(const PatchCache& cache, int level = 8);
  /// n samples from a std::mt19937_64 seeded with `seed`; deterministic for (cache, level, n,
  /// seed) whatever the thread count. Points whose evaluation fails are redrawn.
  std::vector<SurfaceSample> sample(size_t n, uint64_t seed) const;
  /// Sum of the small triangles' areas, m^2.
  double area() const { return area_; }

 private:
  const PatchCache& cache_;
  std::vector<int32_t> faces_;                     ///< the built faces, in order
  std::vector<size_t> first_;                      ///< #faces_ + 1: each one's first small triangle
  std::vector<std::vector<Eigen::Vector2d>> dom_;  ///< per polygon size n: 3 domain corners per small triangle
  std::vector<double> cdf_;                        ///< cumulative areas, per small triangle
  double area_ = 0;
};

/// n samples uniform by area on a triangle mesh; normals interpolated from the corner normals
/// (barycentric, normalised). Deterministic for (soup, n, seed).
std::vector<SurfaceSample> sampleTriangleSoup(const TriangleSoup& soup, size_t n, uint64_t seed);

/// Nearest point on the patch surface: the nearest vertex of a level-`level` tessellation
/// (k-d tree), then Gauss-Newton on |G(xi, eta) - q|^2 inside that patch (kept in its domain),
/// from the 4 nearest tessellation vertices; the closest result wins. Thread-safe.
class PatchProjector {
 public:
  explicit PatchProjector(const PatchCache& cache, int level = 8);
  ~PatchProjector();
  SurfaceSample project(const Eigen::Vector3d& q) const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

/// Reads a CSV with header `x,y,z` (readNumericCsv: strict, throws InputError `file:line: what`).
std::vector<Eigen::Vector3d> readPointsCsv(const std::string& path);
/// Writes `x,y,z` rows with %.17g. Throws InputError on failure.
void writePointsCsv(const std::vector<Eigen::Vector3d>& pts, const std::string& path);

/// The most points resamplePolyline makes of one polyline: 10^7 (at 1 kHz, 2.8 hours of a
/// device's motion; about 1 GB of samples in a sweep).
constexpr double kMaxResampledPoints = 1e7;
/// Arc length of the polyline, m (each segment's length without overflow: stableNorm).
double polylineLength(const std::vector<Eigen::Vector3d>& pts);
/// The InputError message for a polyline (named `what`: a file, the default loop) whose
/// resampling every `step` m would make more than kMaxResampledPoints points; empty when it
/// would not.
std::string resampleLimitError(const std::vector<Eigen::Vector3d>& pts, double step, const std::string& what);
/// Points every `step` (m, > 0; none otherwise) of arc length along the polyline, starting at
/// its first point: about polylineLength / step + 1. Throws InputError (resampleLimitError)
/// where that would be more than kMaxResampledPoints.
std::vector<Eigen::Vector3d> resamplePolyline(const std::vector<Eigen::Vector3d>& pts, double step);

/// The longest chain of the section of a welded triangle mesh (vertices P, m; triangles tri,
/// indices into P) by the plane x[axis] = c: a closed loop (first point repeated last) or an open
/// polyline of positive length, its points where the triangles' edges cross the plane (a vertex
/// exactly on it counts as on the positive side); empty when the plane misses. Chains follow
/// the triangles' order; of equally long ones, the first.
std::vector<Eigen::Vector3d> longestSection(const std::vector<Eigen::Vector3d>& P,
                                            const std::vector<std::array<int, 3>>& tri, int axis, double c);

/// A default trajectory: the longest loop (or open chain) of the section of the level-`level`
/// tessellation by the plane through the bounding-box centre normal to the box's shortest axis
/// (a great circle on a sphere, the outer equator of a torus); where that plane meets no edge, or
/// the box is flat along that axis (extent at most 1e-9 of its diagonal: a planar mesh lies in
/// that plane), normal to the next shortest axis, then the longest (a line across a flat mesh).
/// Points in metres, on the tessellation. Empty when none of the three planes meets the surface.
std::vector<Eigen::Vector3d> defaultTrajectory(const PatchCache& cache, int level = 8);

}  // namespace sf
