// SPDX-License-Identifier: Apache-2.0
// The haptic device interface and the simulated devices (null, scripted paths, replay).
#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include <smoothforce/runtime/safety.h>

namespace sf::rt {

/// Whether the device has a usable sample.
enum class DeviceStatus : uint8_t {
  Ok,        ///< position is current
  NoSample,  ///< no sample has arrived yet (a network device before its sender starts): nothing is rendered
  Stale,     ///< the device's watchdog expired: the servo step latches Fault::StaleDevice (zero force)
};

/// What the device reports each step.
struct DeviceState {
  Eigen::Vector3d position{0, 0, 0};  ///< haptic interface point (HIP), m, device frame (DeviceTransform maps it)
  uint32_t buttons = 0;               ///< bit i set: button i pressed
  DeviceStatus status = DeviceStatus::Ok;
  uint64_t sample = 0;  ///< the device's number of this sample (network: the packet's sequence number; else 0)
  double age = 0;       ///< s from when the sample was taken or received to this read (0: simulated)
};

/// The step's outcome that goes with a commanded force (network devices send it back).
struct ForceStatus {
  double loopTime = 0;        ///< s since the loop start
  uint32_t flags = 0;         ///< SafetyFlag | StepFlag bits (servo_step.h)
  Fault fault = Fault::None;  ///< the latched fault, if any (the force is then zero)
  bool contact = false;       ///< the renderer reported contact
};

/// A 3-DoF haptic device as the servo loop sees it. read() and writeForce() run inside the
/// 1 kHz loop and must be real-time safe (no allocation, locking, throwing or blocking I/O).
/// A real driver implements the same two calls (and ignores `t`). Positions and forces are
/// in the device frame; the loop maps them with its DeviceTransform.
class HapticDevice {
 public:
  virtual ~HapticDevice() = default;
  /// Samples the device; t: seconds since the loop started (simulated devices move with it).
  virtual DeviceState read(double t) noexcept = 0;
  /// Commands force `f` (N, device frame) until the next call.
  virtual void writeForce(const Eigen::Vector3d& f) noexcept = 0;
  /// Commands force `f` with the step's status; the loop calls this one. Network devices send
  /// both; the default forwards to writeForce(f). Real-time safe.
  virtual void commandForce(const Eigen::Vector3d& f, const ForceStatus& status) noexcept {
    (void)status;
    writeForce(f);
  }
  /// True when the device can pace the loop (LoopOptions::devicePaced: one step per sample).
  virtual bool canPace() const noexcept { return false; }
  /// Device-paced loops only: returns true as soon as a sample newer than the last read() has
  /// arrived, false after `timeout` s or when the device's watchdog expires first (then read()
  /// reports Stale). This is the loop's wait; it does not allocate or throw.
  virtual bool waitForSample(double timeout) noexcept {
    (void)timeout;
    return false;
  }
  /// One line for the report (not real-time).
  virtual std::string describe() const = 0;
  /// End-of-run lines for the report, each ending in '\n' ("" when none). Not real-time.
  virtual std::string report() const { return {}; }
};

/// Base of the simulated devices: keeps the last commanded force (tests read it).
class SimulatedDevice : public HapticDevice {
 public:
  void writeForce(const Eigen::Vector3d& f) noexcept override {
    lastForce_ = f;
    ++writes_;
  }
  const Eigen::Vector3d& lastForce() const noexcept { return lastForce_; }
  int64_t writes() const noexcept { return writes_; }

 private:
  Eigen::Vector3d lastForce_{0, 0, 0};
  int64_t writes_ = 0;
};

/// `null`: the HIP rests at a fixed point; forces are discarded.
class NullDevice final : public SimulatedDevice {
 public:
  explicit NullDevice(const Eigen::Vector3d& position = Eigen::Vector3d::Zero()) : position_(position) {}
  DeviceState read(double) noexcept override { return {position_, 0}; }
  std::string describe() const override;

 private:
  Eigen::Vector3d position_;
};

/// A polyline traversed at constant speed (arc length = speed * t). Points [0, loopStart]
/// are a lead-in traversed once; then, when closed, points [loopStart, end] repeat as a loop
/// (the last point should equal points[loopStart]); otherwise the whole polyline is
/// traversed back and forth (ping-pong).
struct ScriptedPath {
  std::vector<Eigen::Vector3d> points;  ///< m, at least 2 (the device's frame once handed to a PathDevice)
  size_t loopStart = 0;
  bool closed = false;
  std::string description;  ///< for the report
};

/// `scripted`, `scripted:slide`, `scripted:circle`: moves along a ScriptedPath.
class PathDevice final : public SimulatedDevice {
 public:
  /// speed: m/s (> 0). Throws InputError for an empty or zero-length path.
  PathDevice(ScriptedPath path, double speed);
  DeviceState read(double t) noexcept override;
  std::string describe() const override;
  const ScriptedPath& path() const { return path_; }
  double speed() const { return speed_; }

 private:
  Eigen::Vector3d at(double s) const noexcept;  ///< point at arc length s, clamped to [0, total] (NaN: the first)

  ScriptedPath path_;
  double speed_;
  std::vector<double> arc_;  ///< cumulative arc length at each point, m
};

/// A recorded trajectory: sample times (s, strictly increasing) and positions (m).
struct Trajectory {
  std::vector<double> t;
  std::vector<Eigen::Vector3d> p;
};

/// Reads CSV `t,x,y,z` (an optional header line `t,x,y,z`; blank lines and lines starting
/// with '#' are skipped). Throws InputError naming `path:line` for: a missing file, a wrong
/// column count, a non-numeric or non-finite value, a time not greater than the previous
/// one, no rows.
Trajectory readTrajectoryCsv(const std::string& path);

/// `replay:FILE`: plays a trajectory, linearly interpolated in time; before the first sample
/// it holds the first position, after the last it holds the last.
class ReplayDevice final : public SimulatedDevice {
 public:
  explicit ReplayDevice(Trajectory traj, std::string source = "");
  DeviceState read(double t) noexcept override;
  std::string describe() const override;

 private:
  Trajectory traj_;
  std::string source_;
};

}  // namespace sf::rt
