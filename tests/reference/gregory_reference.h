// SPDX-License-Identifier: Apache-2.0
// Independent double-precision reference of the n-sided Gregory patch, for tests only.
// Written from ../shared/design/gregory-patch.md alone, with Eigen, sharing no code with
// kernels/gp_patch.h. Derivatives by complex-step differentiation (exact to rounding).
#pragma once

#include <Eigen/Core>
#include <memory>
#include <vector>

namespace sf::ref {

enum class CrossTangent { Corrected, Paper, Blend };

/// One polygon's patch. V, N: n by 3 positions and unit normals, n >= 3, CCW from outside.
struct RefPatch {
  std::vector<Eigen::Vector3d> V, N;
  CrossTangent mode = CrossTangent::Corrected;
  /// Optional given end tangents (empty, or n each): where TS[k] (TE[k]) is nonzero, edge k's
  /// unit t_s (t_e) is that direction instead of Eq. 8 (Eq. 9) (the fold repair's untangled fans).
  std::vector<Eigen::Vector3d> TS, TE;
};

/// Result of evaluating the patch at a domain point X = (xi, eta).
struct RefEval {
  Eigen::Vector3d pos, dxi, deta, normal;  ///< G, dG/dxi, dG/deta, unit(dG/dxi x dG/deta)
};

/// Edge curve C_k(t) (Eq. 6-9, with the design page's guard) and its t-derivative.
Eigen::Vector3d refEdgeCurve(const RefPatch& p, int k, double t);
Eigen::Vector3d refEdgeCurveDerivative(const RefPatch& p, int k, double t);
/// Unit surface normal along edge k, n_c(t) (Eq. 10, normalised and oriented).
Eigen::Vector3d refEdgeNormal(const RefPatch& p, int k, double t);
/// Cross tangent T_k(t) (Eq. 11-14 with the selected correction) and dT_k/dt.
Eigen::Vector3d refCrossTangent(const RefPatch& p, int k, double t);
Eigen::Vector3d refCrossTangentDerivative(const RefPatch& p, int k, double t);
/// Domain corner C_k of the regular n-gon.
Eigen::Vector2d refDomainCorner(int n, int k);
/// G(X) and its exact first derivatives (Eq. 2-5). X must lie in the closed domain.
RefEval refEvaluate(const RefPatch& p, double xi, double eta);

// ---- Additions beyond the fixed API (tests only) ----

struct RefPatchData;

/// Reusable evaluator: builds the edge curves, cross tangents and the twists once, then
/// evaluates G(X) many times. refEvaluate(p, xi, eta) == RefPatchEvaluator(p).evaluate(xi, eta).
class RefPatchEvaluator {
 public:
  explicit RefPatchEvaluator(const RefPatch& p);  ///< throws std::invalid_argument if n < 3
  RefEval evaluate(double xi, double eta) const;
  Eigen::Vector3d position(double xi, double eta) const;  ///< G(X) only (cheaper)
  int size() const;

 private:
  std::shared_ptr<const RefPatchData> d_;
};

/// Which end tangents of edge k the backward-tangent guard replaced: bit 0 = t_s, bit 1 = t_e.
int refEdgeGuardMask(const RefPatch& p, int k);
/// Outward unit normal m_k of domain edge C_k C_{k+1} (Eq. 3-5 of the design page).
Eigen::Vector2d refDomainEdgeNormal(int n, int k);

}  // namespace sf::ref
