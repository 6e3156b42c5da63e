// SPDX-License-Identifier: Apache-2.0
// Test-object generators with exact normals: torus knot tube, quad-sphere, torus.
// Their offset surfaces are known exactly, so force sweeps can measure accuracy against them.
#pragma once

#include <Eigen/Core>
#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include <smoothforce/mesh/mesh.h>

namespace sf {

/// A generated quad mesh: positions, normals #V by 3 (normals unit, exact: taken from the
/// analytic surface, not from the polygons); faces #F by 4, counter-clockwise seen from outside.
struct GeneratedMesh {
  std::vector<Eigen::Vector3d> positions, normals;
  std::vector<std::array<int32_t, 4>> quads;
  /// The same as a PolygonMesh with per-vertex file normals.
  PolygonMesh toPolygonMesh() const;
};

/// Torus knot tube (units as given, then multiplied by scale). The centre curve, phi in [0, 2 pi):
///   C(phi) = scale ((R + r cos q phi) cos p phi, (R + r cos q phi) sin p phi, -r sin q phi).
/// The tube has radius scale * tube; vertex (i, j) = C(phi_i) + scale tube (cos th_j N + sin th_j B)
/// with phi_i = 2 pi i / segments, th_j = 2 pi j / sides and (T, N, B) the Frenet frame of C
/// (periodic, so the tube closes without a seam twist); its normal is cos th_j N + sin th_j B,
/// the exact tube normal. segments * sides quads; p, q coprime for a single closed knot.
struct TorusKnotParams {
  int p = 2, q = 3, segments = 120, sides = 12;
  double R = 1, r = 0.4, tube = 0.15, scale = 1;
};
/// Throws InputError for counts < 3, more than 1e8 quads, fewer than 4 (|p| + |q|) segments
/// (too few to follow the windings), non-positive radii or scale, vertices beyond the coordinate
/// range (scale (R + r + tube) > 1e15 m), or a Frenet frame that degenerates (curvature ~ 0
/// somewhere on the curve).
GeneratedMesh torusKnot(const TorusKnotParams& params);
/// Centre curve point and its first two derivatives with respect to phi (scaled).
void torusKnotCurve(const TorusKnotParams& k, double phi, Eigen::Vector3d& c, Eigen::Vector3d& d1, Eigen::Vector3d& d2);
/// Frenet frame (unit T, N, B) of the centre curve at phi.
void torusKnotFrame(const TorusKnotParams& k, double phi, Eigen::Vector3d& t, Eigen::Vector3d& n, Eigen::Vector3d& b);
/// Point on the tube surface at (phi, theta) (scaled) and its unit outward normal.
Eigen::Vector3d torusKnotSurface(const TorusKnotParams& k, double phi, double theta, Eigen::Vector3d* normal = nullptr);
/// A helix on the tube surface (`turns` turns around the tube over one lap of the knot),
/// sampled at `count` points: a trajectory for force sweeps. count >= 2.
std::vector<Eigen::Vector3d> torusKnotHelix(const TorusKnotParams& k, double turns, int count);

/// Quad-sphere of radius `radius` centred at the origin: each cube face split into
/// segments x segments quads (equal-angle mapping), vertices on the sphere, normals radial.
/// 6 segments^2 quads, 6 segments^2 + 2 vertices. Throws InputError for segments < 1, radius <= 0
/// and radius > 1e15 m (the coordinate range).
GeneratedMesh quadSphere(double radius, int segments);

/// Torus about the z axis: major radius R, minor radius r (0 < r < R), `segments` around the
/// axis and `sides` around the tube; normals exact. segments * sides quads. Throws InputError
/// unless 0 < r < R, R + r <= 1e15 m (the coordinate range), counts >= 3 and at most 1e8 quads.
GeneratedMesh torusMesh(double R, double r, int segments, int sides);

/// Writes OBJ: `v` and `vn` per vertex (%.17g) and faces `f a//a b//b ...` (1-based).
/// Read it back with `--normals file` to build patches on the exact normals.
/// Throws InputError when the file cannot be written.
void writeGeneratedObj(const GeneratedMesh& mesh, const std::string& path, const std::string& comment);

}  // namespace sf
