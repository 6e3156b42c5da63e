// SPDX-License-Identifier: Apache-2.0
// Helpers for the extreme-input tests (tests/test_extremes_*.cpp): meshes
// built in code with per-corner normals, a sweep that evaluates every face at its corners,
// on its edges, at the centre and inside, and measures what the tests bound.
#pragma once

#include <gtest/gtest.h>

#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

#include <smoothforce/patch/detail/gp_math.h>
#include <smoothforce/patch/patch_eval.h>

namespace sf::extreme {

using Vec3 = Eigen::Vector3d;
using Vec2 = Eigen::Vector2d;

/// A mesh with one normal per corner (#C, unit), as patch construction takes it.
struct CornerMesh {
  PolygonMesh mesh;
  std::vector<Vec3> normals;  ///< #C

  /// Appends a face with its corner normals; vertex ids index mesh.positions.
  void face(const std::vector<int32_t>& ids, const std::vector<Vec3>& n) {
    mesh.addFace(ids);
    for (const Vec3& v : n) normals.push_back(v.normalized());
  }
};

/// One polygon V[0..n-1] (CCW from outside) with unit normals N.
inline CornerMesh polygon(const std::vector<Vec3>& V, const std::vector<Vec3>& N) {
  CornerMesh m;
  m.mesh.positions = V;
  std::vector<int32_t> ids(V.size());
  for (size_t i = 0; i < V.size(); ++i) ids[i] = static_cast<int32_t>(i);
  m.face(ids, N);
  return m;
}
/// One polygon whose normals all equal n.
inline CornerMesh polygon(const std::vector<Vec3>& V, const Vec3& n) {
  return polygon(V, std::vector<Vec3>(V.size(), n));
}

/// The same mesh with every coordinate multiplied by s (normals unchanged).
inline CornerMesh scaled(CornerMesh m, double s) {
  for (Vec3& p : m.mesh.positions) p *= s;
  return m;
}

/// preparePatchCache + constructPatches on a CPU backend.
inline PatchCache build(const CornerMesh& m, Precision p, CrossTangentMode mode = CrossTangentMode::Corrected,
                        Backend b = Backend::Serial) {
  PatchOptions o;
  o.precision = p;
  o.crossTangent = mode;
  PatchCache c = preparePatchCache(m.mesh, m.normals, o, 0);
  constructPatches(c, b);
  return c;
}

inline bool finite(const Vec3& v) { return v.allFinite(); }
inline bool finite(const PatchPoint& p) { return finite(p.pos) && finite(p.dxi) && finite(p.deta) && finite(p.normal); }

/// Where a face is evaluated: every corner exactly, 7 points on every edge, 1e-9 inside
/// every edge, the centre, and rings at 0.25, 0.5, 0.9 and 0.999 towards corners and edge
/// midpoints (dense = false: 3 points per edge, rings 0.5 and 0.999). Points on the
/// boundary carry their edge and parameter s, corners their index; others -1.
struct Sample {
  Vec2 x;
  int corner = -1, edge = -1;
  double s = 0;
};
inline std::vector<Sample> samples(int n, bool dense = true) {
  std::vector<Sample> out;
  const std::vector<double> along = dense ? std::vector<double>{1e-9, 0.01, 0.25, 0.5, 0.75, 0.99, 1 - 1e-9}
                                          : std::vector<double>{1e-9, 0.5, 1 - 1e-9};
  const std::vector<double> rings =
      dense ? std::vector<double>{0.25, 0.5, 0.9, 0.999} : std::vector<double>{0.5, 0.999};
  for (int k = 0; k < n; ++k) {
    const Vec2 a = domainCorner(n, k), b = domainCorner(n, (k + 1) % n);
    out.push_back({a, k, -1, 0});
    for (double s : along) out.push_back({a + s * (b - a), -1, k, s});
    const Vec2 m = 0.5 * (a + b);
    out.push_back({m * (1 - 1e-9), -1, -1, 0});
    for (double r : rings) {
      out.push_back({r * a, -1, -1, 0});
      out.push_back({r * m, -1, -1, 0});
    }
  }
  out.push_back({Vec2(0, 0), -1, -1, 0});
  return out;
}

/// What a sweep over every face measured. Errors are relative to `scale` (the largest
/// of the face diameters and vertex distances from the origin: float and double round
/// relative to the coordinates' magnitude).
struct Sweep {
  int points = 0, nonFinite = 0;
  double corner = 0;                    ///< max |G(C_k) - V_k| / scale
  double edge = 0;                      ///< max |G on domain edge k at s - C_k(s)| / scale
  double unit = 0;                      ///< max ||normal| - 1|
  double plane = 0;                     ///< max distance from the plane (planeN, planeD) / scale, when given
  uint32_t status = 0, faceStatus = 0;  ///< OR over all points / faces
  int maxN = 3;                         ///< largest face evaluated
  std::string firstBad;
};

inline double meshScale(const PatchCache& c) {
  double s = 0;
  for (int v = 0; v < c.numVertices(); ++v) {
    const Vec3 p(c.positions[3 * v], c.positions[3 * v + 1], c.positions[3 * v + 2]);
    s = std::max(s, p.norm());
    for (int w = 0; w < v; ++w)
      s = std::max(s, (p - Vec3(c.positions[3 * w], c.positions[3 * w + 1], c.positions[3 * w + 2])).norm());
  }
  return s > 0 ? s : 1;
}

/// The edge curve C_k(s) of face f from its cached records, in the cache's precision.
inline Vec3 edgeCurve(const PatchCache& c, int f, int k, double s) {
  if (c.options.precision == Precision::Double) {
    double recs[GP_MAX_N * GP_E_NFIELDS];
    gatherRecords(c, f, recs);
    gpd::gp_dvec3 v, d;
    gpd::gp_edge_curve(recs + k * GP_E_NFIELDS, s, &v, &d);
    return {v.v.x, v.v.y, v.v.z};
  }
  float recs[GP_MAX_N * GP_E_NFIELDS];
  gatherRecords(c, f, recs);
  gpf::gp_dvec3 v, d;
  gpf::gp_edge_curve(recs + k * GP_E_NFIELDS, float(s), &v, &d);
  return {v.v.x, v.v.y, v.v.z};
}

/// Evaluates every face at samples(n); with planeN != 0 also measures flatness.
inline Sweep sweep(const PatchCache& c, const Vec3& planeN = Vec3::Zero(), double planeD = 0, bool dense = true) {
  Sweep r;
  const double scale = meshScale(c);
  for (int f = 0; f < c.numFaces(); ++f) {
    r.faceStatus |= c.faceStatus[f];
    const int n = c.faceSize(f);
    if (n < 3 || n > GP_MAX_N) continue;
    r.maxN = std::max(r.maxN, n);
    for (const Sample& q : samples(n, dense)) {
      const PatchPoint p = evaluatePatch(c, f, q.x.x(), q.x.y());
      ++r.points;
      r.status |= p.status;
      if (!finite(p)) {
        if (!r.nonFinite++)
          r.firstBad =
              "face " + std::to_string(f) + " at (" + std::to_string(q.x.x()) + ", " + std::to_string(q.x.y()) + ")";
        continue;
      }
      r.unit = std::max(r.unit, std::abs(p.normal.norm() - 1));
      if (q.corner >= 0) {
        const int v = c.faceVertices[c.faceOffsets[f] + q.corner];
        const Vec3 V(c.positions[3 * v], c.positions[3 * v + 1], c.positions[3 * v + 2]);
        r.corner = std::max(r.corner, (p.pos - V).norm() / scale);
      }
      if (q.edge >= 0) r.edge = std::max(r.edge, (p.pos - edgeCurve(c, f, q.edge, q.s)).norm() / scale);
      if (planeN.squaredNorm() > 0) r.plane = std::max(r.plane, std::abs(planeN.dot(p.pos) - planeD) / scale);
    }
  }
  return r;
}

/// Bounds for a sweep of faces with at most n sides, relative to the mesh scale, in units
/// of the precision's epsilon. Corners and edges: the domain corners come from cos/sin and
/// miss the exact corner by ~1 ulp; the edge parameter u = d_{k-1} / (d_{k-1} + d_{k+1})
/// then errs by ~ulp / d_{k+1}, and d_{k+1} ~ 4 (pi/n)^2 at a corner, so the error may grow
/// like n^2. Measured (SF_EXTREMES_REPORT=1, all cases of tests/test_extremes_*.cpp): at
/// n <= 10 double 3.0 eps, float 3.2 eps; up to n = 64 double 36 eps, float 26 eps (random
/// irregular 53- and 62-gons). Bound: (16 + n^2 / 16) eps, i.e. 17 eps at n = 3, 272 eps at
/// n = 64. Unit normals: measured 1.5 eps, bound 8 eps. Flatness of planar faces with face
/// normals: measured 0 (z = 0 exactly), bound 1 eps.
struct Bounds {
  double corner, edge, unit, plane;
};
inline Bounds bounds(Precision p, int n) {
  const double eps = p == Precision::Double ? 0x1p-52 : 0x1p-23;
  const double ce = (16 + n * n / 16.0) * eps;
  return {ce, ce, 8 * eps, eps};
}

inline std::string num(double v) {
  char b[32];
  std::snprintf(b, sizeof b, "%g", v);
  return b;
}

inline std::string bits(uint32_t st) {
  static const char* names[] = {"GUARD", "ZERO_EDGE", "EDGE_NORMAL", "CROSS_TANGENT",  "FOLD",
                                "BULGE", "OUTSIDE",   "SINGULAR",    "TOO_MANY_SIDES", "NONFINITE"};
  std::string s;
  for (int i = 0; i < 10; ++i)
    if (st & (1u << i)) {
      if (!s.empty()) s += '|';
      s += names[i];
    }
  return s.empty() ? "-" : s;
}

/// With SF_EXTREMES_REPORT set, prints one table row per case (for the measured bounds).
inline void report(const std::string& name, Precision p, const Sweep& r) {
  if (!std::getenv("SF_EXTREMES_REPORT")) return;
  const double eps = p == Precision::Double ? 0x1p-52 : 0x1p-23;
  std::printf(
      "| %-34s | %-6s | %6d | %s | corner+edge %5.1f eps (bound %5.0f) | unit %4.1f eps | plane %.1e | face %s | eval "
      "%s |\n",
      name.c_str(), toString(p), r.points, r.nonFinite ? "NONFINITE" : "finite", std::max(r.corner, r.edge) / eps,
      bounds(p, r.maxN).corner / eps, r.unit / eps, r.plane, bits(r.faceStatus).c_str(),
      bits(r.status & ~r.faceStatus).c_str());
}

/// Sweeps, reports and checks the bounds every case must meet: finite everywhere, corners
/// interpolated, the boundary equal to the edge curves, unit normals (and flatness when a
/// plane is given). Returns the sweep for case-specific checks.
inline Sweep check(const std::string& name, const PatchCache& c, const Vec3& planeN = Vec3::Zero(), double planeD = 0,
                   bool dense = true) {
  const Sweep r = sweep(c, planeN, planeD, dense);
  const Precision p = c.options.precision;
  report(name, p, r);
  const Bounds b = bounds(p, r.maxN);
  SCOPED_TRACE(name + " (" + toString(p) + ")");
  EXPECT_EQ(r.nonFinite, 0) << "first at " << r.firstBad;
  EXPECT_LE(r.corner, b.corner);
  EXPECT_LE(r.edge, b.edge);
  EXPECT_LE(r.unit, b.unit);
  EXPECT_LE(r.plane, b.plane);
  return r;
}

constexpr Precision kBoth[] = {Precision::Double, Precision::Float};

}  // namespace sf::extreme
