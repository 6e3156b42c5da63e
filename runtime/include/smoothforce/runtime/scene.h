// SPDX-License-Identifier: Apache-2.0
// A scene: several posed objects, each with its own force renderer; forces are summed.
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include <smoothforce/force/force_method.h>
#include <smoothforce/patch/patch_cache.h>
#include <smoothforce/runtime/device_transform.h>
#include <smoothforce/runtime/pose.h>
#include <smoothforce/runtime/seqlock.h>

namespace sf::rt {

/// Creates a renderer for one object (makeForceRenderer, or a fake in tests).
using RendererFactory =
    std::function<std::unique_ptr<ForceRenderer>(std::shared_ptr<const PatchCache>, ForceMethod, const ForceOptions&)>;

/// One object of a scene.
struct SceneObject {
  std::string name;
  std::string source;       ///< the mesh or cache file it came from
  bool fromMesh = false;    ///< a mesh: a skeleton cache, patches built lazily by the renderer
  double buildSeconds = 0;  ///< time spent reading the mesh and its normals, s
  Pose pose;
  ForceMethod method = ForceMethod::Patch;
  ForceOptions force;  ///< force.stiffness: N per metre of world-frame penetration
  std::shared_ptr<const PatchCache> cache;
  std::unique_ptr<ForceRenderer> renderer;
};

/// The objects the HIP can touch. step() maps the HIP into each object's frame
/// (p = R^T (hip - t) / s), steps that object's renderer, maps its force back
/// (F = s R F_obj, so that the stiffness is per world metre: the renderer's k (SCP - HIP)
/// in object units times s is k times the world-frame penetration) and sums the forces.
/// The returned sample's scp/normal/face come from the first object in contact (world
/// frame); contact is true when any object is in contact. Real-time safe like the renderers.
///
/// Moving objects: setPose(i, pose) publishes a new pose for object i, and the next step()
/// applies it before it maps the HIP. Each object has a seqlock mailbox (seqlock.h): the
/// caller may be the servo thread between steps or another thread (a physics or ROS thread
/// at its own rate); neither ever waits for the other. Nothing is rebuilt: patches and the
/// polygon queries live in the object's frame. The renderer's contact state (the SCP's face
/// and domain coordinates, or the god-object) is kept in object coordinates, so it moves with
/// the object: in contact, tracking continues from the same surface point towards the HIP's
/// new object-frame position. A slow motion is a slow change of that position, so the force
/// is as continuous as for a HIP moving slowly over a still object. A pose change that moves
/// the HIP's object-frame position by more than maxPoseStep() (measured in world metres) in
/// one step is counted as a jump (motion()). Below the patch method's own jump bound
/// (kJumpDiagonals of the object's diagonal per step, force_tracking.h) tracking continues
/// locally, as for a fast HIP: a surface that moves onto or through the HIP does not let it
/// pop through to the other side; the penetration, and the force, grow at once, and the safety
/// layer clamps and rate-limits the commanded force (and counts it). Beyond it the patch
/// method's global query decides (contact iff the HIP is inside), so that a pose reset or a
/// teleported object leaves no phantom contact; the god-object and force shading keep their
/// proxy, as published.
class Scene final : public ForceRenderer {
 public:
  /// Adds an object; its renderer must be set. Poses are checked (scale > 0, finite).
  /// Not while a loop runs.
  void add(SceneObject object);
  ForceSample step(const Eigen::Vector3d& hip) noexcept override;
  void reset() noexcept override;
  int patchesBuilt() const noexcept override;

  /// Publishes object i's pose for the next step (see above). False, and nothing published,
  /// when i is out of range, the pose is not finite with scale > 0 and a non-zero quaternion,
  /// or another thread is publishing a pose for object i at this very moment. Real-time
  /// safe (no allocation, lock or wait).
  bool setPose(size_t i, const Pose& pose) noexcept;

  /// Pose changes applied by step().
  struct MotionStats {
    int64_t updates = 0;     ///< poses applied (all objects)
    int64_t jumps = 0;       ///< updates that moved the HIP's object-frame position by more than maxPoseStep
    double largestStep = 0;  ///< largest such movement of any update, m (world)
  };
  const MotionStats& motion() const noexcept { return motion_; }
  /// Threshold of a jump, m per step (> 0; default 1 mm, i.e. 1 m/s at 1 kHz). Throws InputError.
  void setMaxPoseStep(double metres);
  double maxPoseStep() const noexcept { return maxPoseStep_; }

  /// Objects with their current poses (updated by step(): read them from the servo thread, or
  /// while no loop runs).
  const std::vector<SceneObject>& objects() const { return objects_; }
  /// Faces of the objects' caches, each cache once (objects may share one: loadScene).
  int totalFaces() const;
  /// World-frame position of vertex v of object i (current pose).
  Eigen::Vector3d worldVertex(size_t i, int v) const;

  /// The device-to-world transform given by the scene file ("device"), identity by default.
  const DeviceTransform& deviceTransform() const noexcept { return device_; }
  void setDeviceTransform(const DeviceTransform& t) { device_ = t; }

