// SPDX-License-Identifier: Apache-2.0
// The per-patch certificate: the patch math of kernels/ instantiated once more with an
// interval type (detail/gp_interval.h) and bounded on boxes of the domain.
#include <smoothforce/patch/patch_certificate.h>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include <Eigen/Geometry>

#include <algorithm>
#include <array>
#include <cmath>
#include <stdexcept>

#include <smoothforce/patch/detail/gp_interval.h>
#include <smoothforce/patch/detail/gp_math.h>
#include <smoothforce/patch/detail/patch_enclosure.h>
#include <smoothforce/patch/normal_groups.h>
#include <smoothforce/patch/patch_build.h>

// ---- the patch math on intervals (GP_INTERVAL: gp_eval.h's range-keeping forms) ----
namespace sf::gpi {
using ::sf::gpd::gp_domain;
using ::sf::gpd::gp_domain_of;
using ::sf::gpd::gp_quality_sample;
using ::sf::interval::Taylor;
using gp_lane_mask = ::sf::interval::Mask;
using gp_lane_status = unsigned;
using gp_lane_vid = int;
#define GP_LANES 1
#define GP_INTERVAL 1
#define GP_SREAL double
#define GP_REAL ::sf::interval::Taylor
#define GP_IS_DOUBLE 1
#include "gp_instantiate.h"
}  // namespace sf::gpi

