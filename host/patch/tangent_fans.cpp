// SPDX-License-Identifier: Apache-2.0
#include <smoothforce/patch/tangent_fans.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <numbers>

#include <smoothforce/mesh/normals.h>
#include <smoothforce/patch/detail/face_inputs.h>
#include <smoothforce/patch/detail/gp_traits.h>

namespace sf {

namespace {

using Vec3 = Eigen::Vector3d;
constexpr double kPi = std::numbers::pi;

Vec3 at(const std::vector<double>& a, size_t i) { return Vec3(a[3 * i], a[3 * i + 1], a[3 * i + 2]); }

/// The construction's unit end tangents of every slot (#C*6, as TangentFans::tangents), from
/// gp_patch_end_tangents with the inputs buildPatchRecords gives it (detail::faceInputs).
std::vector<double> constructionTangents(const PatchCache& c) {
  std::vector<double> t(size_t(c.numSlots()) * 6, 0.0);
  gpd::gp_vec3 V[GP_MAX_N], N[GP_MAX_N], PS[GP_MAX_N], PE[GP_MAX_N], ts[GP_MAX_N], te[GP_MAX_N];
  int vid[GP_MAX_N];
  for (int f = 0; f < c.numFaces(); ++f) {
    const int n = c.faceSize(f), first = c.faceOffsets[f];
    if (n < 3 || n > GP_MAX_N) continue;
    const bool creased = detail::faceInputs<Gp<double>>(c, f, V, N, vid, PS, PE);
    gp_uint st = 0;
    gpd::gp_patch_end_tangents(n, V, N, PS, PE, creased ? 1 : 0, vid, ts, te, &st);
    for (int k = 0; k < n; ++k) {
      double* o = &t[6 * size_t(first + k)];
      o[0] = ts[k].x, o[1] = ts[k].y, o[2] = ts[k].z, o[3] = te[k].x, o[4] = te[k].y, o[5] = te[k].z;
    }
  }
  return t;
}

/// One constraint a . theta >= b of the fan's angles, a = (ci at i, cj at j; j < 0: none).
struct HalfSpace {
  int i, j;
  double ci, cj, b;
};

/// The Euclidean projection of phi on the intersection of the half spaces (Dykstra's
/// alternating projections, which converge to the nearest point of the intersection, not just to
/// some point of it). Returns false where the result still misses a constraint by more than tol
/// (an empty intersection, or one not reached).
bool nearestFeasible(const std::vector<double>& phi, const std::vector<HalfSpace>& hs, std::vector<double>& theta,
                     double tol) {
  theta = phi;
  std::vector<double> yi(hs.size(), 0.0), yj(hs.size(), 0.0);  // Dykstra's increments
  auto slack = [&](const HalfSpace& h) { return h.ci * theta[h.i] + (h.j >= 0 ? h.cj * theta[h.j] : 0.0) - h.b; };
  for (int sweep = 0; sweep < 3000; ++sweep) {
    double moved = 0;
    for (size_t c = 0; c < hs.size(); ++c) {
      const HalfSpace& h = hs[c];
      const double xi = theta[h.i] + yi[c], xj = h.j >= 0 ? theta[h.j] + yj[c] : 0.0;
      const double a2 = h.ci * h.ci + (h.j >= 0 ? h.cj * h.cj : 0.0);
      const double s = h.ci * xi + (h.j >= 0 ? h.cj * xj : 0.0) - h.b;
      const double step = s < 0 ? -s / a2 : 0.0;
      const double ni = xi + step * h.ci, nj = xj + step * h.cj;
      moved = std::max(moved, std::fabs(ni - theta[h.i]));
      yi[c] = xi - ni;
      theta[h.i] = ni;
      if (h.j >= 0) {
        moved = std::max(moved, std::fabs(nj - theta[h.j]));
        yj[c] = xj - nj;
        theta[h.j] = nj;
      }
    }
    if (moved < 1e-13) break;
  }
  for (const HalfSpace& h : hs)
    if (slack(h) < -tol) return false;
  return true;
}

double wrapPositive(double a) {
  a = std::fmod(a, 2 * kPi);
  return a < 0 ? a + 2 * kPi : a;
}

}  // namespace

TangentFans untangleTangentFans(const PatchCache& c) {
  TangentFans out;
  if (c.options.foldRepair == FoldRepairMode::Off || c.numSlots() == 0) return out;
  // closed manifold meshes only: there the surface has an inside, so the fault measure and the
  // winding number check what the turn does (on the open, non-manifold Stanford bunnies, a face
  // bent by an untangled fan had a nearest point the lazy contact query missed)
  for (const int32_t t : c.slotTwin)
    if (t < 0) return out;
  const std::vector<double> own = constructionTangents(c);
  const int ns = c.numSlots();
  std::vector<int> slotFace(ns), slotCorner(ns), cornerOfVertex(c.numVertices(), -1);
  for (int f = 0; f < c.numFaces(); ++f)
    for (int k = 0; k < c.faceSize(f); ++k) slotFace[c.faceOffsets[f] + k] = f, slotCorner[c.faceOffsets[f] + k] = k;
  std::vector<int> cornerCount(c.numVertices(), 0);
  for (int s = ns - 1; s >= 0; --s) cornerOfVertex[c.faceVertices[s]] = s, ++cornerCount[c.faceVertices[s]];
  const double tlo = kFanTangledGapDeg * kPi / 180, thi = kPi - tlo;
  std::vector<int> fan;
  for (int v = 0; v < c.numVertices(); ++v) {
    const int s0 = cornerOfVertex[v];
    if (s0 < 0) continue;
    // the corners at v in the faces' order about the outward normal: the edge into a corner is
    // the edge out of the next corner, in the face across it
    fan.clear();
    bool closed = true;
    for (int s = s0;;) {
      const int f = slotFace[s], n = c.faceSize(f);
      if (n < 3 || n > GP_MAX_N || int(fan.size()) >= GP_MAX_N) {
        closed = false;
        break;
      }
      fan.push_back(s);
      const int in = c.faceOffsets[f] + (slotCorner[s] + n - 1) % n;
      const int t = c.slotTwin[in];
      if (t < 0) {
        closed = false;
        break;
      }
      s = t;
      if (s == s0) break;
    }
    const int m = static_cast<int>(fan.size());
    if (!closed || m < 3 || m != cornerCount[v]) continue;  // open, or one of several fans (non-manifold)
    const Vec3 N = at(c.cornerNormals, fan[0]);
    bool one = true;
    for (const int s : fan) one = one && at(c.cornerNormals, s) == N;
    if (!one) continue;
    const Vec3 u = (std::fabs(N.x()) < 0.9 ? Vec3::UnitX() : Vec3::UnitY()).cross(N).normalized(), w = N.cross(u);
    std::vector<double> phi(m), corner(m);
    std::vector<Vec3> chord(m);  // the chords to the far ends, projected on the tangent plane
    const Vec3 P = at(c.positions, v);
    for (int i = 0; i < m; ++i) {
      const Vec3 d = at(own, 2 * size_t(fan[i]));
      phi[i] = std::atan2(d.dot(w), d.dot(u));
      const int f = slotFace[fan[i]], k = slotCorner[fan[i]], n = c.faceSize(f), first = c.faceOffsets[f];
      const Vec3 a = at(c.positions, c.faceVertices[first + (k + 1) % n]) - P;
      chord[i] = a - a.dot(N) * N;
      const Vec3 b = at(c.positions, c.faceVertices[first + (k + n - 1) % n]) - P;
      corner[i] = angleBetween(a, b);
    }
    double winding = 0;
    bool tangled = false;
    for (int i = 0; i < m; ++i) {
      const double g = wrapPositive(phi[(i + 1) % m] - phi[i]);
      winding += g;
      tangled = tangled || !(g >= tlo && g <= thi);
    }
    tangled = tangled || std::fabs(winding - 2 * kPi) > 1e-9;
    if (!tangled) continue;
    // unwrap phi next to gaps in proportion to the faces' corner angles, turned to fit phi best
    double angleSum = 0;
    for (const double a : corner) angleSum += a;
    if (!(angleSum > 0)) continue;
    std::vector<double> start(m, 0.0);
    for (int i = 1; i < m; ++i) start[i] = start[i - 1] + 2 * kPi * corner[i - 1] / angleSum;
    double sx = 0, sy = 0;
    for (int i = 0; i < m; ++i) sx += std::cos(phi[i] - start[i]), sy += std::sin(phi[i] - start[i]);
    const double turn0 = std::atan2(sy, sx);
    for (int i = 0; i < m; ++i) phi[i] += 2 * kPi * std::round((turn0 + start[i] - phi[i]) / (2 * kPi));
    // the constraints: consecutive gaps in [lo, pi - lo], once round (lo at most half the mean gap); each tangent within
    // kFanMaxChordTurnDeg of its chord's projection, so that it runs forward along its edge
    const double lo = std::min(kFanGapDeg * kPi / 180, kPi / m), hi = kPi - lo;
    std::vector<HalfSpace> hs;
    for (int i = 0; i + 1 < m; ++i) hs.push_back({i + 1, i, 1, -1, lo}), hs.push_back({i + 1, i, -1, 1, -hi});
    hs.push_back({0, m - 1, 1, -1, lo - 2 * kPi});
    hs.push_back({0, m - 1, -1, 1, 2 * kPi - hi});
    const double reach = kFanMaxChordTurnDeg * kPi / 180;
    for (int i = 0; i < m; ++i) {
      double psi = std::atan2(chord[i].dot(w), chord[i].dot(u));
      psi += 2 * kPi * std::round((phi[i] - psi) / (2 * kPi));
      hs.push_back({i, -1, 1, 0, psi - reach});
      hs.push_back({i, -1, -1, 0, -psi - reach});
    }
    std::vector<double> theta;
    if (!nearestFeasible(phi, hs, theta, 1e-9)) continue;  // no such fan: the construction's stays
    if (out.tangents.empty()) out.tangents.assign(size_t(ns) * 6, 0.0), out.turnDeg.assign(size_t(ns) * 2, 0.0);
    out.vertices.push_back(v);
    for (int i = 0; i < m; ++i) {
      const Vec3 d = std::cos(theta[i]) * u + std::sin(theta[i]) * w;
      const Vec3 o = at(own, 2 * size_t(fan[i]));  // the construction's direction (unit, in the plane)
      const double turn = angleBetween(o, d) * 180 / kPi;
      out.maxTurnDeg = std::max(out.maxTurnDeg, turn);
      const size_t twin = size_t(c.slotTwin[fan[i]]);  // the same edge, ending at v
      double* start3 = &out.tangents[6 * size_t(fan[i])];
      double* end3 = &out.tangents[6 * twin + 3];
      for (int j = 0; j < 3; ++j) start3[j] = d[j], end3[j] = -d[j];
      out.turnDeg[2 * size_t(fan[i])] = out.turnDeg[2 * twin + 1] = turn;
    }
  }
  return out;
}

void refreshEdgeTangents(PatchCache& cache) { cache.edgeTangents = untangleTangentFans(cache).tangents; }

bool givesEndTangents(const std::vector<double>& tangents, size_t first, size_t last) {
  if (tangents.empty()) return false;
  for (size_t i = 6 * first; i < 6 * last; ++i)
    if (tangents[i] != 0) return true;
  return false;
}

bool faceHasEdgeTangents(const PatchCache& c, int f) {
  return givesEndTangents(c.edgeTangents, size_t(c.faceOffsets[f]), size_t(c.faceOffsets[f + 1]));
}

}  // namespace sf
