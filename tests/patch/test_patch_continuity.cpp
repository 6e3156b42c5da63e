// SPDX-License-Identifier: Apache-2.0
// The patch surface is continuous inside every face (C0), and so are its first derivatives (C1: no
// crease), on every bundled mesh. Two causes of tears are fixed and checked here:
// - a cross-tangent direction that turns over along an edge (design page, Robustness 4): pmp/L.off
//   (a reflex corner), tetris.obj and L-plane.obj (straight and reflex corners) and the scanned
//   bunny at resolutions 3 and 4 tore, by up to 0.5 m, 0.17 m and 0.0068 m;
// - an orientation rule on the edge normal n_c (n_c . ((1-t) N_k + t N_{k+1}) >= 0 at every t)
//   that turned n_c over inside an edge where the raw n_c, not small, is perpendicular to the
//   interpolated vertex normal: 8 faces of the scanned bunny at resolutions 2 and 4 (1925 1973
//   1997 2031; 695 775 925 926). n_c is now the normalised Eq. 10 direction, continuous, and the
//   vertex normal at both ends (test_patch_identities.cpp).
//
// And one cause of creases: the turn of Robustness 4 pushed by (eps - |a|) b was continuous but its
// derivative jumped where the push starts (|a| = eps): on pmp/L.off's folded hexagon dG/dxi jumped
// from 0.6 to 31 m per domain unit across that curve and the normal turned over, a crease the
// Newton refinement crawled along to its iteration cap (36 of 600 lazy global queries ended
// farther than the prebuilt one, up to 3% of the diagonal). The push is now (eps - |a|)^2 / eps.
//
// Independent check: chords of each domain parallel to each of its edges, sampled; a step whose
// position change exceeds 4 times what the derivatives at its two ends predict is bisected, the
// half with the larger change kept, down to 1e-9 domain units. A tear keeps its jump there; a steep
// but continuous stretch (a cross tangent turning fast) does not. Likewise for creases with the
// derivative along the chord (three insets: L.off's crease lies nearer the centre than the two
// above): a step whose derivative changes by more than a tenth of the chord's largest derivative
// is bisected (the half with the larger change kept); a crease keeps its jump at 1e-9 domain
// units (more than 1% of that scale), a smooth but fast-turning stretch does not. With the first
// push, 85 faces creased: L.off 1, L-plane.obj 16, tetris.obj 13, bun_zipper_res2/3/4 46, 4, 5.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <initializer_list>
#include <string>
#include <vector>

#include <smoothforce/patch/patch_eval.h>
#include "patch_test_support.h"

