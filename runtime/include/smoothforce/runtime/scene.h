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

namespace sf::rt {

/// Object-to-world similarity: world = translation + rotation * (scale * object).
struct Pose {
  Eigen::Vector3d translation{0, 0, 0};                          ///< m
  Eigen::Quaterniond rotation = Eigen::Quaterniond::Identity();  ///< unit quaternion
  double scale = 1;                                              ///< uniform, > 0
};

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
class Scene final : public ForceRenderer {
 public:
  /// Adds an object; its renderer must be set. Poses are checked (scale > 0, finite).
  void add(SceneObject object);
  ForceSample step(const Eigen::Vector3d& hip) noexcept override;
  void reset() noexcept override;
  int patchesBuilt() const noexcept override;

  const std::vector<SceneObject>& objects() const { return objects_; }
  /// Total faces over all objects.
  int totalFaces() const;
  /// World-frame position of vertex v of object i.
  Eigen::Vector3d worldVertex(size_t i, int v) const;

 private:
  struct Frame {
    Eigen::Matrix3d r, rt;  ///< rotation and its transpose
    Eigen::Vector3d t;
    double s = 1;
  };
  std::vector<SceneObject> objects_;
  std::vector<Frame> frames_;
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
/// Each object has exactly one of `mesh` (read now; patches built lazily near the contact) or
/// `cache` (a patch cache file). Optional: `name` (default: the file's stem), `pose`
/// (translation in m; rotation as axis-angle with a non-zero axis (normalised) and an angle
/// in radians, or as a quaternion [w, x, y, z] (normalised; non-zero); uniform scale > 0),
/// `stiffness` (N/m, > 0), `method` (patch|direct|shading), `preset` (fast|balanced|accurate,
/// force_presets.h: the refinement options, and the precision of a `mesh` object's patches;
/// `stiffness` still applies), `comment`. Unknown keys are
/// errors. Throws InputError `FILE: /json/path: message` for bad JSON, missing or unknown
/// fields and bad values; errors inside a mesh or cache file name that file.
Scene loadScene(const std::string& path, const SceneDefaults& defaults, const RendererFactory& factory);

/// A scene of one object at the identity pose.
Scene singleObjectScene(std::shared_ptr<const PatchCache> cache, std::string source, ForceMethod method,
                        const ForceOptions& force, const RendererFactory& factory);

}  // namespace sf::rt
