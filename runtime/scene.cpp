// SPDX-License-Identifier: Apache-2.0
// The real-time scene: posed objects, each with its renderer, stepped at the HIP in its frame
// (scene_file.cpp reads scene files into one).
#include <smoothforce/runtime/scene.h>

#include <cmath>
#include <filesystem>
#include <map>
#include <utility>
#include <vector>

#include <smoothforce/base/coordinate_range.h>
#include <smoothforce/force/shared_geometry.h>

namespace sf::rt {

Scene::Frame Scene::frameOf(const Pose& p) noexcept {
  Frame f;
  f.r = p.rotation.normalized().toRotationMatrix();
  f.rt = f.r.transpose();
  f.t = p.translation;
  f.s = p.scale;
  return f;
}

void Scene::add(SceneObject object) {
  if (!object.renderer) throw InputError("scene object '" + object.name + "': no renderer");
  if (!isValid(object.pose) || !inCoordinateRange(object.pose.translation))
    throw InputError("scene object '" + object.name +
                     "': pose must be finite, with a translation within +-1e15 m, a quaternion of norm 1e-12 to 1e150 "
                     "and a scale > 0");
  object.pose.rotation.normalize();
  frames_.push_back(frameOf(object.pose));
  objects_.push_back(std::move(object));
  mailboxes_.push_back(std::make_unique<SeqlockMailbox<PoseWords>>());
}

bool Scene::setPose(size_t i, const Pose& pose) noexcept {
  if (i >= mailboxes_.size() || !isValid(pose)) return false;
  const Eigen::Quaterniond q = pose.rotation.normalized();
  const PoseWords w{
      {pose.translation.x(), pose.translation.y(), pose.translation.z()}, {q.w(), q.x(), q.y(), q.z()}, pose.scale};
  return mailboxes_[i]->tryWrite(w);
}

void Scene::setMaxPoseStep(double metres) {
  if (!(metres > 0) || !std::isfinite(metres)) throw InputError("scene: the pose-jump threshold must be > 0 m");
  maxPoseStep_ = metres;
}

void Scene::applyPoses(const Eigen::Vector3d& hip) noexcept {
  for (size_t i = 0; i < objects_.size(); ++i) {
    Frame& f = frames_[i];
    const SeqlockMailbox<PoseWords>& box = *mailboxes_[i];
    if (box.version() == f.version) continue;
    PoseWords w;
    uint64_t v = 0;
    if (!box.read(w, v) || v == f.version) continue;  // a write in progress: taken at the next step
    Pose& p = objects_[i].pose;
    p.translation = Eigen::Vector3d(w.t[0], w.t[1], w.t[2]);
    p.rotation = Eigen::Quaterniond(w.q[0], w.q[1], w.q[2], w.q[3]);
    p.scale = w.s;
    Frame g = frameOf(p);
    g.version = v;
    // How far the HIP moved in the object's frame, in world metres.
    const Eigen::Vector3d before = f.rt * (hip - f.t) / f.s, after = g.rt * (hip - g.t) / g.s;
    const double moved = (after - before).norm() * g.s;
    ++motion_.updates;
    if (moved > maxPoseStep_) ++motion_.jumps;
    if (moved > motion_.largestStep) motion_.largestStep = moved;
    f = g;
  }
}

ForceSample Scene::step(const Eigen::Vector3d& hip) noexcept {
  applyPoses(hip);
  ForceSample out;
  for (size_t i = 0; i < objects_.size(); ++i) {
    const Frame& f = frames_[i];
    const Eigen::Vector3d local = f.rt * (hip - f.t) / f.s;
    const ForceSample s = objects_[i].renderer->step(local);
    out.force += f.s * (f.r * s.force);
    if (s.contact && !out.contact) {
      out.contact = true;
      out.scp = f.t + f.s * (f.r * s.scp);
      out.normal = f.r * s.normal;
      out.face = s.face;
      out.xi = s.xi;
      out.eta = s.eta;
      out.iterations = s.iterations;
      out.transitions = s.transitions;
      out.status = s.status;
    }
  }
  return out;
}

void Scene::reset() noexcept {
  for (SceneObject& o : objects_) o.renderer->reset();
}

int Scene::patchesBuilt() const noexcept {
  int n = 0;
  for (size_t i = 0; i < objects_.size(); ++i) {  // a store that objects share, once (no allocation: a scan)
    const void* store = objects_[i].renderer->patchStore();
    bool seen = false;
    for (size_t j = 0; j < i && store && !seen; ++j) seen = objects_[j].renderer->patchStore() == store;
    if (!seen) n += objects_[i].renderer->patchesBuilt();
  }
  return n;
}

int Scene::totalFaces() const {
  int n = 0;
  for (size_t i = 0; i < objects_.size(); ++i) {
    bool seen = false;
    for (size_t j = 0; j < i && !seen; ++j) seen = objects_[j].cache == objects_[i].cache;
    if (!seen) n += objects_[i].cache->numFaces();
  }
  return n;
}

Eigen::Vector3d Scene::worldVertex(size_t i, int v) const {
  const Frame& f = frames_[i];
  const double* p = objects_[i].cache->positions.data() + 3 * size_t(v);
  return f.t + f.s * (f.r * Eigen::Vector3d(p[0], p[1], p[2]));
}

RendererFactory sharedRendererFactory() {
  auto shared = std::make_shared<std::map<const PatchCache*, std::shared_ptr<SharedGeometry>>>();
  return [shared](std::shared_ptr<const PatchCache> cache, ForceMethod method, const ForceOptions& options) {
    std::shared_ptr<SharedGeometry>& geometry = (*shared)[cache.get()];
    if (!geometry) geometry = std::make_shared<SharedGeometry>(std::move(cache));
    return geometry->makeRenderer(method, options);
  };
}

ForceOptions servoForceOptions(ForceOptions force) {
  if (force.surfaceIndex == SurfaceIndex::Auto) force.surfaceIndex = SurfaceIndex::Bounds;
  return force;
}

Scene singleObjectScene(std::shared_ptr<const PatchCache> cache, std::string source, ForceMethod method,
                        const ForceOptions& force, const RendererFactory& factory) {
  SceneObject obj;
  obj.name = std::filesystem::path(source).stem().string();
  obj.source = std::move(source);
  obj.method = method;
  obj.force = servoForceOptions(force);
  obj.cache = std::move(cache);
  obj.renderer = factory(obj.cache, method, obj.force);
  if (!obj.renderer) throw InputError(obj.source + ": no renderer");
  Scene s;
  s.add(std::move(obj));
  return s;
}

}  // namespace sf::rt