 private:
  struct Frame {
    Eigen::Matrix3d r, rt;  ///< rotation and its transpose
    Eigen::Vector3d t;
    double s = 1;
    uint64_t version = 0;  ///< mailbox version applied
  };
  struct PoseWords {  ///< a Pose as plain data for the mailbox
    double t[3], q[4], s;
  };
  static Frame frameOf(const Pose& p) noexcept;
  void applyPoses(const Eigen::Vector3d& hip) noexcept;

  std::vector<SceneObject> objects_;
  std::vector<Frame> frames_;
  std::vector<std::unique_ptr<SeqlockMailbox<PoseWords>>> mailboxes_;
  MotionStats motion_;
  double maxPoseStep_ = 1e-3;
  DeviceTransform device_;
};

/// What objects get when the scene file does not say (and how meshes become patches).
struct SceneDefaults {
  ForceMethod method = ForceMethod::Patch;
  ForceOptions force;         ///< stiffness etc.
  PatchOptions patchOptions;  ///< for objects given as meshes
};

/// Reads a scene file (JSON). Format, with paths relative to the scene file:
///
///     {
///       "objects": [
///         { "name": "spot", "cache": "spot.sfpc",
///           "pose": { "translation": [0, 0, 0.1],
///                     "rotation": { "axis": [0, 0, 1], "angle": 1.5708 },
///                     "scale": 0.1 },
///           "stiffness": 800, "method": "patch" },
///         { "mesh": "cube.obj", "pose": { "rotation": { "quaternion": [1, 0, 0, 0] } } }
///       ]
///     }
///
/// An optional top-level `"device": {"transform": {"translation": .., "rotation": ..,
/// "scale": ..}}` (the same keys as a pose, read device-to-world: device_transform.h) sets
/// deviceTransform(), e.g. `"scale": 0.001` for a device that reports millimetres.
/// Each object has exactly one of `mesh` (read now; patches built lazily near the contact) or
/// `cache` (a patch cache file); objects naming one file (with the same patch options, for a
/// mesh) share one cache, read once. Optional: `name` (default: the file's stem, control
/// characters replaced by '?'; a given name has no control characters and is no other
/// object's name), `pose` (translation in m; rotation as axis-angle with a non-zero axis
/// (normalised) and an angle in radians, or as a quaternion [w, x, y, z] (normalised;
/// non-zero); uniform scale in [kMinSceneScale, kMaxSceneScale] = [1e-9, 1e9], pose.h; the
/// device transform's too); the force options, keys of force_option_text.h read by its parser
/// with its messages (strings, or numbers where they are numbers): `method`
/// (patch|direct|shading), `preset` (fast|balanced|accurate, force_presets.h: the refinement
/// options, and the precision of a `mesh` object's patches; options given beside it override it),
/// `stiffness` (N/m, in (0, 1e12]), `refine`, `angle_tolerance`, `position_tolerance`,
/// `max_iterations`, `initial_guess`, `guess_level`, `final_step`, `patch_capacity` (as the
/// command line's --method, --stiffness, ..., which give the defaults);
/// `precision` (float|double), `normals` (auto|file|angle|area),
/// `cross_tangent` (corrected|paper|blend), `orient` (outward|keep), `cage` (none|catmull-clark,
/// cage_limit.h), `creases` (a list of tags, groups, normals, or none; creases.h), `crease_angle`
/// (a number, degrees in [0, 180)): a `mesh` object's patch options, as the command line's
/// --precision, --normals, --cross-tangent, --orient, --cage, --creases, --crease-angle (which
/// give the defaults; errors on a `cache` object, which keeps its own; values read by
/// patch_option_text.h, with its messages), `comment`. Unknown keys are
/// errors. Throws InputError `FILE: /json/path: message` for bad JSON, missing or unknown
/// fields and bad values; errors inside a mesh or cache file name that file.
Scene loadScene(const std::string& path, const SceneDefaults& defaults, const RendererFactory& factory);

/// A RendererFactory over makeForceRenderer that shares each cache's geometry (polygon scenes,
/// patch surfaces, lazy patches: SharedGeometry) among the renderers it makes, for objects that
/// step on one thread, as a scene's do. loadScene gives objects that name one file with the same
/// patch options one cache, so a scene of many copies of a mesh reads and sets it up once.
RendererFactory sharedRendererFactory();

/// The force options a scene's renderer is made with: `force` with SurfaceIndex::Auto resolved to
/// Bounds (force_method.h): a servo loop holds the compact index of a prebuilt cache, not its
/// tessellation. loadScene and singleObjectScene apply it to every object.
ForceOptions servoForceOptions(ForceOptions force);

/// A scene of one object at the identity pose.
Scene singleObjectScene(std::shared_ptr<const PatchCache> cache, std::string source, ForceMethod method,
                        const ForceOptions& force, const RendererFactory& factory);

}  // namespace sf::rt
