// SPDX-License-Identifier: Apache-2.0
#include <smoothforce/sweep/sweep.h>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>
#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>
#include <limits>

#include <smoothforce/base/hash.h>
#include <smoothforce/base/thread_limit.h>
#include <smoothforce/mesh/topology.h>
#include <smoothforce/patch/patch_build.h>
#include <smoothforce/sweep/morton_order.h>

namespace sf {

Eigen::Vector3d HipSet::hip(size_t g) const {
  const size_t n = samples.size(), gi = g / n, s = g % n;
  const HipGroup& G = groups[gi];
  if (!G.hips.empty()) return G.hips[s];
  return samples[s].point - G.depth * samples[s].normal;
}

Eigen::Vector3d HipSet::approach(size_t g) const {
  const size_t n = samples.size(), gi = g / n, s = g % n;
  const HipGroup& G = groups[gi];
  const SurfaceSample& p = samples[s];
  const double depth = G.hips.empty() ? G.depth : std::max((G.hips[s] - p.point).norm(), 1e-9 * diagonal);
  return p.point + approachFactor * depth * p.normal;
}

double HipSet::spacing() const { return samples.empty() ? 0 : std::sqrt(area / static_cast<double>(samples.size())); }

uint64_t HipSet::hash() const {
  std::vector<double> xyz;
  xyz.reserve(3 * size());
  for (size_t g = 0; g < size(); ++g) {
    const Eigen::Vector3d h = hip(g);
    xyz.insert(xyz.end(), {h.x(), h.y(), h.z()});
  }
  return hashBytes(xyz.data(), xyz.size() * sizeof(double));
}

HipSet makeDepthHips(std::vector<SurfaceSample> samples, const std::vector<DepthSpec>& depths, double diagonal,
                     double area) {
  HipSet s;
  s.samples = std::move(samples);
  s.diagonal = diagonal;
  s.area = area;
  for (const DepthSpec& d : depths) s.groups.push_back(HipGroup{d.label, d.metres(diagonal), {}});
  return s;
}

HipSet makeFileHips(const std::vector<Eigen::Vector3d>& hips, const PatchProjector& projector, double diagonal,
                    double area) {
  HipSet s;
  s.samples.resize(hips.size());
  tbb::parallel_for(size_t(0), hips.size(), [&](size_t i) { s.samples[i] = projector.project(hips[i]); });
  s.groups.push_back(HipGroup{"file", 0, hips});
  s.diagonal = diagonal;
  s.area = area;
  return s;
}

void fillHipResult(HipResult& r, const ForceSample& s, const ReferenceSurface* ref) {
  for (int a = 0; a < 3; ++a) {
    r.force[a] = static_cast<float>(s.force[a]);
    r.scp[a] = static_cast<float>(s.scp[a]);
  }
  r.contact = s.contact ? 1 : 0;
  r.face = s.face;
  r.status = s.status;
  r.iterations = static_cast<uint16_t>(std::clamp(s.iterations, 0, 65535));
  r.refDistance = std::numeric_limits<float>::quiet_NaN();
  if (ref && s.contact) r.refDistance = static_cast<float>(ref->distance(s.scp));
  r.done = 1;
}

std::vector<uint32_t> probeOrder(const HipSet& set, size_t begin, size_t end) {
  const size_t n = end > begin ? end - begin : 0;
  std::vector<uint32_t> order(n);
  constexpr size_t kSegment = size_t(1) << 20;  // sorted segment by segment: bounded scratch
  std::vector<Eigen::Vector3d> q;
  for (size_t s0 = 0; s0 < n; s0 += kSegment) {
    const size_t m = std::min(kSegment, n - s0);
    q.resize(m);
    tbb::parallel_for(size_t(0), m, [&](size_t i) { q[i] = set.hip(begin + s0 + i); });
    const std::vector<uint32_t> seg = mortonOrder(q);
    for (size_t i = 0; i < m; ++i) order[s0 + i] = static_cast<uint32_t>(s0 + seg[i]);
  }
  return order;
}

namespace {
template <class F>
void inArena(int threads, F&& f) {
  if (threads > 0) {
    tbb::task_arena arena(arenaThreads(threads));
    arena.execute(f);
  } else {
    f();
  }
}
}  // namespace

ForceRenderer& RendererPool::local() {
  std::shared_ptr<ForceRenderer>& r = tls_.local();
  if (!r) r = std::shared_ptr<ForceRenderer>(make_());
  return *r;
}

long RendererPool::patchesBuilt() const {
  long n = 0;
  for (const auto& r : tls_)
    if (r) n += r->patchesBuilt();
  return n;
}

size_t runProbes(const HipSet& set, size_t begin, size_t end, RendererPool& pool, const ReferenceSurface* ref,
                 HipResult* out, const SweepControl& control) {
  if (begin >= end) return 0;
  std::atomic<size_t> done{0};
  inArena(control.threads, [&] {
    const std::vector<uint32_t> order = probeOrder(set, begin, end);
    tbb::parallel_for(tbb::blocked_range<size_t>(0, end - begin, 64), [&](const tbb::blocked_range<size_t>& r) {
      if (control.stop && control.stop->load(std::memory_order_relaxed)) return;
      ForceRenderer& R = pool.local();
      for (size_t i = r.begin(); i < r.end(); ++i) {
        const size_t g = begin + order[i];
        const SurfaceSample& from = set.sample(g);
        R.resetNear(from.face, from.xi, from.eta);  // the HIP's surface sample seeds the approach step
        R.step(set.approach(g));
        fillHipResult(out[g - begin], R.step(set.hip(g)), ref);
      }
      done.fetch_add(r.size(), std::memory_order_relaxed);
      if (control.progress) control.progress(r.size());
    });
  });
  return done.load();
}

size_t runProbes(const HipSet& set, size_t begin, size_t end, const RendererFactory& make, const ReferenceSurface* ref,
                 HipResult* out, const SweepControl& control, long* patchesBuilt) {
  RendererPool pool(make);
  const size_t done = runProbes(set, begin, end, pool, ref, out, control);
  if (patchesBuilt) *patchesBuilt += pool.patchesBuilt();
  return done;
}

std::vector<SurfaceSample> trajectorySamples(const std::vector<Eigen::Vector3d>& polyline, double step,
                                             const PatchProjector& projector) {
  const std::vector<Eigen::Vector3d> pts = resamplePolyline(polyline, step);
  std::vector<SurfaceSample> out(pts.size());
  tbb::parallel_for(size_t(0), pts.size(), [&](size_t i) { out[i] = projector.project(pts[i]); });
  return out;
}

void runTrajectory(const std::vector<SurfaceSample>& path, double depth, double approach, ForceRenderer& renderer,
                   TrajectorySeries& out) {
  out.force.assign(3 * path.size(), 0.f);
  out.contact.assign(path.size(), 0);
  if (path.empty()) return;
  renderer.resetNear(path[0].face, path[0].xi, path[0].eta);  // the approach step from the first point's patch point
  renderer.step(path[0].point + approach * depth * path[0].normal);
  for (size_t i = 0; i < path.size(); ++i) {
    const ForceSample s = renderer.step(path[i].point - depth * path[i].normal);
    for (int a = 0; a < 3; ++a) out.force[3 * i + a] = static_cast<float>(s.force[a]);
    out.contact[i] = s.contact ? 1 : 0;
  }
}

std::vector<uint8_t> creaseCrossings(const std::vector<SurfaceSample>& path, const PatchCache& cache) {
  std::vector<uint8_t> crease(path.size(), 0);
  std::vector<char> creaseVertex(cache.numVertices(), 0);
  bool any = false;
  for (int f = 0; f < cache.numFaces(); ++f)
    for (int k = 0, n = cache.faceSize(f); k < n; ++k)
      if (isCreaseEdge(cache, f, k)) {
        any = true;
        creaseVertex[cache.faceVertices[cache.faceOffsets[f] + k]] = 1;
        creaseVertex[cache.faceVertices[cache.faceOffsets[f] + (k + 1) % n]] = 1;
      }
  if (!any) return crease;
  for (size_t i = 1; i < path.size(); ++i) {
    const int a = path[i - 1].face, b = path[i].face;
    if (a < 0 || b < 0 || a == b || a >= cache.numFaces() || b >= cache.numFaces()) continue;
    bool shareEdge = false, creaseEdge = false, sharedCreaseVertex = false;
    for (int k = 0, n = cache.faceSize(a); k < n; ++k) {
      const int t = cache.slotTwin[cache.faceOffsets[a] + k];
      if (t >= 0 && slotFace(cache.faceOffsets, t) == b) {
        shareEdge = true;
        creaseEdge = creaseEdge || isCreaseEdge(cache, a, k);
      }
      const int v = cache.faceVertices[cache.faceOffsets[a] + k];
      for (int j = cache.faceOffsets[b]; j < cache.faceOffsets[b + 1]; ++j)
        sharedCreaseVertex = sharedCreaseVertex || (cache.faceVertices[j] == v && creaseVertex[v]);
    }
    crease[i] = shareEdge ? creaseEdge : sharedCreaseVertex;
  }
  return crease;
}

std::array<double, 2> maxDifferenceByCreases(const TrajectorySeries& series, size_t window) {
  const size_t n = series.force.size() / 3;
  std::array<double, 2> mx{NAN, NAN};
  std::vector<char> near(n, 0);
  for (size_t i = 0; i < series.crease.size() && i < n; ++i)
    if (series.crease[i])
      for (size_t j = i > window ? i - window : 0; j <= i + window && j < n; ++j) near[j] = 1;
  for (size_t j = 0; j + 1 < n; ++j) {
    const float* a = &series.force[3 * j];
    const double d = std::sqrt(double(a[3] - a[0]) * (a[3] - a[0]) + double(a[4] - a[1]) * (a[4] - a[1]) +
                               double(a[5] - a[2]) * (a[5] - a[2]));
    double& m = mx[near[j] || near[j + 1] ? 1 : 0];
    if (!(m >= d)) m = d;
  }
  return mx;
}

void markPastMedialAxis(const std::vector<SurfaceSample>& path, double depth, const PatchProjector& projector,
                        TrajectorySeries& out) {
  out.pastMedialAxis.assign(path.size(), 0);
  for (size_t i = 0; i < path.size(); ++i) {
    const Eigen::Vector3d hip = path[i].point - depth * path[i].normal;
    const SurfaceSample q = projector.project(hip);
    out.pastMedialAxis[i] = q.face >= 0 && (hip - q.point).norm() < 0.999 * depth ? 1 : 0;
  }
}

}  // namespace sf
