// SPDX-License-Identifier: Apache-2.0
#include <smoothforce/runtime/scripted.h>

#include <algorithm>
#include <cmath>
#include <cstdio>

#include <smoothforce/base/csv_reader.h>
#include <smoothforce/mesh/mesh.h>
#include <smoothforce/runtime/udp_device.h>

namespace sf::rt {
namespace {

std::string fmt(const char* f, double a, double b = 0, double c = 0, double d = 0) {
  char buf[200];
  std::snprintf(buf, sizeof buf, f, a, b, c, d);
  return buf;
}

}  // namespace

Eigen::AlignedBox3d sceneBounds(const Scene& scene) {
  Eigen::AlignedBox3d box;
  for (size_t i = 0; i < scene.objects().size(); ++i)  // the vertices faces reference (not stray ones)
    for (const int32_t v : scene.objects()[i].cache->faceVertices) box.extend(scene.worldVertex(i, v));
  return box;
}

SurfaceProbe::SurfaceProbe(const Scene& scene) {
  for (size_t i = 0; i < scene.objects().size(); ++i) {
    const PatchCache& c = *scene.objects()[i].cache;
    for (int f = 0; f < c.numFaces(); ++f) {
      const int32_t* fv = c.faceVertices.data() + c.faceOffsets[f];
      const Eigen::Vector3d a = scene.worldVertex(i, fv[0]);
      for (int k = 1; k + 1 < c.faceSize(f); ++k) {
        Tri t{a, scene.worldVertex(i, fv[k]), scene.worldVertex(i, fv[k + 1]), 0, 0, 0, 0};
        t.xmin = std::min({t.a.x(), t.b.x(), t.c.x()});
        t.xmax = std::max({t.a.x(), t.b.x(), t.c.x()});
        t.ymin = std::min({t.a.y(), t.b.y(), t.c.y()});
        t.ymax = std::max({t.a.y(), t.b.y(), t.c.y()});
        tri_.push_back(t);
      }
    }
  }
}

std::optional<double> SurfaceProbe::topHeight(double x, double y) const {
  std::optional<double> best;
  for (const Tri& t : tri_) {
    if (x < t.xmin || x > t.xmax || y < t.ymin || y > t.ymax) continue;
    // Barycentric coordinates of (x, y) in the triangle's xy projection.
    const double det = (t.b.x() - t.a.x()) * (t.c.y() - t.a.y()) - (t.c.x() - t.a.x()) * (t.b.y() - t.a.y());
    const double scale = (t.xmax - t.xmin) * (t.ymax - t.ymin);
    if (!(std::abs(det) > 1e-14 * scale)) continue;  // seen edge-on from above
    const double u = ((x - t.a.x()) * (t.c.y() - t.a.y()) - (t.c.x() - t.a.x()) * (y - t.a.y())) / det;
    const double v = ((t.b.x() - t.a.x()) * (y - t.a.y()) - (x - t.a.x()) * (t.b.y() - t.a.y())) / det;
    const double eps = 1e-12;
    if (u < -eps || v < -eps || u + v > 1 + eps) continue;
    const double z = t.a.z() + u * (t.b.z() - t.a.z()) + v * (t.c.z() - t.a.z());
    if (!best || z > *best) best = z;
  }
  return best;
}

double effectiveDepth(const Scene& scene, double depth) {
  const double diagonal = sceneBounds(scene).diagonal().norm();
  if (!(depth > 0)) return 0.01 * diagonal;
  if (depth > diagonal) {  // a path beyond the scene's size (1e308 made it infinite, then a safety fault)
    char msg[160];
    std::snprintf(msg, sizeof msg, "--depth: %g m is deeper than the scene's bounding-box diagonal (%g m)", depth,
                  diagonal);
    throw OptionError(msg);
  }
  return depth;
}

ScriptedPath slidePath(const Scene& scene, double depth) {
  const Eigen::AlignedBox3d box = sceneBounds(scene);
  const SurfaceProbe probe(scene);
  const double y = box.center().y(), x0 = box.min().x(), x1 = box.max().x();
  constexpr int kSamples = 257;
  std::vector<double> xs(kSamples);
  std::vector<std::optional<double>> hs(kSamples);
  for (int i = 0; i < kSamples; ++i) {
    xs[i] = x0 + (x1 - x0) * i / (kSamples - 1);
    hs[i] = probe.topHeight(xs[i], y);
  }
  // The hit nearest the centre, then the contiguous run of hits around it.
  int seed = -1;
  for (int d = 0; d <= kSamples / 2 && seed < 0; ++d)
    for (int i : {kSamples / 2 - d, kSamples / 2 + d})
      if (seed < 0 && i >= 0 && i < kSamples && hs[i]) seed = i;
  if (seed < 0)
    throw InputError(fmt("scripted:slide: no surface along the line y = %.6g m across the bounding box", y));
  int lo = seed, hi = seed;
  while (lo > 0 && hs[lo - 1]) --lo;
  while (hi + 1 < kSamples && hs[hi + 1]) ++hi;
  const double margin = 0.1 * (xs[hi] - xs[lo]);
  std::vector<int> keep;
  for (int i = lo; i <= hi; ++i)
    if (xs[i] >= xs[lo] + margin - 1e-12 && xs[i] <= xs[hi] - margin + 1e-12) keep.push_back(i);
  if (keep.size() < 2)
    throw InputError(fmt("scripted:slide: the surface along y = %.6g m is too narrow to slide on", y));
  ScriptedPath p;
  const int a = keep.front(), b = keep.back();
  p.points.emplace_back(xs[a], y, *hs[a] + depth);
  for (int i : keep) p.points.emplace_back(xs[i], y, *hs[i] - depth);
  p.points.emplace_back(xs[b], y, *hs[b] + depth);
  p.description = "scripted:slide along x from " +
                  fmt("%.4g to %.4g m at y = %.4g m, %.4g m below the top surface", xs[a], xs[b], y, depth);
  return p;
}

ScriptedPath circlePath(const Scene& scene, double depth) {
  const Eigen::AlignedBox3d box = sceneBounds(scene);
  const SurfaceProbe probe(scene);
  const Eigen::Vector3d c = box.center();
  const Eigen::Vector3d ext = box.sizes();
  const double r = 0.25 * std::min(ext.x(), ext.y());
  if (!(r > 0)) throw InputError("scripted:circle: the scene has no horizontal extent");
  constexpr int kSamples = 256;
  ScriptedPath p;
  for (int i = 0; i < kSamples; ++i) {
    const double a = 2 * M_PI * i / kSamples;
    const double x = c.x() + r * std::cos(a), y = c.y() + r * std::sin(a);
    const auto h = probe.topHeight(x, y);
    if (!h)
      throw InputError(
          fmt("scripted:circle: no surface below the circle of radius %.4g m around (%.4g, %.4g) at "
              "angle %.4g rad; try scripted:slide",
              r, c.x(), c.y(), a));
    if (i == 0) p.points.emplace_back(x, y, *h + depth);
    p.points.emplace_back(x, y, *h - depth);
  }
  p.points.push_back(p.points[1]);
  p.loopStart = 1;
  p.closed = true;
  p.description = "scripted:circle " +
                  fmt("of radius %.4g m around (%.4g, %.4g), %.4g m below the top surface", r, c.x(), c.y(), depth);
  return p;
}

void checkScriptedSpeed(double speed) {
  if (!(speed > 0 && speed <= kMaxScriptedSpeed)) {
    char buf[128];
    std::snprintf(buf, sizeof buf, "--speed: expected a speed in (0, %g] m/s, got %g", kMaxScriptedSpeed, speed);
    throw InputError(buf);
  }
}

void checkDeviceSpec(const std::string& spec) {
  if (spec == "null" || spec == "scripted" || spec == "scripted:slide" || spec == "scripted:circle") return;
  if (spec.rfind("replay:", 0) == 0) {
    if (spec.size() == 7) throw InputError("--device replay:FILE: missing FILE");
    return;
  }
  if (spec.rfind("udp:", 0) == 0) {
    parseUdpSpec(spec);
    return;
  }
  throw InputError(
      "--device: expected null, scripted, scripted:slide, scripted:circle, replay:FILE or udp:[HOST:]PORT, got '" +
      spec + "'");
}

namespace {

/// A world-frame path in the device frame (the loop maps it back with the device transform).
ScriptedPath toDevice(ScriptedPath p, const DeviceTransform& t) {
  for (Eigen::Vector3d& q : p.points) q = t.toDevice(q);
  return p;
}

}  // namespace

std::unique_ptr<HapticDevice> makeDevice(const std::string& spec, const Scene& scene, const ScriptOptions& o) {
  checkDeviceSpec(spec);
  const DeviceTransform& t = scene.deviceTransform();
  if (spec == "null") {
    const Eigen::AlignedBox3d box = sceneBounds(scene);
    const Eigen::Vector3d c = box.center();
    return std::make_unique<NullDevice>(
        t.toDevice(Eigen::Vector3d(c.x(), c.y(), box.max().z() + 0.1 * box.diagonal().norm())));
  }
  if (spec.rfind("replay:", 0) == 0) {
    const std::string file = spec.substr(7);
    Trajectory tr = readTrajectoryCsv(file);
    if (o.duration > 0 && !(tr.t.front() < o.duration)) {
      char buf[256];
      std::snprintf(buf, sizeof buf,
                    ": the first sample is at t = %.10g s, not before the run's end (%g s): the run would hold its "
                    "position throughout (times are seconds from the loop's start; subtract the first time)",
                    tr.t.front(), o.duration);
      throw InputError(csvDisplayName(file) + buf);
    }
    return std::make_unique<ReplayDevice>(std::move(tr), csvDisplayName(file));
  }
  if (spec.rfind("udp:", 0) == 0) {
    UdpOptions u;
    u.watchdog = o.watchdog;
    return std::make_unique<UdpDevice>(parseUdpSpec(spec), u);
  }
  checkScriptedSpeed(o.speed);
  const double depth = effectiveDepth(scene, o.depth);
  ScriptedPath path = spec == "scripted:circle" ? circlePath(scene, depth) : slidePath(scene, depth);
  return std::make_unique<PathDevice>(toDevice(std::move(path), t), o.speed / t.scale());
}

}  // namespace sf::rt
