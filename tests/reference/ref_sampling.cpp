// SPDX-License-Identifier: Apache-2.0
#include "ref_sampling.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>

namespace sf::ref {

std::vector<Eigen::Vector2d> refDomainSamples(int n, int m) {
  std::vector<Eigen::Vector2d> out;
  for (int k = 0; k < n; ++k) {
    const Eigen::Vector2d a = refDomainCorner(n, k), b = refDomainCorner(n, k + 1);
    for (int i = 0; i <= m; ++i)
      for (int j = 0; i + j <= m; ++j) out.push_back((i * a + j * b) / m);
  }
  return out;
}

Eigen::Vector2d refDomainEdgePoint(int n, int k, double s, double inset) {
  const Eigen::Vector2d a = refDomainCorner(n, k), b = refDomainCorner(n, k + 1);
  return a + s * (b - a) - inset * refDomainEdgeNormal(n, k);
}

double refTangentPlaneAngle(const Eigen::Vector3d& n0, const Eigen::Vector3d& n1) {
  return std::atan2(n0.cross(n1).norm(), std::abs(n0.dot(n1)));
}

RefSphereDeviation refSphereDeviation(const RefMesh& m, CrossTangent mode, int grid) {
  RefSphereDeviation d;
  for (int f = 0; f < static_cast<int>(m.faces.size()); ++f) {
    const RefPatch p = refFacePatch(m, f, mode);
    const RefPatchEvaluator ev(p);
    const int n = ev.size();
    for (const auto& X : refDomainSamples(n, grid))
      d.patch = std::max(d.patch, std::abs(ev.position(X.x(), X.y()).norm() - 1));
    d.centre = std::max(d.centre, std::abs(ev.position(0, 0).norm() - 1));
    Eigen::Vector3d c = Eigen::Vector3d::Zero();
    for (const auto& v : p.V) c += v / n;
    for (int k = 0; k < n; ++k)
      for (int i = 0; i <= grid; ++i)
        for (int j = 0; i + j <= grid; ++j) {
          const double a = double(i) / grid, b = double(j) / grid;
          const Eigen::Vector3d x = a * p.V[k] + b * p.V[(k + 1) % n] + (1 - a - b) * c;
          d.flat = std::max(d.flat, std::abs(x.norm() - 1));
        }
  }
  return d;
}

RefEdgeJumpMeter::RefEdgeJumpMeter(const RefMesh& m, CrossTangent mode) : nb_(refEdgeNeighbours(m)) {
  for (int f = 0; f < static_cast<int>(m.faces.size()); ++f) eval_.emplace_back(refFacePatch(m, f, mode));
}

double RefEdgeJumpMeter::edgeJump(int f, int k, double inset, int samples) const {
  const RefEdgeNeighbour& o = nb_[f][k];
  if (o.face < 0) return 0.0;
  const int n = eval_[f].size(), no = eval_[o.face].size();
  double worst = 0.0;
  for (int i = 0; i < samples; ++i) {
    const double s = (i + 0.5) / samples;
    const Eigen::Vector2d X = refDomainEdgePoint(n, k, s, inset);
    const Eigen::Vector2d Y = refDomainEdgePoint(no, o.edge, 1.0 - s, inset);
    const RefEval a = eval_[f].evaluate(X.x(), X.y());
    const RefEval b = eval_[o.face].evaluate(Y.x(), Y.y());
    worst = std::max(worst, refTangentPlaneAngle(a.normal, b.normal));
  }
  return worst;
}

double RefEdgeJumpMeter::maxJump(double inset, int samples) const {
  double worst = 0.0;
  for (int f = 0; f < static_cast<int>(nb_.size()); ++f)
    for (int k = 0; k < static_cast<int>(nb_[f].size()); ++k) worst = std::max(worst, edgeJump(f, k, inset, samples));
  return worst;
}

}  // namespace sf::ref
