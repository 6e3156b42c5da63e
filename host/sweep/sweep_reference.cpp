// SPDX-License-Identifier: Apache-2.0
#include <smoothforce/sweep/sweep_reference.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <sstream>

#include <smoothforce/base/coordinate_range.h>
#include <smoothforce/mesh/mesh_io.h>
#include <smoothforce/mesh/normals.h>
#include <smoothforce/query/point_index.h>
#include <smoothforce/sweep/generators.h>

namespace sf {

namespace {

std::vector<double> parseNumbers(const std::string& spec, const std::string& list) {
  std::vector<double> v;
  std::stringstream ss(list);
  std::string item;
  while (std::getline(ss, item, ',')) {
    size_t used = 0;
    double x = 0;
    try {
      x = std::stod(item, &used);
    } catch (const std::exception&) {
      used = 0;
    }
    if (used == 0 || used != item.size() || !std::isfinite(x))
      throw InputError("--analytic " + spec + ": '" + item + "' is not a number");
    v.push_back(x);
  }
  return v;
}

class SphereSurface final : public ReferenceSurface {
 public:
  explicit SphereSurface(double r) : r_(r) {}
  double distance(const Eigen::Vector3d& p) const override { return std::abs(p.norm() - r_); }
  std::string describe() const override { return "sphere:" + std::to_string(r_); }

 private:
  double r_;
};

class TorusSurface final : public ReferenceSurface {
 public:
  TorusSurface(double R, double r) : R_(R), r_(r) {}
  double distance(const Eigen::Vector3d& p) const override {
    const double rho = std::hypot(p.x(), p.y());
    return std::abs(std::hypot(rho - R_, p.z()) - r_);
  }
  std::string describe() const override { return "torus:" + std::to_string(R_) + "," + std::to_string(r_); }

 private:
  double R_, r_;
};

class KnotSurface final : public ReferenceSurface {
 public:
  explicit KnotSurface(const TorusKnotParams& k) : k_(k), index_(curveSamples(k)) {}
  double distance(const Eigen::Vector3d& x) const override {
    const int64_t i = index_.nearest(x);
    double phi = 2 * std::numbers::pi * static_cast<double>(i) / kSamples;
    const double maxStep = 4 * std::numbers::pi / kSamples;
    Eigen::Vector3d c, d1, d2;
    for (int it = 0; it < 12; ++it) {  // Newton on |C(phi) - x|^2 / 2
      torusKnotCurve(k_, phi, c, d1, d2);
      const double g = (c - x).dot(d1), h = d1.squaredNorm() + (c - x).dot(d2);
      double step = h > 0 ? -g / h : (g > 0 ? -maxStep : maxStep);
      step = std::clamp(step, -maxStep, maxStep);
      phi += step;
      if (std::abs(step) < 1e-15) break;
    }
    torusKnotCurve(k_, phi, c, d1, d2);
    return std::abs((x - c).norm() - k_.scale * k_.tube);
  }
  std::string describe() const override {
    std::ostringstream s;
    s << "torus-knot:" << k_.p << "," << k_.q << "," << k_.R << "," << k_.r << "," << k_.tube << "," << k_.scale;
    return s.str();
  }