namespace sf {
namespace {

using interval::Interval;
using interval::Taylor;

struct Box {
  double x0, x1, y0, y1;
  int depth;
  double d[3];  ///< unit direction J is bounded along on this box
};

/// The Taylor models of a box's coordinates: centre plus half-width times its symbol.
void boxForms(double x0, double x1, double y0, double y1, Taylor* xi, Taylor* eta) {
  const double cx = 0.5 * (x0 + x1), cy = 0.5 * (y0 + y1);
  *xi = Taylor(cx, interval::roundUp(std::max(x1 - cx, cx - x0)), 0.0, 0.0);
  *eta = Taylor(cy, 0.0, interval::roundUp(std::max(y1 - cy, cy - y0)), 0.0);
}

/// The patch math's enclosure over a box of the domain, with derivatives.
gpi::gp_eval_result evalBox(const gpd::gp_domain* dom, const std::array<Taylor, GP_MAX_N * GP_E_NFIELDS>& irecs,
                            int mode, double x0, double x1, double y0, double y1) {
  Taylor xi, eta;
  boxForms(x0, x1, y0, y1, &xi, &eta);
  return gpi::gp_patch_eval_dom_d(dom, irecs.data(), mode, xi, eta, 1);
}

/// J = dot(dG/dxi x dG/deta, d) and the upper bound of |dG/dxi x dG/deta| over a box, from its
/// enclosure r.
struct CellBound {
  Interval J;
  double lenHi;
};
CellBound boundJ(const gpi::gp_eval_result& r, const double d[3]) {
  const gpi::gp_vec3 N = gpi::gp_cross(r.dxi, r.deta);
  return {(N.x * Taylor(d[0]) + N.y * Taylor(d[1]) + N.z * Taylor(d[2])).range(),
          gp_sqrt(N.x * N.x + N.y * N.y + N.z * N.z).hi()};
}
CellBound boundCell(const gpd::gp_domain* dom, const std::array<Taylor, GP_MAX_N * GP_E_NFIELDS>& irecs, int mode,
                    double x0, double x1, double y0, double y1, const double d[3]) {
  return boundJ(evalBox(dom, irecs, mode, x0, x1, y0, y1), d);
}

/// d = the unit patch normal at the domain point nearest the centre of box b (double records
/// drecs); d unchanged where that normal is not defined (singular, not finite).
void centreNormal(int n, const double* drecs, int mode, const Box& b, double d[3]) {
  double x = 0.5 * (b.x0 + b.x1), y = 0.5 * (b.y0 + b.y1);
  gpd::gp_dom_clamp(n, &x, &y);
  const gpd::gp_eval_result p = gpd::gp_patch_eval(n, drecs, mode, x, y);
  const double l2 = p.normal.x * p.normal.x + p.normal.y * p.normal.y + p.normal.z * p.normal.z;
  if ((p.status & (GP_ST_OUTSIDE | GP_ST_SINGULAR)) || !(std::abs(l2 - 1) < 1e-6)) return;
  d[0] = p.normal.x, d[1] = p.normal.y, d[2] = p.normal.z;
}

/// The certificate along one fixed direction d (unnormalised; any d != 0 makes a valid test):
/// J = dot(dG/dxi x dG/deta, d / |d|) bounded over the domain as certifyPatch describes. With
/// local directions (drecs, the records in double), each box is bounded along the unit normal at
/// its own centre instead (d is the start's), which proves dG/dxi x dG/deta != 0 on it: the
/// patch is regular, not a height field; a box proven negative then proves nothing.
PatchCertificate certifyAlong(int n, const std::array<Taylor, GP_MAX_N * GP_E_NFIELDS>& irecs, int mode,
                              const CertificateOptions& o, const double d[3], const double* drecs = nullptr) {
  PatchCertificate out;
  const double nl = std::sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
  out.verdict = CertificateVerdict::Undecided;
  if (!(nl > 0) || !std::isfinite(nl)) return out;
  const bool local = drecs != nullptr;
  for (int i = 0; i < 3; ++i) out.direction[i] = local ? 0.0 : d[i] / nl;

  gpd::gp_domain scratch;
  const gpd::gp_domain* dom = gpd::gp_domain_of(n, &scratch, 1);
  double lo[2] = {1e300, 1e300}, hi[2] = {-1e300, -1e300};
  for (int k = 0; k < n; ++k) {
    lo[0] = std::min(lo[0], dom->cx[k]), hi[0] = std::max(hi[0], dom->cx[k]);
    lo[1] = std::min(lo[1], dom->cy[k]), hi[1] = std::max(hi[1], dom->cy[k]);
  }
  std::vector<Box> stack;
  const int maxDepth = n == 3 ? o.triangleMaxDepth : o.maxDepth, maxCells = n == 3 ? o.triangleMaxCells : o.maxCells;
  // a marked patch reaches here only without its bound's proof (certifyWith): one cell first, the
  // domain's box, which decides it where its edges are straight (J constant)
  const int start = (mode & GP_EVAL_AFFINE)
                        ? 0
                        : std::clamp(n == 4 ? o.quadStartDepth : o.startDepth, 0, std::max(0, maxDepth)),
            g = 1 << std::min(start, 12);
  for (int j = g - 1; j >= 0; --j)
    for (int i = g - 1; i >= 0; --i)
      stack.push_back({lo[0] + (hi[0] - lo[0]) * i / g, lo[0] + (hi[0] - lo[0]) * (i + 1) / g,
                       lo[1] + (hi[1] - lo[1]) * j / g, lo[1] + (hi[1] - lo[1]) * (j + 1) / g, start,
                       {d[0] / nl, d[1] / nl, d[2] / nl}});
  double margin = 1;
  bool undecided = false;
  while (!stack.empty()) {
    Box b = stack.back();
    stack.pop_back();
    const Interval bx(b.x0, b.x1), by(b.y0, b.y1);
    bool meets = true;  // the box meets the domain (not proven outside one of its edges)
    for (int k = 0; k < n && meets; ++k) meets = (Interval(dom->apothem) - (bx * dom->mx[k] + by * dom->my[k])).hi >= 0;
    if (!meets) continue;
    if (out.cells >= maxCells) {
      undecided = true;
      break;
    }
    ++out.cells;
    if (local) centreNormal(n, drecs, mode, b, b.d);  // else the parent's stays
    const CellBound c = boundCell(dom, irecs, mode, b.x0, b.x1, b.y0, b.y1, b.d);
    if (c.J.lo > 0 && c.lenHi < interval::kInf) {
      margin = std::min(margin, interval::roundDown(c.J.lo / interval::roundUp(c.lenHi)));
      continue;
    }
    if (!local && c.J.hi < 0 && c.lenHi > 0) {  // every point of the box, some of them in the domain, turns over
      out.verdict = CertificateVerdict::Folded;
      out.margin = c.lenHi < interval::kInf ? std::min(-1e-300, c.J.hi / c.lenHi) : -1e-300;
      return out;
    }
    if (b.depth >= maxDepth) {
      undecided = true;
      if (local) break;  // no fold to look for
      continue;          // keep looking for a proven fold elsewhere
    }
    const double xm = 0.5 * (b.x0 + b.x1), ym = 0.5 * (b.y0 + b.y1);
    const int dd = b.depth + 1;
    stack.push_back({b.x0, xm, b.y0, ym, dd, {b.d[0], b.d[1], b.d[2]}});
    stack.push_back({xm, b.x1, b.y0, ym, dd, {b.d[0], b.d[1], b.d[2]}});
    stack.push_back({b.x0, xm, ym, b.y1, dd, {b.d[0], b.d[1], b.d[2]}});
    stack.push_back({xm, b.x1, ym, b.y1, dd, {b.d[0], b.d[1], b.d[2]}});
  }
  if (undecided) return out;
  out.verdict = CertificateVerdict::Certified;
  out.margin = std::max(margin, 1e-300);
  return out;
}

/// How the patch meets its edges and corners: its normal along the edge normal n_c at each
/// edge's midpoint (t = 1/2) and along the vertex normal N_k at each corner, where the G1
/// construction makes it parallel to them, bounded on a box of width 2e-9 just inside the domain
/// there. -1: proven against one of them (the patch meets its neighbours, which share n_c and
/// N_k, upside down there: it folds against them; *margin the upper bound < 0 of the cosine);
/// +1: proven along n_c at every edge's midpoint; 0: neither.
int boundaryOrientation(int n, const std::array<Taylor, GP_MAX_N * GP_E_NFIELDS>& irecs, const double* drecs, int mode,
                        double* margin) {
  gpd::gp_domain scratch;
  const gpd::gp_domain* dom = gpd::gp_domain_of(n, &scratch, 1);
  int verdict = 1;
  const double s = 1 - 1e-7, h = 1e-9;  // just inside the domain
  for (int k = 0; k < n; ++k) {
    const double* rec = drecs + k * GP_E_NFIELDS;
    for (int corner = 0; corner < 2; ++corner) {
      double d[3], x = 0, y = 0;
      if (corner) {
        const double* nk = rec + GP_E_N0;
        for (int i = 0; i < 3; ++i) d[i] = nk[i];
        x = dom->cx[k], y = dom->cy[k];
      } else {
        gpd::gp_dvec3 c, cp;
        gpd::gp_edge_curve(rec, 0.5, &c, &cp);
        gp_uint st = 0u;
        const gpd::gp_dvec3 nc = gpd::gp_edge_normal(rec, 0.5, cp, gpd::gp_edge_length(rec), &st);
        d[0] = nc.v.x, d[1] = nc.v.y, d[2] = nc.v.z;
        gpd::gp_dom_edge_point(n, k, 0.5, &x, &y);
      }
      const CellBound b = boundCell(dom, irecs, mode, x * s - h, x * s + h, y * s - h, y * s + h, d);
      if (b.J.hi < 0 && b.lenHi > 0) {
        *margin = b.lenHi < interval::kInf ? std::min(-1e-300, b.J.hi / b.lenHi) : -1e-300;
        return -1;
      }
      // a corner right side up follows from its two edges' midpoints, a normal that vanishes
      // nowhere and G1 (the enclosure at a triangle's corner may be unbounded): only a corner
      // proven upside down decides
      if (!corner && !(b.J.lo > 0)) verdict = 0;
    }
  }
  return verdict;
}

/// True where unit(a) and unit(b) agree within 1e-12: a run along b would repeat a's (a flat
/// polygon's Newell normal, its corner normals' mean and its normal cone's centre are one
/// direction up to rounding), so the certificate tries it once.
bool sameDirection(const double a[3], const double b[3]) {
  const double la = std::sqrt(a[0] * a[0] + a[1] * a[1] + a[2] * a[2]),
               lb = std::sqrt(b[0] * b[0] + b[1] * b[1] + b[2] * b[2]);
  if (!(la > 0) || !(lb > 0) || !std::isfinite(la) || !std::isfinite(lb)) return false;
  double d2 = 0;
  for (int i = 0; i < 3; ++i) d2 += (a[i] / la - b[i] / lb) * (a[i] / la - b[i] / lb);
  return d2 <= 1e-24;
}

template <class Real>
PatchCertificate certify(int n, const Real* recs, int mode, const CertificateOptions& o) {
  PatchCertificate out;
  if (n < 3 || n > GP_MAX_N) return out;
  std::array<Taylor, GP_MAX_N * GP_E_NFIELDS> irecs;
  for (int i = 0; i < n * GP_E_NFIELDS; ++i) {
    const double x = static_cast<double>(recs[i]);
    if (!std::isfinite(x)) return out;
    irecs[i] = Taylor(x);
  }
  std::array<double, GP_MAX_N * GP_E_NFIELDS> drecs;
  for (int i = 0; i < n * GP_E_NFIELDS; ++i) drecs[i] = static_cast<double>(recs[i]);
  // a patch that meets an edge or a corner upside down folds against its neighbours there,
  // whatever it does inside; one not proven to meet its edges right side up is certified by no
  // direction
  double turned = 0;
  const int orientation = boundaryOrientation(n, irecs, drecs.data(), mode, &turned);
  if (orientation < 0) {
    out.verdict = CertificateVerdict::Folded;
    out.margin = turned;
    out.cells = 2 * n;
    return out;
  }
  // first along the polygon's Newell normal (in double)
  double newell[3] = {0, 0, 0};
  for (int k = 0; k < n; ++k) {
    const Real* a = recs + k * GP_E_NFIELDS + GP_E_V0;
    const Real* b = recs + k * GP_E_NFIELDS + GP_E_V1;
    newell[0] += (double(a[1]) - double(b[1])) * (double(a[2]) + double(b[2]));
    newell[1] += (double(a[2]) - double(b[2])) * (double(a[0]) + double(b[0]));
    newell[2] += (double(a[0]) - double(b[0])) * (double(a[1]) + double(b[1]));
  }
  out = certifyAlong(n, irecs, mode, o, newell);
  out.cells += 2 * n;  // the boundary boxes
  if (orientation == 0) {  // the Newell normal's run may still prove a fold; nothing certifies it
    if (out.verdict == CertificateVerdict::Certified) {
      out.verdict = CertificateVerdict::Undecided;
      out.margin = 0;
    }
    return out;
  }
  if (out.verdict == CertificateVerdict::Certified) return out;
  double mean[3] = {0, 0, 0};
  for (int k = 0; k < n; ++k) {
    const Real* c = recs + k * GP_E_NFIELDS + GP_E_N0;
    const double l = std::sqrt(double(c[0]) * double(c[0]) + double(c[1]) * double(c[1]) + double(c[2]) * double(c[2]));
    if (l > 0 && std::isfinite(l))
      for (int i = 0; i < 3; ++i) mean[i] += double(c[i]) / l;
  }
  if (o.cornerNormalDirection && !sameDirection(mean, newell)) {
    // then along the mean of its unit corner normals: a curved patch (a subdivision limit's,
    // say) can turn past 90 degrees from its polygon's plane and still be a regular height field
    PatchCertificate second = certifyAlong(n, irecs, mode, o, mean);
    second.cells += out.cells;
    if (second.verdict == CertificateVerdict::Certified) return second;
    out.cells = second.cells;
  }
  if (o.normalConeDirection) {
    // along the centre of the patch's sampled normal cone (the direction of the largest smallest
    // cosine to them), where that cone is narrower than a half-space: the direction with the
    // most room for a patch whose normals spread far from both above
    std::vector<Eigen::Vector3d> normals;
    const int g = std::clamp(o.coneSamples, 2, 256);
    for (int j = 0; j <= g; ++j)
      for (int i = 0; i <= g; ++i) {
        const double x = -1 + 2.0 * i / g, y = -1 + 2.0 * j / g;
        const gpd::gp_eval_result p = gpd::gp_patch_eval(n, drecs.data(), mode, x, y);
        const Eigen::Vector3d N(p.normal.x, p.normal.y, p.normal.z);
        if (!(p.status & GP_ST_OUTSIDE) && std::isfinite(N.squaredNorm()) && N.squaredNorm() > 0.5)
          normals.push_back(N);
      }
    if (!normals.empty()) {
      const Eigen::Vector3d m(mean[0], mean[1], mean[2]);
      const Eigen::Vector3d start = m.squaredNorm() > 0 ? Eigen::Vector3d(m.normalized()) : normals[0];
      const Eigen::Vector3d axis = minimaxDirection(normals, start);
      double worst = 1;
      for (const Eigen::Vector3d& N : normals) worst = std::min(worst, N.dot(axis));
      const double cone[3] = {axis.x(), axis.y(), axis.z()};
      const bool tried = sameDirection(cone, newell) || (o.cornerNormalDirection && sameDirection(cone, mean));
      if (worst > 0 && !tried) {  // else the samples already turn past a half-space: no direction proves it
        PatchCertificate third = certifyAlong(n, irecs, mode, o, cone);
        third.cells += out.cells;
        if (third.verdict == CertificateVerdict::Certified) return third;
        out.cells = third.cells;
      }
    }
  }
  // last, regular without a common direction: every box bounded along its own centre's normal,
  // and each edge met along its edge normal. Along a whole edge the patch normal is parallel to
  // n_c where the construction is G1 (corrected and blended cross tangents; the printed ones keep
  // a jump at backward end tangents), so with a normal that vanishes nowhere its side of n_c at
  // the edge's midpoint is its side along the whole edge.
  if (!o.regularity || (mode & GP_CT_MASK) == GP_CT_PAPER) return out;
  PatchCertificate fourth = certifyAlong(n, irecs, mode, o, newell, drecs.data());
  fourth.cells += out.cells;
  if (fourth.verdict == CertificateVerdict::Certified) {
    fourth.verdict = CertificateVerdict::Regular;
    return fourth;
  }
  out.cells = fourth.cells;
  return out;
}

/// A margin as a float no farther from 0 than the double (so a stored bound stays a bound).
float towardZero(double m) {
  float f = static_cast<float>(m);
  if (std::fabs(static_cast<double>(f)) > std::fabs(m)) f = std::nextafter(f, 0.0f);
  if (m != 0 && f == 0)
    f = m > 0 ? std::numeric_limits<float>::denorm_min() : -std::numeric_limits<float>::denorm_min();
  return f;
}

}  // namespace

namespace detail {
PatchEnclosure enclosePatch(int n, const double* recs, CrossTangentMode mode, const double nFace[3], double x0,
                            double x1, double y0, double y1) {
  PatchEnclosure out;
  if (n < 3 || n > GP_MAX_N) return out;
  std::array<Taylor, GP_MAX_N * GP_E_NFIELDS> irecs;
  for (int i = 0; i < n * GP_E_NFIELDS; ++i) irecs[i] = Taylor(recs[i]);
  gpd::gp_domain scratch;
  const gpi::gp_eval_result r =
      evalBox(gpd::gp_domain_of(n, &scratch, 1), irecs, static_cast<int>(mode), x0, x1, y0, y1);
  const gpi::gp_vec3* v[3] = {&r.pos, &r.dxi, &r.deta};
  interval::Interval* o[3] = {out.pos, out.dxi, out.deta};
  for (int i = 0; i < 3; ++i) o[i][0] = v[i]->x.range(), o[i][1] = v[i]->y.range(), o[i][2] = v[i]->z.range();
  out.J = boundJ(r, nFace).J;  // the bound the certificate decides on
  return out;
}
}  // namespace detail

namespace {
/// A patch marked GP_ST_AFFINE: the affine map plus its curved edges' deviations, proven regular
/// along its plane's normal by affineTriangleMargin (a bound on the map's Jacobian, not cells);
/// the cells' certificate where that proves nothing (records whose mark is not the construction's).
template <class Real>
PatchCertificate certifyWith(int n, const Real* recs, CrossTangentMode mode, const CertificateOptions& options,
                             uint32_t faceStatus) {
  if ((faceStatus & GP_ST_AFFINE) && n == 3) {
    if (const double margin = affineTriangleMargin(n, recs); margin > 0) {
      auto vertex = [&](int k) {
        const Real* r = recs + k * GP_E_NFIELDS + GP_E_V0;
        return Eigen::Vector3d(double(r[0]), double(r[1]), double(r[2]));
      };
      const Eigen::Vector3d normal = (vertex(1) - vertex(0)).cross(vertex(2) - vertex(0)).normalized();
      PatchCertificate c;
      c.verdict = CertificateVerdict::Certified;
      c.margin = margin;
      for (int i = 0; i < 3; ++i) c.direction[i] = normal[i];
      return c;
    }
  }
  return certify(n, recs, gpd::gp_eval_mode(static_cast<int>(mode), faceStatus), options);
}
}  // namespace

PatchCertificate certifyPatch(int n, const double* recs, CrossTangentMode mode, const CertificateOptions& options,
                              uint32_t faceStatus) {
  return certifyWith(n, recs, mode, options, faceStatus);
}
PatchCertificate certifyPatch(int n, const float* recs, CrossTangentMode mode, const CertificateOptions& options,
                              uint32_t faceStatus) {
  return certifyWith(n, recs, mode, options, faceStatus);
}

CertificateSummary certifyPatches(PatchCache& cache, int threads, const CertificateOptions& options) {
  const int nf = cache.numFaces();
  if (!hasPatchData(cache) && nf > 0) throw std::invalid_argument("certifyPatches: the cache has no patch data");
  cache.faceCertificate.assign(nf, 0.f);
  std::vector<char> regular(nf, 0);
  auto one = [&](int f) {
    const int n = cache.faceSize(f);
    if ((cache.faceStatus[f] & GP_ST_NOT_BUILT) || n < 3 || n > GP_MAX_N) return;
    PatchCertificate c;
    if (cache.options.precision == Precision::Double) {
      std::array<double, GP_MAX_N * GP_E_NFIELDS> recs;
      gatherRecords(cache, f, recs.data());
      c = certifyPatch(n, recs.data(), cache.options.crossTangent, options, cache.faceStatus[f]);
    } else {
      std::array<float, GP_MAX_N * GP_E_NFIELDS> recs;
      gatherRecords(cache, f, recs.data());
      c = certifyPatch(n, recs.data(), cache.options.crossTangent, options, cache.faceStatus[f]);
    }
    cache.faceCertificate[f] = towardZero(c.margin);
    regular[f] = c.verdict == CertificateVerdict::Regular;
  };
  auto run = [&] {
    tbb::parallel_for(tbb::blocked_range<int>(0, nf, 8), [&](const tbb::blocked_range<int>& r) {
      for (int f = r.begin(); f != r.end(); ++f) one(f);
    });
  };
  if (threads > 0) {
    tbb::task_arena arena(threads);
    arena.execute(run);
  } else {
    run();
  }
  CertificateSummary s = summarizeCertificates(cache);
  s.regular = 0;
  for (int f = 0; f < nf; ++f)
    if (regular[f]) {
      ++s.regular;
      s.regularFaces.push_back(f);
    }
  return s;
}

CertificateSummary summarizeCertificates(const PatchCache& c) {
  CertificateSummary s;
  const int nf = c.numFaces();
  s.present = static_cast<int>(c.faceCertificate.size()) == nf;
  if (!s.present) return s;
  double minMargin = 2;
  for (int f = 0; f < nf; ++f) {
    const float m = c.faceCertificate[f];
    if (c.faceStatus[f] & GP_ST_NOT_BUILT) {
      ++s.notBuilt;
    } else if (m > 0) {
      ++s.certified;
      minMargin = std::min(minMargin, static_cast<double>(m));
    } else {
      (m < 0 ? s.folded : s.undecided) += 1;
      s.uncertifiedFaces.push_back(f);
      if (m < 0) s.foldedFaces.push_back(f);
    }
  }
  s.minMargin = s.certified ? minMargin : 0;
  return s;
}

}  // namespace sf
