// SPDX-License-Identifier: Apache-2.0
// Tracking at creases: the other sheets a tracked contact must ask (a ridge's nearer side), and
// the contact test of an SCP held on a valley's crease curve (force_tracking_detail.h).
#include <algorithm>
#include <cstdint>

#include <smoothforce/mesh/topology.h>
#include <smoothforce/patch/patch_build.h>
#include <smoothforce/patch/patch_eval.h>
#include <smoothforce/query/embree_scene.h>
#include <smoothforce/query/global_query.h>
#include <smoothforce/query/patch_refine.h>

#include "force_tracking_detail.h"

namespace sf::detail {

namespace {

/// How near the crease (in tracked distances) a HIP must be for the other side's sheet to be
/// asked (nearerAcrossCreases): where a sheet that turns away by theta (a ridge) becomes the
/// nearer one, the HIP is 1 / cos(theta / 2) tracked distances from the crease, 4 up to about
/// 150 degrees.
inline constexpr double kCreaseReach = 4.0;

/// The point of the crease curve under edge k of face f nearest X in f's domain (by edge
/// parameter), seen from the other face: that face in *g, its domain point in *Y, and its patch
/// point there (the same position, the other side's normal). False where there is no usable one.
bool acrossCrease(const PatchCache& c, PatchRefiner& refiner, int f, int k, const Eigen::Vector2d& X, int* g,
                  Eigen::Vector2d* Y, PatchPoint* p) noexcept {
  const int n = c.faceSize(f);
  const Eigen::Vector2d a = domainCorner(n, k), e = domainCorner(n, (k + 1) % n) - a;
  const double t = std::clamp((X - a).dot(e) / e.squaredNorm(), 0.0, 1.0);
  const int twin = c.slotTwin[c.faceOffsets[f] + k];
  if (twin < 0) return false;
  *g = slotFace(c.faceOffsets, twin);
  const int m = c.faceSize(*g), i = twin - c.faceOffsets[*g];
  if (!refiner.evaluable(*g)) return false;
  const Eigen::Vector2d b = domainCorner(m, i);
  *Y = b + (1 - t) * (domainCorner(m, (i + 1) % m) - b);
  *p = refiner.eval(*g, *Y);
  return p->pos.allFinite() && p->normal.allFinite();
}

/// The most faces around a vertex that nearerAcrossCreases visits.
inline constexpr int kMaxRing = 64;

/// The faces around corner k of face f and each one's corner there, f's first: around the
/// vertex one way through the edges that enter it, and where a boundary stops that, the other
/// way. Returns how many (at most kMaxRing).
int facesAroundCorner(const PatchCache& c, int f, int k, int32_t* faces, int32_t* corners) noexcept {
  int count = 0;
  faces[count] = f;
  corners[count++] = k;
  for (int dir = 0; dir < 2; ++dir) {
    int g = f, i = k;
    while (count < kMaxRing) {
      const int n = c.faceSize(g);
      const int e = dir == 0 ? (i + n - 1) % n : i;  // the edge entering (leaving) the vertex
      const int twin = c.slotTwin[c.faceOffsets[g] + e];
      if (twin < 0) break;
      g = slotFace(c.faceOffsets, twin);
      const int t = twin - c.faceOffsets[g];
      i = dir == 0 ? t : (t + 1) % c.faceSize(g);  // the vertex is the twin edge's start (end)
      if (g == f && i == k) return count;  // around: a closed ring
      faces[count] = g;
      corners[count++] = i;
    }
  }
  return count;
}

}  // namespace

/// At a crease the two faces are separate sheets meeting at an angle, and the local refinement
/// keeps the sheet it tracks for as long as its own nearest point exists: at a ridge it stayed
/// on one face while the HIP slid under the other, far past where that sheet was nearer (the
/// force grew with the slide). So, on a face that touches a crease, the other sheets near the
/// SCP are asked too: across each crease edge of the face (from the crease curve's point nearest
/// r), and at each corner where a crease meets (from the corner of each face around it whose
/// normal there differs from r's face's), each where the HIP lies within kCreaseReach x
/// r.distance of that point and below that sheet's tangent plane there. The refinement runs on
/// such a sheet from that point, and a nearer converged point below which the HIP lies wins, so
/// that the nearer of the sheets holds the contact (at a valley they all end on the crease curve
/// itself: no change). Nothing on faces that touch no crease; otherwise a normal comparison per
/// face around a crease vertex, a patch evaluation per nearby crease edge, and a refinement only
/// where the HIP is below another sheet.
RefineResult nearerAcrossCreases(const PolygonScene& scene, PatchRefiner& refiner, const Eigen::Vector3d& hip,
                                 const RefineResult& r, const ForceOptions& options) noexcept {
  const PatchCache& c = scene.cache();
  if (!scene.hasCreases() || !usableRefinement(r) || r.face < 0 || r.face >= c.numFaces()) return r;
  const int n = c.faceSize(r.face), first = c.faceOffsets[r.face];
  bool touches = false;
  for (int k = 0; k < n && !touches; ++k) touches = scene.creaseVertex(c.faceVertices[first + k]);
  if (!touches) return r;
  RefineResult best = r;
  auto tryFrom = [&](int g, const Eigen::Vector2d& Y) {
    const RefineResult o = refiner.refine(hip, g, Y.x(), Y.y(), options);
    if (usableRefinement(o) && (o.status & SF_TRACK_CONVERGED) && o.distance < best.distance * (1 - 1e-9) &&
        (hip - o.scp).dot(o.normal) < 0)
      best = o;
  };
  const double reach = kCreaseReach * r.distance;
  for (int k = 0; k < n; ++k) {  // across the crease edges
    int g;
    Eigen::Vector2d Y;
    PatchPoint p;
    if (!isCreaseEdge(c, r.face, k) || !acrossCrease(c, refiner, r.face, k, {r.xi, r.eta}, &g, &Y, &p)) continue;
    if ((hip - p.pos).norm() > reach || (hip - p.pos).dot(p.normal) >= 0) continue;
    tryFrom(g, Y);
  }
  int32_t faces[kMaxRing], corners[kMaxRing];
  for (int k = 0; k < n; ++k) {  // around the corners where creases meet
    const int32_t v = c.faceVertices[first + k];
    if (!scene.creaseVertex(v)) continue;
    const Eigen::Vector3d P(&c.positions[3 * static_cast<size_t>(v)]);
    if ((hip - P).norm() > reach) continue;
    const int around = facesAroundCorner(c, r.face, k, faces, corners);
    for (int j = 1; j < around; ++j) {
      const int g = faces[j], slot = c.faceOffsets[g] + corners[j];
      if (!cornerNormalsDiffer(c, first + k, slot) || !refiner.evaluable(g)) continue;
      bool seen = false;  // one start per sector normal
      for (int q = 1; q < j && !seen; ++q)
        seen = !cornerNormalsDiffer(c, c.faceOffsets[faces[q]] + corners[q], slot);
      const Eigen::Vector3d N(&c.cornerNormals[3 * static_cast<size_t>(slot)]);
      if (seen || (hip - P).dot(N) >= 0) continue;
      tryFrom(g, 0.999 * domainCorner(c.faceSize(g), corners[j]));
    }
  }
  return best;
}

/// Whether a HIP is below a tracked SCP held on crease edge r.edge by the other side's tangent
/// plane there: at a valley the SCP rests on the crease curve while the HIP turns under it, and
/// the HIP is then below at least one of the two sides (not always the one r is on).
bool belowOtherSide(const PatchCache& c, PatchRefiner& refiner, const Eigen::Vector3d& hip,
                    const RefineResult& r) noexcept {
  if (r.edge < 0 || r.face < 0 || r.face >= c.numFaces() || r.edge >= c.faceSize(r.face) ||
      !isCreaseEdge(c, r.face, r.edge))
    return false;
  int g;
  Eigen::Vector2d Y;
  PatchPoint p;
  return acrossCrease(c, refiner, r.face, r.edge, {r.xi, r.eta}, &g, &Y, &p) && (hip - r.scp).dot(p.normal) < 0;
}

int creaseSidesVerdict(const PatchCache& c, PatchRefiner& refiner, const Eigen::Vector3d& hip,
                       const RefineResult& r) noexcept {
  if (!usableRefinement(r) || r.edge < 0 || r.face < 0 || r.face >= c.numFaces() || r.edge >= c.faceSize(r.face) ||
      !isCreaseEdge(c, r.face, r.edge))
    return -1;
  int g;
  Eigen::Vector2d Y;
  PatchPoint p;
  if (!acrossCrease(c, refiner, r.face, r.edge, {r.xi, r.eta}, &g, &Y, &p)) return -1;
  const bool own = (hip - r.scp).dot(r.normal) < 0, other = (hip - r.scp).dot(p.normal) < 0;
  if (own == other) return own ? 1 : 0;
  // the sides disagree: at a valley (the other sheet rises above this side's tangent plane just
  // past the crease) the solid is the union of the two sides' half spaces there, at a ridge their
  // intersection
  const PatchPoint past = refiner.eval(g, 0.9 * Y);
  if (!past.pos.allFinite()) return -1;
  const bool valley = (past.pos - r.scp).dot(r.normal) > 0;
  return valley ? 1 : 0;
}

}  // namespace sf::detail