namespace sf {
namespace {

struct Sample {
  int face;
  Eigen::Vector2d X;
};

/// Whether the position change over the step a -> b is no more than 4x the derivatives' estimate.
bool stepFits(const PatchPoint& a, const PatchPoint& b, const Eigen::Vector2d& d, double floor) {
  const double predicted = std::max((a.dxi * d.x() + a.deta * d.y()).norm(), (b.dxi * d.x() + b.deta * d.y()).norm());
  return (b.pos - a.pos).norm() <= 4 * predicted + floor;
}

/// The change of value(p) (a 3-vector of the patch point p) left after bisecting the step x0 -> x1
/// of face f to 1e-9 domain units, the half with the larger change kept: a jump of the position
/// (a tear) or of a derivative (a crease) keeps its size, a continuous change shrinks.
template <class Value>
double changeAfterBisection(const PatchCache& c, int f, Eigen::Vector2d x0, Eigen::Vector2d x1, Value value) {
  PatchPoint a = evaluatePatch(c, f, x0.x(), x0.y()), b = evaluatePatch(c, f, x1.x(), x1.y());
  while ((x1 - x0).norm() > 1e-9) {
    const Eigen::Vector2d m = 0.5 * (x0 + x1);
    const PatchPoint pm = evaluatePatch(c, f, m.x(), m.y());
    if ((value(pm) - value(a)).norm() >= (value(b) - value(pm)).norm()) {
      x1 = m;
      b = pm;
    } else {
      x0 = m;
      a = pm;
    }
  }
  return (value(b) - value(a)).norm();
}

/// The faces of a list as " f0 f1 ...", empty for none (what a test expects to be empty).
std::string faceList(const std::vector<int>& faces) {
  std::string list;
  for (int f : faces) (list += ' ') += std::to_string(f);  // no string temporary: GCC 12 -Wrestrict
  return list;
}

/// Chords of the built faces' domains (parallel to each of its edges, at the given insets: the
/// fractions of the way to the centre), sampled and evaluated: s[chordStart[c], chordStart[c + 1])
/// is chord c, in face order.
struct Chords {
  std::vector<Sample> s;
  std::vector<size_t> chordStart;
  std::vector<PatchPoint> p;
  std::vector<int32_t> face;
  std::vector<double> xi, eta;
  int faces = 0;
};

/// The chords of faces [f0, f1) into h, whose buffers are reused: a dense mesh's chords, a
/// batch of faces at a time, never hold more than a batch's samples (the whole of bunny_hr's
/// would be gigabytes).
void sampleChords(const PatchCache& c, std::initializer_list<double> insets, int f0, int f1, Chords& h) {
  constexpr int kSamples = 64;  // per chord, over 3 edge lengths (clipped to the domain)
  h.s.clear();
  h.chordStart.clear();
  h.faces = 0;
  for (int f = f0; f < f1; ++f) {
    if (c.faceStatus[f] & GP_ST_NOT_BUILT) continue;
    ++h.faces;
    const int n = c.faceSize(f);
    for (int k = 0; k < n; ++k) {
      const Eigen::Vector2d a = domainCorner(n, k), b = domainCorner(n, (k + 1) % n);
      for (double inset : insets) {
        h.chordStart.push_back(h.s.size());
        for (int i = 0; i <= kSamples; ++i) {
          const double lambda = -1.0 + 3.0 * i / kSamples;
          const Eigen::Vector2d X = (1 - inset) * (a + lambda * (b - a));
          if (insideDomain(n, X.x(), X.y(), -1e-9)) h.s.push_back({f, X});
        }
      }
    }
  }
  h.chordStart.push_back(h.s.size());
  h.face.resize(h.s.size());
  h.xi.resize(h.s.size());
  h.eta.resize(h.s.size());
  for (size_t i = 0; i < h.s.size(); ++i) {
    h.face[i] = h.s[i].face;
    h.xi[i] = h.s[i].X.x();
    h.eta[i] = h.s[i].X.y();
  }
  h.p.resize(h.s.size());
  evaluatePatches(c, h.face.data(), h.xi.data(), h.eta.data(), h.s.size(), h.p.data(), Backend::Tbb);
}

constexpr int kChordFaces = 2048;  ///< faces per batch of chords

TEST(PatchContinuity, NoTearInsideAnyFaceOfAnyBundledMesh) {
  int meshes = 0, faces = 0;
  size_t tornFaces = 0;
  size_t steps = 0, bisected = 0;
  for (const std::string& path : test::sharedMeshFiles()) {
    SCOPED_TRACE(path);
    const PatchCache c = test::cacheFromFile(path);
    const double diag = boundingDiagonal(c);
    std::vector<int> torn;  // faces with a tear, ascending (the steps come face by face, in face order)
    Chords h;
    for (int f0 = 0; f0 < c.numFaces(); f0 += kChordFaces) {
      sampleChords(c, {0.15, 0.5}, f0, std::min(c.numFaces(), f0 + kChordFaces), h);
      faces += h.faces;
      for (size_t ch = 0; ch + 1 < h.chordStart.size(); ++ch)
        for (size_t i = h.chordStart[ch]; i + 1 < h.chordStart[ch + 1]; ++i) {
          ++steps;
          if (stepFits(h.p[i], h.p[i + 1], h.s[i + 1].X - h.s[i].X, 1e-12 * diag)) continue;
          ++bisected;
          const double jump =
              changeAfterBisection(c, h.s[i].face, h.s[i].X, h.s[i + 1].X, [](const PatchPoint& p) { return p.pos; });
          if (jump > 1e-4 * diag && (torn.empty() || torn.back() != h.s[i].face)) torn.push_back(h.s[i].face);
        }
    }
    EXPECT_EQ(faceList(torn), "") << "faces that tear";
    tornFaces += torn.size();
    ++meshes;
  }
  std::printf("%d meshes, %d faces, %zu chord steps, %zu bisected, %zu faces tear\n", meshes, faces, steps, bisected,
              tornFaces);
  EXPECT_EQ(meshes, 28);
  EXPECT_GT(steps, size_t(100) * faces);
}

/// G's derivative along the unit domain direction u at p (m per domain unit).
Eigen::Vector3d along(const PatchPoint& p, const Eigen::Vector2d& u) { return p.dxi * u.x() + p.deta * u.y(); }

TEST(PatchContinuity, NoCreaseInsideAnyFaceOfAnyBundledMesh) {
  int meshes = 0;
  size_t steps = 0, bisected = 0, creasedFaces = 0;
  for (const std::string& path : test::sharedMeshFiles()) {
    SCOPED_TRACE(path);
    const PatchCache c = test::cacheFromFile(path);
    const double floor = 1e-9 * boundingDiagonal(c);  // m per domain unit: below it a derivative is noise
    // a third chord near the centre: L.off's crease is crossed by none of the other two
    std::vector<int> creased;  // faces with a crease, ascending
    Chords h;
    for (int f0 = 0; f0 < c.numFaces(); f0 += kChordFaces) {
      sampleChords(c, {0.15, 0.5, 0.85}, f0, std::min(c.numFaces(), f0 + kChordFaces), h);
      for (size_t ch = 0; ch + 1 < h.chordStart.size(); ++ch) {
        if (h.chordStart[ch + 1] - h.chordStart[ch] < 2) continue;
        // the chord's derivative scale: the largest derivative along it (a smooth fold passes
        // through zero, so the step's own derivatives are no scale)
        const Eigen::Vector2d u = (h.s[h.chordStart[ch] + 1].X - h.s[h.chordStart[ch]].X).normalized();
        const auto alongU = [&u](const PatchPoint& p) { return along(p, u); };
        double scale = floor;
        for (size_t i = h.chordStart[ch]; i < h.chordStart[ch + 1]; ++i)
          scale = std::max(scale, along(h.p[i], u).norm());
        for (size_t i = h.chordStart[ch]; i + 1 < h.chordStart[ch + 1]; ++i) {
          ++steps;
          if ((along(h.p[i + 1], u) - along(h.p[i], u)).norm() <= 0.1 * scale) continue;
          ++bisected;
          if (changeAfterBisection(c, h.s[i].face, h.s[i].X, h.s[i + 1].X, alongU) > 1e-2 * scale &&
              (creased.empty() || creased.back() != h.s[i].face))
            creased.push_back(h.s[i].face);
        }
      }
    }
    EXPECT_EQ(faceList(creased), "") << "faces with a crease";
    creasedFaces += creased.size();
    ++meshes;
  }
  std::printf("%d meshes, %zu chord steps, %zu bisected, %zu faces with a crease\n", meshes, steps, bisected,
              creasedFaces);
  EXPECT_EQ(meshes, 28);
  EXPECT_GT(bisected, size_t(0));  // the fast-turning stretches are looked at
}

}  // namespace
}  // namespace sf
