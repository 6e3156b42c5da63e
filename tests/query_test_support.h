// SPDX-License-Identifier: Apache-2.0
// Shapes and independent checks for the SCP-query property tests: every closed mesh of
// ../shared/meshes plus generated analytic shapes, and an oracle built from a dense
// tessellation of the patches (its own ray parity and its own nearest vertex), independent of
// the production query (PatchSurface, insidePatchSurface, nearestOnPatches).
#pragma once

#include <Eigen/Core>
#include <limits>
#include <memory>
#include <string>
#include <vector>

#include <smoothforce/patch/patch_cache.h>
#include <smoothforce/patch/tessellate.h>
#include <smoothforce/query/patch_refine.h>

namespace sf::test {

/// The closed meshes of ../shared/meshes (the README catalogue's "closed" rows, relative
/// paths) and the generated shapes "generated:sphere", "generated:torus", "generated:knot".
std::vector<std::string> closedShapes();

/// A prebuilt double cache of a closed shape (default patch options; generated shapes use their
/// exact normals).
std::shared_ptr<const PatchCache> closedShapeCache(const std::string& name);

/// A file-name-safe test name for a shape.
std::string shapeTestName(const std::string& name);

/// The oracle: a dense tessellation of every patch (tessellatePatches at the largest level whose
/// triangle count stays within `triangleBudget`, at most 16).
class DenseOracle {
 public:
  explicit DenseOracle(const PatchCache& cache, long triangleBudget = 400000);
  ~DenseOracle();
  DenseOracle(const DenseOracle&) = delete;
  DenseOracle& operator=(const DenseOracle&) = delete;

  /// Winding number of the dense tessellation around q by ray parity: each of three rays in
  /// fixed skew directions (others than production's) is intersected hit by hit (Embree, restarted
  /// past every hit), crossings summed with their sign; the majority. agree: all three equal.
  int winding(const Eigen::Vector3d& q, bool* agree = nullptr) const;

  /// The patch point nearest q: the nearest of the 24 nearest dense vertices and of the
  /// refinements (with `refiner`, Newton, tight tolerances) from each of them that lies more than
  /// two vertex spacings (in the domain) from the ones refined before on its face.
  struct Nearest {
    Eigen::Vector3d point, normal;
    double distance = 0;
    int face = -1;
    /// The nearest refined points the query is below / above (m), and held on a fold edge.
    double nearestBelow = std::numeric_limits<double>::infinity();
    double nearestAbove = std::numeric_limits<double>::infinity();
    double foldEdge = std::numeric_limits<double>::infinity();
    /// Sheets about as near (within `factor`) see the query on both sides, or a fold edge is
    /// that near: the surface folds, overlaps or is thin here.
    bool conflicting(double factor) const {
      const double d = std::min(nearestBelow, nearestAbove);
      return std::max(nearestBelow, nearestAbove) <= factor * d || foldEdge <= factor * d;
    }
  };
  Nearest nearest(const Eigen::Vector3d& q, PatchRefiner& refiner) const;

  int level() const { return level_; }
  size_t numTriangles() const { return mesh_.triangles.size(); }

 private:
  struct Impl;
  int level_ = 1;
  TriangleMesh mesh_;
  std::vector<Eigen::Vector2d> domain_;  ///< per dense vertex
  std::unique_ptr<Impl> impl_;
};

/// A curve on the patch surface: points p_i with normals n_i, faces and domain points, from
/// `start` (face, X) along `direction` (projected on the tangent plane) in 3-D steps of `step`
/// (m), each step projected back on the surface by refinement from the previous point and the
/// direction carried along (tangent-plane projection). Stops after `count` points or when a
/// projection fails or jumps (more than 2 steps away).
struct SurfacePath {
  std::vector<Eigen::Vector3d> point, normal;
  std::vector<int> face;
  int faceChanges = 0;
};
SurfacePath walkSurface(const PatchCache& cache, PatchRefiner& refiner, int face, const Eigen::Vector2d& X,
                        const Eigen::Vector3d& direction, double step, int count);

}  // namespace sf::test
