// SPDX-License-Identifier: Apache-2.0
// Scripted device paths computed from a scene's base polygons, and the --device factory.
#pragma once

#include <Eigen/Geometry>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <smoothforce/runtime/device.h>
#include <smoothforce/runtime/scene.h>

namespace sf::rt {

/// Axis-aligned bounding box of all objects' base-mesh vertices, world frame, m.
Eigen::AlignedBox3d sceneBounds(const Scene& scene);

/// Exact vertical ray casts against the scene's base polygons (each polygon split into a
/// triangle fan from its first corner, in the world frame). For path planning before the
/// loop, not for the loop: each query tests every triangle.
class SurfaceProbe {
 public:
  explicit SurfaceProbe(const Scene& scene);
  /// Height (z, m) of the highest base-polygon point above (x, y), or nullopt when a
  /// vertical line there meets no polygon.
  std::optional<double> topHeight(double x, double y) const;
  size_t triangles() const { return tri_.size(); }

 private:
  struct Tri {
    Eigen::Vector3d a, b, c;
    double xmin, xmax, ymin, ymax;
  };
  std::vector<Tri> tri_;
};

/// The fastest a scripted device moves, m/s along its path (world frame): 10. A hand moves a
/// haptic stylus at up to a few m/s; at 10 m/s a 1 kHz loop already sees the HIP jump 1 cm a
/// step. Beyond it the HIP jumps across contacts between steps (no haptic rendering is left to
/// test), and at 1e308 m/s the arc length overflowed.
inline constexpr double kMaxScriptedSpeed = 10;

/// Parameters of the devices makeDevice makes.
struct ScriptOptions {
  double speed = 0.1;      ///< scripted: m/s along the path, world frame, in (0, kMaxScriptedSpeed]
  double depth = 0;        ///< scripted: m below the top surface (> 0; 0: 1% of the bounding-box diagonal)
  double watchdog = 0.05;  ///< udp: s without a fresh sample before the stale-device fault (> 0)
  double duration = 0;     ///< replay: the run's length, s (> 0: checked, see makeDevice; 0: not checked)
};

/// The depth used for `depth` (m): itself when > 0, else 1% of the scene's bounding-box
/// diagonal. Throws OptionError when it exceeds that diagonal.
double effectiveDepth(const Scene& scene, double depth);

/// `scripted` / `scripted:slide`: the vertical plane y = (bounding-box centre y) is sampled
/// at 257 x positions across the bounding box with SurfaceProbe; the run of hits nearest the
/// centre, less 10% of its length at each end, is the slide. The path starts `depth` above
/// the surface at the run's first point, goes straight down to `depth` below it, follows the
/// sampled top surface `depth` below it (linear between samples) to the last point, rises to
/// `depth` above it; the device traverses it back and forth. Throws InputError when the
/// line meets no surface.
ScriptedPath slidePath(const Scene& scene, double depth);

/// `scripted:circle`: a horizontal circle of radius 25% of the smaller horizontal extent of
/// the bounding box around its centre, `depth` below the top surface (sampled at 256
/// angles), entered straight down from `depth` above the surface at angle 0 and then
/// repeated. Throws InputError when the circle leaves the surface.
ScriptedPath circlePath(const Scene& scene, double depth);

/// Throws InputError ("--speed: expected a speed in (0, 10] m/s, got ...") unless speed (m/s)
/// lies in (0, kMaxScriptedSpeed].
void checkScriptedSpeed(double speed);

/// Throws InputError ("--device: expected ...") unless `spec` is one of the forms below.
void checkDeviceSpec(const std::string& spec);

/// Makes the device named by `spec`: null | scripted | scripted:slide | scripted:circle |
/// replay:FILE | udp:[HOST:]PORT (udp_device.h). The null device rests 10% of the
/// bounding-box diagonal above the top of the bounding box (out of contact). Scripted paths
/// and the null position are planned in the world and handed to the device in the device
/// frame (the inverse of scene.deviceTransform(), speed divided by its scale), so the loop's
/// transform maps them back; a replay file and udp samples are in the device frame. Throws
/// InputError for an unknown spec or bad input: a scripted speed outside (0, kMaxScriptedSpeed];
/// a replay whose first time is not before options.duration (times are seconds from the loop's
/// start: a file of absolute times, e.g. 1.7e9 s since 1970, would hold its first position for
/// the whole run), naming the file, its first time and the duration.
std::unique_ptr<HapticDevice> makeDevice(const std::string& spec, const Scene& scene, const ScriptOptions& options);

}  // namespace sf::rt
