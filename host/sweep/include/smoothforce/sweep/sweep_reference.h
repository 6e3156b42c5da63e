// SPDX-License-Identifier: Apache-2.0
// Reference surfaces for sweep accuracy: analytic (sphere, torus, torus-knot tube) or a dense
// triangle mesh (unsigned distance through a uniform grid).
#pragma once

#include <Eigen/Core>
#include <array>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

namespace sf {

/// Unsigned distance from a point to a known surface. distance() is const and thread-safe.
class ReferenceSurface {
 public:
  virtual ~ReferenceSurface() = default;
  /// m; >= 0.
  virtual double distance(const Eigen::Vector3d& p) const = 0;
  /// "sphere:R=0.05", "mesh:path (T triangles)".
  virtual std::string describe() const = 0;
};

/// Parses `sphere:R` (centred at the origin), `torus:R,r` (about the z axis, centred at the
/// origin), `torus-knot:p,q,R,r,tube[,scale]` (the `generate torus-knot` tube: the distance
/// from the knot curve minus the tube radius). Throws InputError naming the spec.
std::unique_ptr<ReferenceSurface> makeAnalyticSurface(const std::string& spec);

/// A triangle mesh: positions #V by 3, triangles #T by 3, corner normals #T by 3 by 3 (unit).
struct TriangleSoup {
  std::vector<Eigen::Vector3d> positions;
  std::vector<std::array<int32_t, 3>> triangles;
  std::vector<std::array<Eigen::Vector3d, 3>> cornerNormals;
  double area() const;
};

/// Reads a mesh file (OBJ/OFF/PLY), fan-triangulates its polygons and takes corner normals
/// from the file when it has one per vertex, else angle-weighted ones. Throws InputError.
TriangleSoup loadTriangleSoup(const std::string& path);

/// Unsigned distance to a triangle mesh: every triangle binned in a uniform grid (about one
/// triangle per cell), rings of cells searched outward until no closer triangle can exist.
class MeshDistance final : public ReferenceSurface {
 public:
  MeshDistance(TriangleSoup soup, std::string name);
  double distance(const Eigen::Vector3d& p) const override;
  std::string describe() const override;
  /// The nearest point found, and its triangle (-1 for an empty mesh).
  Eigen::Vector3d closestPoint(const Eigen::Vector3d& p, int* triangle = nullptr) const;
  const TriangleSoup& soup() const { return soup_; }

 private:
  TriangleSoup soup_;
  std::string name_;
  Eigen::Vector3d lo_{0, 0, 0};
  double h_ = 1;
  std::array<int, 3> dim_{1, 1, 1};
  std::vector<uint32_t> cellStart_, cellTris_;
};

/// Closest point of triangle (a, b, c) to p (Ericson, Real-Time Collision Detection 5.1.5).
Eigen::Vector3d closestPointOnTriangle(const Eigen::Vector3d& p, const Eigen::Vector3d& a, const Eigen::Vector3d& b,
                                       const Eigen::Vector3d& c);

}  // namespace sf