 private:
  static constexpr int kSamples = 8192;
  static std::vector<Eigen::Vector3d> curveSamples(const TorusKnotParams& k) {
    std::vector<Eigen::Vector3d> pts(kSamples);
    Eigen::Vector3d d1, d2;
    for (int i = 0; i < kSamples; ++i) torusKnotCurve(k, 2 * std::numbers::pi * i / kSamples, pts[i], d1, d2);
    return pts;
  }
  TorusKnotParams k_;
  PointIndex index_;
};

}  // namespace

std::unique_ptr<ReferenceSurface> makeAnalyticSurface(const std::string& spec) {
  const auto colon = spec.find(':');
  if (colon == std::string::npos)
    throw InputError("--analytic " + spec + ": expected sphere:R, torus:R,r or torus-knot:p,q,R,r,tube[,scale]");
  const std::string kind = spec.substr(0, colon);
  const std::vector<double> v = parseNumbers(spec, spec.substr(colon + 1));
  for (double x : v) {
    if (kind != "torus-knot" && !(x > 0)) throw InputError("--analytic " + spec + ": radii must be positive");
    // a surface beyond the queries' coordinate range has no distance to report (inf, not an error)
    if (!(std::abs(x) <= kMaxCoordinate))
      throw InputError("--analytic " + spec + ": every value must be within the coordinate range (1e15 m)");
  }
  if (kind == "sphere" && v.size() == 1) return std::make_unique<SphereSurface>(v[0]);
  if (kind == "torus" && v.size() == 2) {
    if (!(v[1] < v[0])) throw InputError("--analytic " + spec + ": need r < R");
    return std::make_unique<TorusSurface>(v[0], v[1]);
  }
  if (kind == "torus-knot" && (v.size() == 5 || v.size() == 6)) {
    TorusKnotParams k;
    k.p = static_cast<int>(v[0]);
    k.q = static_cast<int>(v[1]);
    k.R = v[2];
    k.r = v[3];
    k.tube = v[4];
    k.scale = v.size() == 6 ? v[5] : 1.0;
    if (k.p != v[0] || k.q != v[1] || k.p == 0 || k.q == 0 || !(k.R > 0 && k.r > 0 && k.tube > 0 && k.scale > 0))
      throw InputError("--analytic " + spec + ": p, q non-zero integers; R, r, tube, scale positive");
    return std::make_unique<KnotSurface>(k);
  }
  throw InputError("--analytic " + spec + ": expected sphere:R, torus:R,r or torus-knot:p,q,R,r,tube[,scale]");
}

double TriangleSoup::area() const {
  double a = 0;
  for (const auto& t : triangles)
    a += 0.5 * (positions[t[1]] - positions[t[0]]).cross(positions[t[2]] - positions[t[0]]).norm();
  return a;
}

TriangleSoup loadTriangleSoup(const std::string& path) {
  const PolygonMesh m = readMesh(path);
  const std::vector<Eigen::Vector3d> cn = cornerNormals(m, NormalMode::Auto);
  TriangleSoup s;
  s.positions = m.positions;
  for (int f = 0; f < m.numFaces(); ++f) {
    const int o = m.faceOffsets[f], n = m.faceSize(f);
    for (int k = 1; k + 1 < n; ++k) {
      s.triangles.push_back({m.faceVertices[o], m.faceVertices[o + k], m.faceVertices[o + k + 1]});
      s.cornerNormals.push_back({cn[o], cn[o + k], cn[o + k + 1]});
    }
  }
  if (s.triangles.empty()) throw InputError(path + ": no triangles");
  if (!(s.area() > 0)) throw InputError(path + ": the reference mesh has zero area");
  return s;
}

Eigen::Vector3d closestPointOnTriangle(const Eigen::Vector3d& p, const Eigen::Vector3d& a, const Eigen::Vector3d& b,
                                       const Eigen::Vector3d& c) {
  const Eigen::Vector3d ab = b - a, ac = c - a, ap = p - a;
  const double d1 = ab.dot(ap), d2 = ac.dot(ap);
  if (d1 <= 0 && d2 <= 0) return a;
  const Eigen::Vector3d bp = p - b;
  const double d3 = ab.dot(bp), d4 = ac.dot(bp);
  if (d3 >= 0 && d4 <= d3) return b;
  const double vc = d1 * d4 - d3 * d2;
  if (vc <= 0 && d1 >= 0 && d3 <= 0) return a + (d1 / (d1 - d3)) * ab;
  const Eigen::Vector3d cp = p - c;
  const double d5 = ab.dot(cp), d6 = ac.dot(cp);
  if (d6 >= 0 && d5 <= d6) return c;
  const double vb = d5 * d2 - d1 * d6;
  if (vb <= 0 && d2 >= 0 && d6 <= 0) return a + (d2 / (d2 - d6)) * ac;
  const double va = d3 * d6 - d5 * d4;
  if (va <= 0 && (d4 - d3) >= 0 && (d5 - d6) >= 0) return b + ((d4 - d3) / ((d4 - d3) + (d5 - d6))) * (c - b);
  const double denom = va + vb + vc;
  if (!(std::abs(denom) > 0)) return a;  // degenerate triangle
  const double v = vb / denom, w = vc / denom;
  return a + v * ab + w * ac;
}

MeshDistance::MeshDistance(TriangleSoup soup, std::string name) : soup_(std::move(soup)), name_(std::move(name)) {
  const auto& P = soup_.positions;
  if (soup_.triangles.empty()) return;
  Eigen::Vector3d lo = P[soup_.triangles[0][0]], hi = lo;
  for (const auto& t : soup_.triangles)
    for (int k = 0; k < 3; ++k) {
      lo = lo.cwiseMin(P[t[k]]);
      hi = hi.cwiseMax(P[t[k]]);
    }
  const Eigen::Vector3d ext = (hi - lo).cwiseMax(1e-12 * std::max(1.0, (hi - lo).norm()));
  const double cells = std::min<double>(static_cast<double>(soup_.triangles.size()), 4e6);
  h_ = std::cbrt(ext.prod() / cells);
  h_ = std::max(h_, ext.maxCoeff() / 256);
  lo_ = lo;
  for (int a = 0; a < 3; ++a) dim_[a] = std::max(1, static_cast<int>(std::ceil(ext[a] / h_)));
  const size_t nc = static_cast<size_t>(dim_[0]) * dim_[1] * dim_[2];
  auto cellRange = [&](const std::array<int32_t, 3>& t, std::array<int, 3>& c0, std::array<int, 3>& c1) {
    Eigen::Vector3d tlo = P[t[0]].cwiseMin(P[t[1]]).cwiseMin(P[t[2]]),
                    thi = P[t[0]].cwiseMax(P[t[1]]).cwiseMax(P[t[2]]);
    for (int a = 0; a < 3; ++a) {
      c0[a] = std::clamp(static_cast<int>(std::floor((tlo[a] - lo_[a]) / h_)), 0, dim_[a] - 1);
      c1[a] = std::clamp(static_cast<int>(std::floor((thi[a] - lo_[a]) / h_)), 0, dim_[a] - 1);
    }
  };
  std::vector<uint32_t> count(nc + 1, 0);
  for (int pass = 0; pass < 2; ++pass) {
    for (size_t ti = 0; ti < soup_.triangles.size(); ++ti) {
      std::array<int, 3> c0, c1;
      cellRange(soup_.triangles[ti], c0, c1);
      for (int z = c0[2]; z <= c1[2]; ++z)
        for (int y = c0[1]; y <= c1[1]; ++y)
          for (int x = c0[0]; x <= c1[0]; ++x) {
            const size_t c = (static_cast<size_t>(z) * dim_[1] + y) * dim_[0] + x;
            if (pass == 0)
              ++count[c + 1];
            else
              cellTris_[count[c]++] = static_cast<uint32_t>(ti);
          }
    }
    if (pass == 0) {
      for (size_t c = 0; c < nc; ++c) count[c + 1] += count[c];
      cellStart_ = count;
      cellTris_.resize(count[nc]);
    }
  }
}

Eigen::Vector3d MeshDistance::closestPoint(const Eigen::Vector3d& p, int* triangle) const {
  const auto& P = soup_.positions;
  double best = std::numeric_limits<double>::infinity();
  Eigen::Vector3d bestPt = p;
  int bestTri = -1;
  if (soup_.triangles.empty()) {
    if (triangle) *triangle = -1;
    return p;
  }
  std::array<int, 3> c0;
  for (int a = 0; a < 3; ++a) c0[a] = std::clamp(static_cast<int>(std::floor((p[a] - lo_[a]) / h_)), 0, dim_[a] - 1);
  const int maxR = std::max({dim_[0], dim_[1], dim_[2]});
  for (int r = 0; r <= maxR; ++r) {
    for (int z = std::max(0, c0[2] - r); z <= std::min(dim_[2] - 1, c0[2] + r); ++z)
      for (int y = std::max(0, c0[1] - r); y <= std::min(dim_[1] - 1, c0[1] + r); ++y)
        for (int x = std::max(0, c0[0] - r); x <= std::min(dim_[0] - 1, c0[0] + r); ++x) {
          if (std::max({std::abs(x - c0[0]), std::abs(y - c0[1]), std::abs(z - c0[2])}) != r) continue;
          const size_t c = (static_cast<size_t>(z) * dim_[1] + y) * dim_[0] + x;
          for (uint32_t i = cellStart_[c]; i < cellStart_[c + 1]; ++i) {
            const auto& t = soup_.triangles[cellTris_[i]];
            const Eigen::Vector3d q = closestPointOnTriangle(p, P[t[0]], P[t[1]], P[t[2]]);
            const double d = (q - p).squaredNorm();
            if (d < best || (d == best && static_cast<int>(cellTris_[i]) < bestTri)) {
              best = d;
              bestPt = q;
              bestTri = static_cast<int>(cellTris_[i]);
            }
          }
        }
    // Triangles not seen yet lie only in cells of ring >= r + 1: at least r h from clamp(p),
    // and projection onto the grid box never increases distances.
    if (bestTri >= 0 && std::sqrt(best) <= r * h_) break;
  }
  if (triangle) *triangle = bestTri;
  return bestPt;
}

double MeshDistance::distance(const Eigen::Vector3d& p) const { return (closestPoint(p) - p).norm(); }

std::string MeshDistance::describe() const {
  return "mesh:" + name_ + " (" + std::to_string(soup_.triangles.size()) + " triangles)";
}

}  // namespace sf
