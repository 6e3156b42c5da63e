// SPDX-License-Identifier: Apache-2.0
// Patch construction on the CPU (serial and oneTBB).
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>
#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <numbers>
#include <stdexcept>
#include <string>
#include <type_traits>
#include <utility>

#include <smoothforce/base/error.h>
#include <smoothforce/base/thread_limit.h>
#include <smoothforce/mesh/normals.h>
#include <smoothforce/mesh/topology.h>
#include <smoothforce/patch/detail/face_inputs.h>
#include <smoothforce/patch/detail/gp_traits.h>
#include <smoothforce/patch/patch_build.h>
#include <smoothforce/patch/patch_cache.h>
#include <smoothforce/patch/tangent_fans.h>

#include "patch_simd_detail.h"

namespace sf {

size_t PatchCache::bytes() const {
  return positions.size() * sizeof(double) + faceOffsets.size() * sizeof(int32_t) +
         faceVertices.size() * sizeof(int32_t) + cornerNormals.size() * sizeof(double) +
         slotTwin.size() * sizeof(int32_t) + faceStatus.size() * sizeof(uint32_t) + faceBulge.size() * sizeof(float) +
         faceCertificate.size() * sizeof(float) + faceSource.size() * sizeof(int32_t) +
         computedNormals.size() * sizeof(double) + edgeTangents.size() * sizeof(double) +
         edgeDataD.size() * sizeof(double) + edgeDataF.size() * sizeof(float);
}

double PatchCache::normalTurnDeg(int s) const {
  if (computedNormals.empty()) return 0;
  const Eigen::Map<const Eigen::Vector3d> a(&computedNormals[3 * size_t(s)]), b(&cornerNormals[3 * size_t(s)]);
  if (a == b) return 0;
  return angleBetween(a, b) * 180 / std::numbers::pi;
}

void acrossCorners(const PatchCache& c, int f, int k, int32_t& atStart, int32_t& atEnd) {
  acrossCorners(c.faceOffsets, c.slotTwin, f, k, atStart, atEnd);
}

bool cornerNormalsDiffer(const PatchCache& c, int32_t a, int32_t b) {
  const double *na = &c.cornerNormals[3 * static_cast<size_t>(a)], *nb = &c.cornerNormals[3 * static_cast<size_t>(b)];
  return na[0] != nb[0] || na[1] != nb[1] || na[2] != nb[2];
}

bool isCreaseEdge(const PatchCache& c, int f, int k) {
  const int first = c.faceOffsets[f], n = c.faceSize(f);
  if (c.slotTwin[first + k] < 0) return false;
  int32_t a, b;
  acrossCorners(c, f, k, a, b);
  return cornerNormalsDiffer(c, first + k, a) || cornerNormalsDiffer(c, first + (k + 1 == n ? 0 : k + 1), b);
}

bool faceHasCrease(const PatchCache& c, int f) {
  for (int k = 0, n = c.faceSize(f); k < n; ++k)
    if (isCreaseEdge(c, f, k)) return true;
  return false;
}

std::vector<uint8_t> creaseVertexFlags(const PatchCache& c) {
  std::vector<uint8_t> flags(c.numVertices(), 0);
  std::vector<int32_t> first(c.numVertices(), -1);  // a corner of each vertex
  for (int32_t s = 0; s < c.numSlots(); ++s) {
    const int32_t v = c.faceVertices[s];
    if (first[v] < 0)
      first[v] = s;
    else if (cornerNormalsDiffer(c, first[v], s))
      flags[v] = 1;
  }
  return flags;
}

double boundingDiagonal(const PatchCache& cache) {
  Eigen::Vector3d lo, hi;
  referencedBox(cache, lo, hi);
  return (hi - lo).norm();
}

bool referencedBox(const PatchCache& cache, Eigen::Vector3d& lo, Eigen::Vector3d& hi) {
  return referencedBox(cache.positions.data(), cache.faceVertices.data(), cache.faceVertices.size(), lo, hi);
}

std::string floatReachProblem(const Eigen::Vector3d& lo, const Eigen::Vector3d& hi, Precision precision) {
  const double diag = (hi - lo).norm(), far = std::max(lo.cwiseAbs().maxCoeff(), hi.cwiseAbs().maxCoeff());
  // (a mesh of one point has no size to lose: its faces are flagged as zero edges instead)
  if (precision != Precision::Float || far <= kFloatReachDiagonals * diag || !(diag > 0) || !std::isfinite(far))
    return {};
  char buf[320];
  std::snprintf(buf, sizeof buf,
                "float precision: the mesh's coordinates reach %.4g m, %.3g times its bounding-box diagonal (%.4g m), "
                "where float rounds them by %.3g m; use double precision (float holds a mesh within %g diagonals of the "
                "origin)",
                far, far / diag, diag, double(std::nextafter(float(far), INFINITY) - float(far)), kFloatReachDiagonals);
  return buf;
}

void requireLazyOptions(const PatchOptions& options) {
  if (options.foldRepair == FoldRepairMode::Search)
    throw InputError(
        "fold_repair search needs every patch of the surface before the first contact: build a cache (smoothforce "
        "cache build, or a cache that is not lazy), or use on");
}

PatchCache preparePatchCache(const PolygonMesh& mesh, const std::vector<Eigen::Vector3d>& cornerNormals,
                             const PatchOptions& options, uint64_t meshHash, bool allocatePatches) {
  if (!allocatePatches) requireLazyOptions(options);
  if (static_cast<int>(cornerNormals.size()) != mesh.numCorners())
    throw std::invalid_argument("preparePatchCache: need one normal per corner");
  PatchCache c;
  c.options = options;
  c.meshHash = meshHash;
  c.positions.reserve(mesh.positions.size() * 3);
  for (const auto& p : mesh.positions) c.positions.insert(c.positions.end(), {p.x(), p.y(), p.z()});
  c.faceOffsets = mesh.faceOffsets;
  c.faceVertices = mesh.faceVertices;
  if (static_cast<int>(mesh.faceSource.size()) == mesh.numFaces() && options.foldRepair != FoldRepairMode::Off)
    c.faceSource = mesh.faceSource;
  else if (options.foldRepair != FoldRepairMode::Off)
    for (int f = 0; f < mesh.numFaces(); ++f) c.faceSource.push_back(f);
  c.cornerNormals.reserve(cornerNormals.size() * 3);
  for (const auto& n : cornerNormals) c.cornerNormals.insert(c.cornerNormals.end(), {n.x(), n.y(), n.z()});
  {
    Eigen::Vector3d lo, hi;
    referencedBox(mesh, lo, hi);
    if (const std::string why = floatReachProblem(lo, hi, options.precision); !why.empty()) throw InputError(why);
  }
  c.slotTwin = computeSlotTwins(mesh);
  c.faceStatus.assign(mesh.numFaces(), 0u);
  c.faceBulge.assign(mesh.numFaces(), 0.f);
  const size_t recs = static_cast<size_t>(GP_E_NFIELDS) * mesh.numCorners();
  if (!allocatePatches) {  // lazy construction reads the fans from here; a whole build makes its own
    refreshEdgeTangents(c);
    return c;
  }
  if (options.precision == Precision::Double)
    c.edgeDataD.assign(recs, 0.0);
  else
    c.edgeDataF.assign(recs, 0.f);
  return c;
}

namespace {

template <class Real>
std::vector<Real>& edgeData(PatchCache& c);
template <>
std::vector<double>& edgeData<double>(PatchCache& c) {
  return c.edgeDataD;
}
template <>
std::vector<float>& edgeData<float>(PatchCache& c) {
  return c.edgeDataF;
}

template <class Real>
void gather(const PatchCache& c, const std::vector<Real>& data, int f, Real* recs) {
  const int n = c.faceSize(f), first = c.faceOffsets[f];
  const size_t ns = c.numSlots();
  for (int i = 0; i < GP_E_NFIELDS; ++i)  // a field's n values lie side by side
    for (int k = 0; k < n; ++k) recs[k * GP_E_NFIELDS + i] = data[i * ns + first + k];
}

template <class Real>
double affineMargin(int n, const Real* recs, double tol) {
  if (n != 3) return 0;
  auto get = [&](int k, int field) {
    const Real* r = recs + k * GP_E_NFIELDS + field;
    return Eigen::Vector3d(double(r[0]), double(r[1]), double(r[2]));
  };
  const Eigen::Vector3d v0 = get(0, GP_E_V0), e1 = get(1, GP_E_V0) - v0, e2 = get(2, GP_E_V0) - v0;
  const Eigen::Vector3d cross = e1.cross(e2);
  double longest = 0;
  for (int k = 0; k < 3; ++k) longest = std::max(longest, (get(k, GP_E_V1) - get(k, GP_E_V0)).norm());
  if (!(cross.norm() > tol * longest * longest)) return 0;  // also NaN
  const Eigen::Vector3d normal = cross.normalized();
  // the plane's basis (u, w, normal) and the affine map's in-plane Jacobian A (columns d/dxi,
  // d/deta; gp_patch_eval_affine3)
  const Eigen::Vector3d u = e1.normalized(), w = normal.cross(u);
  gpd::gp_domain scratch;
  const gpd::gp_domain* dom = gpd::gp_domain_of(3, &scratch, 0);
  const double ih = 1.0 / (3.0 * dom->apothem);
  const Eigen::Vector3d jx = -(dom->mx[2] * e1 + dom->mx[0] * e2) * ih, jy = -(dom->my[2] * e1 + dom->my[0] * e2) * ih;
  Eigen::Matrix2d A;
  A << jx.dot(u), jy.dot(u), jx.dot(w), jy.dot(w);
  const double det = A.determinant();
  if (!(det > 0)) return 0;
  Eigen::Matrix2d adj;
  adj << A(1, 1), -A(0, 1), -A(1, 0), A(0, 0);
  // The curved edges' part P of the Jacobian: per edge k, -ih times the gradients' directions
  // m_{k-1}, m_{k+1} (of d_{k-1}, d_{k+1}) times combinations of a = M0 - E and b = M1 - E with
  // coefficients cubic in t = t_k: alpha = (1-t)^2 (1-2t), beta = 2t(1-t)^2 (for d_{k-1}),
  // gamma = 2t^2(1-t), delta = t^2(2t-1) (for d_{k+1}). In the plane,
  // det(A + s P) = det A + s tr(adj(A) P) + s^2 det P, and tr(adj(A) P) = -ih sum_k f_k(t_k) with
  // f_k(t) = m_{k-1}.adj(A)(alpha a - beta b) + m_{k+1}.adj(A)(gamma a - delta b), a cubic whose
  // largest value on [0, 1] (at an end or where f' = 0) bounds it, each t_k taken independently
  // (the direction of each deviation against A counts: one along the triangle's tall direction
  // moves det little). det P = sum_k det P_k + sum_{j<k} tr(adj(P_j) P_k), with
  // det P_k = ih^2 (beta gamma - alpha delta) det(a, b) det(m_{k-1}, m_{k+1}), that coefficient
  // t^2 (1-t)^2 <= 1/16, and |tr(adj(P_j) P_k)| <= |P_j| |P_k| (Frobenius norms, bounded from the
  // coefficients' largest values 1, 8/27, 8/27, 1). det(A + s P) > 0 for every s in [0, 1] where
  // the bound below is: regular, and on the plane's side from the affine map (s = 0) on.
  double T = 0, norm = 0, out = 0, detP = 0, norms[3] = {0, 0, 0};
  for (int k = 0; k < 3; ++k) {
    const Eigen::Vector3d chord = get(k, GP_E_V1) - get(k, GP_E_V0), m0 = get(k, GP_E_M0), m1 = get(k, GP_E_M1);
    const double len = chord.norm();
    // the corner normals are the plane's; the end tangents lie in it and run along the edge
    if (!((get(k, GP_E_N0) - normal).norm() <= tol && (get(k, GP_E_N1) - normal).norm() <= tol &&
          std::abs(m0.dot(normal)) <= tol * len && std::abs(m1.dot(normal)) <= tol * len && m0.dot(chord) > 0 &&
          m1.dot(chord) > 0))
      return 0;
    const Eigen::Vector3d a3 = m0 - chord, b3 = m1 - chord;
    const Eigen::Vector2d a(a3.dot(u), a3.dot(w)), b(b3.dot(u), b3.dot(w));
    const int km = k == 0 ? 2 : k - 1, kp = k == 2 ? 0 : k + 1;
    const Eigen::Vector2d gm(dom->mx[km], dom->my[km]), gp(dom->mx[kp], dom->my[kp]);
    const double A1 = gm.dot(adj * a), B1 = gm.dot(adj * b), A2 = gp.dot(adj * a), B2 = gp.dot(adj * b);
    const double c[4] = {A1, -4 * A1 - 2 * B1, 5 * A1 + 4 * B1 + 2 * A2 + B2, -2 * (A1 + B1 + A2 + B2)};
    auto f = [&](double t) { return c[0] + t * (c[1] + t * (c[2] + t * c[3])); };
    double top = std::max(f(0), f(1));
    // f' = c1 + 2 c2 t + 3 c3 t^2
    const double qa = 3 * c[3], qb = 2 * c[2], qc = c[1];
    if (qa != 0) {
      const double disc = qb * qb - 4 * qa * qc;
      if (disc >= 0)
        for (const double sg : {-1.0, 1.0})
          if (const double t = (-qb + sg * std::sqrt(disc)) / (2 * qa); t > 0 && t < 1) top = std::max(top, f(t));
    } else if (qb != 0) {
      if (const double t = -qc / qb; t > 0 && t < 1) top = std::max(top, f(t));
    }
    // rounding of the coefficients and of the cubic's value: a relative 1e-12 of their sizes
    top += 1e-12 * (std::abs(A1) + std::abs(B1) + std::abs(A2) + std::abs(B2));
    T += ih * top;
    norms[k] = ih * 35.0 / 27.0 * (a3.norm() + b3.norm());
    norm += norms[k];
    detP += ih * ih / 16.0 * std::abs(a.x() * b.y() - a.y() * b.x()) * std::abs(gm.x() * gp.y() - gm.y() * gp.x());
    out += ih * 35.0 / 27.0 * (std::abs(a3.dot(normal)) + std::abs(b3.dot(normal)));
  }
  T = std::max(T, 0.0);
  detP += norms[0] * norms[1] + norms[0] * norms[2] + norms[1] * norms[2];
  const double lower = det - T - detP;
  // a relative 1e-9 for the rounding of the above (each a few operations on the records)
  if (!(lower > 1e-9 * det)) return 0;
  // cosine to the plane's normal: n . (Jx x Jy) = det(A + P) >= lower, and the part of Jx x Jy
  // across the normal comes from the out-of-plane parts of P only
  const double across = out * (jx.norm() + jy.norm() + 2 * norm);
  return lower / std::hypot(lower, across);
}

/// Status st of a built face with records recs, with GP_ST_AFFINE where markAffineTriangles gives
/// it, the quality bits and bulge (where bulgeOut is not null) then from the affine map.
template <class Real>
uint32_t withAffine(const PatchCache& c, int n, const Real* recs, uint32_t st, float* bulgeOut, bool quality) {
  if (c.options.foldRepair == FoldRepairMode::Off || (st & (GP_ST_DEGENERATE_MASK | GP_ST_AFFINE)) ||
      !isAffineTriangle(n, recs))
    return st;
  st |= GP_ST_AFFINE;
  if (!quality) return st;
  Real bulge = 0;
  const int mode = gpd::gp_eval_mode(static_cast<int>(c.options.crossTangent), st);
  st = (st & ~(GP_ST_FOLD | GP_ST_BULGE)) | Gp<Real>::quality(n, recs, mode, &bulge);
  if (bulgeOut) *bulgeOut = static_cast<float>(bulge);
  return st;
}

template <class Real>
uint32_t buildRecords(const PatchCache& c, int f, Real* recs, float* bulgeOut, bool quality = true) {
  using G = Gp<Real>;
  const int n = c.faceSize(f), first = c.faceOffsets[f];
  if (bulgeOut) *bulgeOut = 0.f;
  if (n < 3 || n > GP_MAX_N) return GP_ST_TOO_MANY_SIDES;
  typename G::vec3 V[GP_MAX_N], N[GP_MAX_N], PS[GP_MAX_N], PE[GP_MAX_N], TS[GP_MAX_N], TE[GP_MAX_N];
  int vid[GP_MAX_N];
  const bool creased = detail::faceInputs<G>(c, f, V, N, vid, PS, PE), turned = faceHasEdgeTangents(c, f);
  for (int k = 0; k < n && turned; ++k) {
    const double* t = &c.edgeTangents[6 * static_cast<size_t>(first + k)];
    TS[k] = G::v3(t[0], t[1], t[2]);
    TE[k] = G::v3(t[3], t[4], t[5]);
  }
  const int mode = static_cast<int>(c.options.crossTangent);
  gp_uint st = G::buildWith(n, V, N, PS, PE, creased, turned ? TS : nullptr, turned ? TE : nullptr, vid, mode, recs);
  Real bulge = 0;
  if (quality && !(st & GP_ST_NOT_BUILT)) st |= G::quality(n, recs, mode, &bulge);
  if (bulgeOut) *bulgeOut = static_cast<float>(bulge);
  return withAffine(c, n, recs, st, bulgeOut, quality);
}

/// Builds face f with buildRecords and scatters the records field-major into the cache.
template <class Real>
void buildFace(PatchCache& c, int f) {
  Real recs[GP_MAX_N * GP_E_NFIELDS];
  c.faceStatus[f] = buildRecords(c, f, recs, &c.faceBulge[f]);
  if (c.faceStatus[f] & GP_ST_TOO_MANY_SIDES) return;
  const int n = c.faceSize(f), first = c.faceOffsets[f];
  std::vector<Real>& data = edgeData<Real>(c);
  const size_t ns = c.numSlots();
  for (int k = 0; k < n; ++k)
    for (int i = 0; i < GP_E_NFIELDS; ++i) data[i * ns + first + k] = recs[k * GP_E_NFIELDS + i];
}

/// Faces by size: the SIMD path builds faces of one size side by side. Faces with a crease edge
/// or given end tangents are listed apart (creased): they are built one at a time, with the other
/// faces' normals and those tangents.
struct SizeGroups {
  std::vector<int32_t> faces;    // grouped by size n (3..GP_MAX_N), then in order
  std::vector<size_t> start;     // faces of size n: [start[n], start[n + 1])
  std::vector<int32_t> creased;  // faces with a crease edge or given end tangents, in order
};
// the i-th of the faces `faces` (null: all of c's) and their number
int faceAt(const std::vector<int>* faces, int i) { return faces ? (*faces)[i] : i; }
int faceCount(const PatchCache& c, const std::vector<int>* faces) {
  return faces ? static_cast<int>(faces->size()) : c.numFaces();
}

// the faces `faces` (null: all) by size
SizeGroups groupBySize(const PatchCache& c, const std::vector<int>* faces) {
  SizeGroups g;
  g.start.assign(GP_MAX_N + 2, 0);
  std::vector<char> plain(c.numFaces(), 0);
  const int count = faceCount(c, faces);
  for (int i = 0; i < count; ++i) {
    const int f = faceAt(faces, i);
    const int n = c.faceSize(f);
    if (n < 3 || n > GP_MAX_N) continue;
    if (faceHasCrease(c, f) || faceHasEdgeTangents(c, f)) {
      g.creased.push_back(f);
      continue;
    }
    plain[f] = 1;
    ++g.start[n + 1];
  }
  for (int n = 0; n <= GP_MAX_N; ++n) g.start[n + 1] += g.start[n];
  g.faces.resize(g.start[GP_MAX_N + 1]);
  std::vector<size_t> pos(g.start.begin(), g.start.end() - 1);
  for (int i = 0; i < count; ++i)
    if (const int f = faceAt(faces, i); plain[f]) g.faces[pos[c.faceSize(f)]++] = f;
  return g;
}

// builds the faces `faces` (null: all)
template <class Real>
void buildAll(PatchCache& c, const BuildOptions& o, const std::vector<int>* faces) {
  const int nf = faceCount(c, faces);
  auto face = [faces](int i) { return faceAt(faces, i); };
  const SimdTarget target = resolveSimdTarget(o.simd);
  auto inArena = [&](auto&& body) {
    if (o.backend == Backend::Serial) return body();
    if (o.threads > 0) {
      tbb::task_arena arena(arenaThreads(o.threads));
      return arena.execute(body);
    }
    return body();
  };
  if (target == SimdTarget::Scalar) {
    if (o.backend == Backend::Serial) {
      for (int i = 0; i < nf; ++i) buildFace<Real>(c, face(i));
      return;
    }
    inArena([&] {
      tbb::parallel_for(tbb::blocked_range<int>(0, nf, 64), [&](const tbb::blocked_range<int>& r) {
        for (int i = r.begin(); i != r.end(); ++i) buildFace<Real>(c, face(i));
      });
    });
    return;
  }
  const simd_detail::BuildFns* fns = simd_detail::buildFns(target);
  const simd_detail::BuildFn fn = std::is_same_v<Real, double> ? fns->buildD : fns->buildF;
  for (int i = 0; i < nf; ++i) {  // faces without a patch: as buildFace leaves them
    const int f = face(i), n = c.faceSize(f);
    if (n < 3 || n > GP_MAX_N) c.faceStatus[f] = GP_ST_TOO_MANY_SIDES, c.faceBulge[f] = 0.f;
  }
  const SizeGroups g = groupBySize(c, faces);
  // work items: runs of up to 64 faces of one size
  std::vector<std::pair<size_t, size_t>> items;
  for (int n = 3; n <= GP_MAX_N; ++n)
    for (size_t b = g.start[n]; b < g.start[n + 1]; b += 64) items.emplace_back(b, std::min(b + 64, g.start[n + 1]));
  // then the faces with a crease, one at a time, as items of 64
  const size_t runs = items.size();
  for (size_t b = 0; b < g.creased.size(); b += 64) items.emplace_back(b, std::min(b + 64, g.creased.size()));
  auto one = [&](size_t i) {
    if (i >= runs) {
      for (size_t j = items[i].first; j < items[i].second; ++j) buildFace<Real>(c, g.creased[j]);
      return;
    }
    fn(c, g.faces.data() + items[i].first, items[i].second - items[i].first);
  };
  if (o.backend == Backend::Serial) {
    for (size_t i = 0; i < items.size(); ++i) one(i);
    return;
  }
  inArena([&] {
    tbb::parallel_for(tbb::blocked_range<size_t>(0, items.size(), 1), [&](const tbb::blocked_range<size_t>& r) {
      for (size_t i = r.begin(); i != r.end(); ++i) one(i);
    });
  });
}

template <class Real>
void markAffine(PatchCache& c, const std::vector<int>* faces) {
  if (c.options.foldRepair == FoldRepairMode::Off) return;
  const std::vector<Real>& data = edgeData<Real>(c);
  Real recs[3 * GP_E_NFIELDS];
  for (int i = 0, count = faceCount(c, faces); i < count; ++i) {
    const int f = faceAt(faces, i);
    if (c.faceSize(f) != 3 || (c.faceStatus[f] & (GP_ST_NOT_BUILT | GP_ST_AFFINE))) continue;
    gather(c, data, f, recs);
    c.faceStatus[f] = withAffine(c, 3, recs, c.faceStatus[f], &c.faceBulge[f], true);
  }
}

}  // namespace

namespace {

void buildFaces(PatchCache& cache, const BuildOptions& options, const std::vector<int>* faces, const char* caller) {
  if (options.backend == Backend::OpenCL)
    throw std::invalid_argument(std::string(caller) + ": use the OpenCL backend's constructPatchesOpenCL");
  if (!hasPatchData(cache) && cache.numFaces() > 0)
    throw std::invalid_argument(std::string(caller) + ": the cache has no patch arrays (prepared as a skeleton)");
  if (faces) {
    std::vector<char> seen(cache.numFaces(), 0);
    for (const int f : *faces) {
      if (f < 0 || f >= cache.numFaces())
        throw std::invalid_argument(std::string(caller) + ": face " + std::to_string(f) + " out of range [0, " +
                                    std::to_string(cache.numFaces()) + ")");
      if (seen[f]++) throw std::invalid_argument(std::string(caller) + ": face " + std::to_string(f) + " given twice");
    }
  }
  refreshEdgeTangents(cache);  // the fans of the normals the patches are built from
  if (cache.options.precision == Precision::Double)
    buildAll<double>(cache, options, faces);
  else
    buildAll<float>(cache, options, faces);
  markAffineTriangles(cache, faces);  // the SIMD path builds lanes of different faces: marked here
}

}  // namespace

void constructPatches(PatchCache& cache, const BuildOptions& options) {
  buildFaces(cache, options, nullptr, "constructPatches");
}

void constructPatchesOf(PatchCache& cache, const std::vector<int>& faces, const BuildOptions& options) {
  buildFaces(cache, options, &faces, "constructPatchesOf");
}

void constructPatches(PatchCache& cache, Backend backend, int threads) {
  BuildOptions o;
  o.backend = backend;
  o.threads = threads;
  constructPatches(cache, o);
}

uint32_t buildPatchRecords(const PatchCache& skeleton, int f, double* recs, float* bulge) noexcept {
  return buildRecords(skeleton, f, recs, bulge);
}
uint32_t buildPatchRecords(const PatchCache& skeleton, int f, float* recs, float* bulge) noexcept {
  return buildRecords(skeleton, f, recs, bulge);
}

uint32_t buildPatchEdges(const PatchCache& skeleton, int f, double* recs) noexcept {
  return buildRecords(skeleton, f, recs, nullptr, false);
}

double affineTriangleMargin(int n, const double* recs, double tolerance) { return affineMargin(n, recs, tolerance); }
double affineTriangleMargin(int n, const float* recs, double tolerance) { return affineMargin(n, recs, tolerance); }
bool isAffineTriangle(int n, const double* recs, double tolerance) { return affineMargin(n, recs, tolerance) > 0; }
bool isAffineTriangle(int n, const float* recs, double tolerance) { return affineMargin(n, recs, tolerance) > 0; }

void markAffineTriangles(PatchCache& cache, const std::vector<int>* faces) {
  if (!hasPatchData(cache) && cache.numFaces() > 0)
    throw std::invalid_argument("markAffineTriangles: the cache has no patch arrays (prepared as a skeleton)");
  if (cache.options.precision == Precision::Double)
    markAffine<double>(cache, faces);
  else
    markAffine<float>(cache, faces);
}

void gatherRecords(const PatchCache& cache, int f, double* recs) { gather(cache, cache.edgeDataD, f, recs); }
void gatherRecords(const PatchCache& cache, int f, float* recs) { gather(cache, cache.edgeDataF, f, recs); }

}  // namespace sf
