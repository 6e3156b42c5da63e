// SPDX-License-Identifier: Apache-2.0
#include <smoothforce/sweep/generators.h>

#include <Eigen/Geometry>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <map>
#include <numbers>

#include <smoothforce/base/coordinate_range.h>

namespace sf {

namespace {
constexpr double kTwoPi = 2 * std::numbers::pi;

/// The most quads a generator makes: 1e8 (an OBJ of about 10 GB; int32 vertex indices).
constexpr double kMaxQuads = 1e8;

/// The shortest decimal form that reads back as x.
std::string shortest(double x) {
  char b[32];
  return std::string(b, std::to_chars(b, b + sizeof b, x).ptr);
}

/// Refuses a mesh whose vertices could lie beyond kMaxCoordinate (`reach`: the largest distance
/// of a vertex from the origin, m): every mesh reader and `cache build` would refuse the file.
void requireReach(double reach, const std::string& what) {
  if (!(reach <= kMaxCoordinate))
    throw InputError(what + " puts vertices up to " + shortest(reach) +
                     " m from the origin, beyond the coordinate range +-1e15 m that the mesh readers take");
}

void requireQuads(double quads, const std::string& what) {
  if (quads > kMaxQuads)
    throw InputError(what + " makes " + shortest(quads) + " quads, more than 1e8 (an OBJ of about 10 GB)");
}
}  // namespace

PolygonMesh GeneratedMesh::toPolygonMesh() const {
  PolygonMesh m;
  m.positions = positions;
  m.fileNormals = normals;
  for (const auto& q : quads) m.addFace({q[0], q[1], q[2], q[3]});
  m.sourcePath = "(generated)";
  return m;
}

void torusKnotCurve(const TorusKnotParams& k, double phi, Eigen::Vector3d& c, Eigen::Vector3d& d1,
                    Eigen::Vector3d& d2) {
  const double p = k.p, q = k.q, cq = std::cos(q * phi), sq = std::sin(q * phi);
  const double cp = std::cos(p * phi), sp = std::sin(p * phi);
  const double a = k.R + k.r * cq, a1 = -k.r * q * sq, a2 = -k.r * q * q * cq;
  c = k.scale * Eigen::Vector3d(a * cp, a * sp, -k.r * sq);
  d1 = k.scale * Eigen::Vector3d(a1 * cp - a * p * sp, a1 * sp + a * p * cp, -k.r * q * cq);
  d2 = k.scale * Eigen::Vector3d(a2 * cp - 2 * a1 * p * sp - a * p * p * cp, a2 * sp + 2 * a1 * p * cp - a * p * p * sp,
                                 k.r * q * q * sq);
}

void torusKnotFrame(const TorusKnotParams& k, double phi, Eigen::Vector3d& t, Eigen::Vector3d& n, Eigen::Vector3d& b) {
  Eigen::Vector3d c, d1, d2;
  torusKnotCurve(k, phi, c, d1, d2);
  t = d1.normalized();
  b = d1.cross(d2).normalized();
  n = b.cross(t);
}

Eigen::Vector3d torusKnotSurface(const TorusKnotParams& k, double phi, double theta, Eigen::Vector3d* normal) {
  Eigen::Vector3d c, d1, d2, t, n, b;
  torusKnotCurve(k, phi, c, d1, d2);
  torusKnotFrame(k, phi, t, n, b);
  const Eigen::Vector3d u = std::cos(theta) * n + std::sin(theta) * b;
  if (normal) *normal = u;
  return c + k.scale * k.tube * u;
}

GeneratedMesh torusKnot(const TorusKnotParams& k) {
  if (k.segments < 3 || k.sides < 3)
    throw InputError("torus-knot: --segments and --sides must be >= 3 (got " + std::to_string(k.segments) + ", " +
                     std::to_string(k.sides) + ")");
  if (!(k.R > 0) || !(k.r > 0) || !(k.tube > 0) || !(k.scale > 0) || !std::isfinite(k.R + k.r + k.tube + k.scale))
    throw InputError("torus-knot: --R, --r, --tube and --scale must be positive and finite");
  if (k.p == 0 || k.q == 0) throw InputError("torus-knot: --p and --q must be non-zero");
  // the centre curve's highest frequency is |p| + |q| windings per lap: at fewer than 4 segments
  // a winding the quads cannot follow the knot (and --p 2000000000 is no knot a mesh can show)
  const double windings = std::fabs(double(k.p)) + std::fabs(double(k.q));
  if (double(k.segments) < 4 * windings)
    throw InputError("torus-knot: --p " + std::to_string(k.p) + " --q " + std::to_string(k.q) + " wind " +
                     shortest(windings) + " times (|p| + |q|) per lap; --segments " + std::to_string(k.segments) +
                     " cannot follow that: give --segments >= 4 (|p| + |q|) = " + shortest(4 * windings));
  requireQuads(double(k.segments) * k.sides, "torus-knot: --segments x --sides");
  requireReach(k.scale * (k.R + k.r + k.tube), "torus-knot: --scale x (--R + --r + --tube)");
  GeneratedMesh m;
  for (int i = 0; i < k.segments; ++i) {
    const double phi = kTwoPi * i / k.segments;
    Eigen::Vector3d c, d1, d2;
    torusKnotCurve(k, phi, c, d1, d2);
    const double kappa = d1.cross(d2).norm() / std::pow(d1.norm(), 3);
    if (!(kappa * k.scale * (k.R + k.r) > 1e-9))
      throw InputError("torus-knot: the Frenet frame degenerates at segment " + std::to_string(i) + " (curvature ~ 0)");
    for (int j = 0; j < k.sides; ++j) {
      Eigen::Vector3d nrm;
      m.positions.push_back(torusKnotSurface(k, phi, kTwoPi * j / k.sides, &nrm));
      m.normals.push_back(nrm);
    }
  }
  auto id = [&](int i, int j) { return static_cast<int32_t>((i % k.segments) * k.sides + (j % k.sides)); };
  // d/dtheta x d/dphi points along the outward normal: corners (i,j) (i,j+1) (i+1,j+1) (i+1,j).
  for (int i = 0; i < k.segments; ++i)
    for (int j = 0; j < k.sides; ++j) m.quads.push_back({id(i, j), id(i, j + 1), id(i + 1, j + 1), id(i + 1, j)});
  return m;
}

std::vector<Eigen::Vector3d> torusKnotHelix(const TorusKnotParams& k, double turns, int count) {
  if (count < 2) throw InputError("torus-knot helix: need at least 2 points");
  std::vector<Eigen::Vector3d> pts;
  for (int i = 0; i < count; ++i) {
    const double phi = kTwoPi * i / (count - 1);
    pts.push_back(torusKnotSurface(k, phi, turns * phi));
  }
  return pts;
}

GeneratedMesh quadSphere(double radius, int n) {
  if (n < 1) throw InputError("sphere: --segments must be >= 1, got " + std::to_string(n));
  if (!(radius > 0) || !std::isfinite(radius)) throw InputError("sphere: --radius must be positive and finite");
  requireReach(radius, "sphere: --radius " + shortest(radius));
  GeneratedMesh m;
  std::map<std::array<int, 3>, int32_t> index;
  auto vertex = [&](std::array<int, 3> g) {
    auto it = index.find(g);
    if (it != index.end()) return it->second;
    Eigen::Vector3d c;
    for (int a = 0; a < 3; ++a) c[a] = std::tan((-1.0 + 2.0 * g[a] / n) * std::numbers::pi / 4);
    const Eigen::Vector3d u = c.normalized();
    const auto id = static_cast<int32_t>(m.positions.size());
    m.positions.push_back(radius * u);
    m.normals.push_back(u);
    index.emplace(g, id);
    return id;
  };
  for (int ax = 0; ax < 3; ++ax)
    for (int side = 0; side < 2; ++side) {
      // e_ua x e_va = +e_ax; swapped on the negative side, so every quad is CCW from outside.
      int ua = (ax + 1) % 3, va = (ax + 2) % 3;
      if (side == 0) std::swap(ua, va);
      for (int u = 0; u < n; ++u)
        for (int v = 0; v < n; ++v) {
          auto g = [&](int du, int dv) {
            std::array<int, 3> p{};
            p[ax] = side ? n : 0;
            p[ua] = u + du;
            p[va] = v + dv;
            return vertex(p);
          };
          m.quads.push_back({g(0, 0), g(1, 0), g(1, 1), g(0, 1)});
        }
    }
  return m;
}

GeneratedMesh torusMesh(double R, double r, int segments, int sides) {
  if (segments < 3 || sides < 3) throw InputError("torus: --segments and --sides must be >= 3");
  if (!(r > 0) || !(R > r) || !std::isfinite(R)) throw InputError("torus: need 0 < r < R (finite)");
  requireQuads(double(segments) * sides, "torus: --segments x --sides");
  requireReach(R + r, "torus: --R " + shortest(R) + " --r " + shortest(r));
  GeneratedMesh m;
  for (int i = 0; i < segments; ++i)
    for (int j = 0; j < sides; ++j) {
      const double u = kTwoPi * i / segments, v = kTwoPi * j / sides;
      const Eigen::Vector3d nrm(std::cos(v) * std::cos(u), std::cos(v) * std::sin(u), std::sin(v));
      m.positions.push_back(Eigen::Vector3d(R * std::cos(u), R * std::sin(u), 0) + r * nrm);
      m.normals.push_back(nrm);
    }
  auto id = [&](int i, int j) { return static_cast<int32_t>((i % segments) * sides + (j % sides)); };
  for (int i = 0; i < segments; ++i)
    for (int j = 0; j < sides; ++j) m.quads.push_back({id(i, j), id(i + 1, j), id(i + 1, j + 1), id(i, j + 1)});
  return m;
}

void writeGeneratedObj(const GeneratedMesh& m, const std::string& path, const std::string& comment) {
  std::FILE* f = std::fopen(path.c_str(), "w");
  if (!f) throw InputError(path + ": cannot open for writing");
  std::fprintf(f, "# %s\n# %zu vertices, %zu quads; exact normals: read with --normals file\n", comment.c_str(),
               m.positions.size(), m.quads.size());
  for (const auto& p : m.positions) std::fprintf(f, "v %.17g %.17g %.17g\n", p.x(), p.y(), p.z());
  for (const auto& n : m.normals) std::fprintf(f, "vn %.17g %.17g %.17g\n", n.x(), n.y(), n.z());
  for (const auto& q : m.quads)
    std::fprintf(f, "f %d//%d %d//%d %d//%d %d//%d\n", q[0] + 1, q[0] + 1, q[1] + 1, q[1] + 1, q[2] + 1, q[2] + 1,
                 q[3] + 1, q[3] + 1);
  const bool bad = std::ferror(f) != 0;
  if (std::fclose(f) != 0 || bad) throw InputError(path + ": write failed");
}

}  // namespace sf
