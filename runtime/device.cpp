// SPDX-License-Identifier: Apache-2.0
#include <smoothforce/runtime/device.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>

#include <smoothforce/base/csv_reader.h>
#include <smoothforce/mesh/mesh.h>

namespace sf::rt {
namespace {

std::string fmtPoint(const Eigen::Vector3d& p) {
  char buf[96];
  std::snprintf(buf, sizeof buf, "(%.4g, %.4g, %.4g)", p.x(), p.y(), p.z());
  return buf;
}

}  // namespace

std::string NullDevice::describe() const {
  return "null (HIP fixed at " + fmtPoint(position_) + " m, force discarded)";
}

PathDevice::PathDevice(ScriptedPath path, double speed) : path_(std::move(path)), speed_(speed) {
  if (path_.points.size() < 2) throw InputError("scripted device: the path needs at least 2 points");
  if (!(speed_ > 0) || !std::isfinite(speed_)) throw InputError("--speed: expected a finite speed > 0 m/s");
  if (path_.loopStart >= path_.points.size()) throw InputError("scripted device: loop start past the path end");
  arc_.resize(path_.points.size());
  arc_[0] = 0;
  for (size_t i = 1; i < path_.points.size(); ++i)
    arc_[i] = arc_[i - 1] + (path_.points[i] - path_.points[i - 1]).norm();
  if (!(arc_.back() > 0)) throw InputError("scripted device: the path has zero length");
  if (path_.closed && !(arc_.back() > arc_[path_.loopStart]))
    throw InputError("scripted device: the closed loop has zero length");
}

Eigen::Vector3d PathDevice::at(double s) const noexcept {
  // NaN lands on the first point: an overflowed arc length (inf, then fmod's NaN) passed both
  // tests and read one past the end of arc_.
  if (!(s > 0)) return path_.points.front();
  if (!(s < arc_.back())) return path_.points.back();
  // First point with arc > s; the segment [i-1, i] holds s and has positive length.
  const size_t i = static_cast<size_t>(std::upper_bound(arc_.begin(), arc_.end(), s) - arc_.begin());
  const double a = arc_[i - 1], b = arc_[i];
  const double u = (s - a) / (b - a);
  return path_.points[i - 1] + u * (path_.points[i] - path_.points[i - 1]);
}

DeviceState PathDevice::read(double t) noexcept {
  double s = speed_ * (t > 0 ? t : 0);
  const double total = arc_.back();
  if (path_.closed) {
    const double lead = arc_[path_.loopStart];
    if (s > lead) s = lead + std::fmod(s - lead, total - lead);
  } else {
    s = std::fmod(s, 2 * total);
    if (s > total) s = 2 * total - s;
  }
  return {at(s), 0};
}

std::string PathDevice::describe() const {
  char buf[64];
  std::snprintf(buf, sizeof buf, " at %.4g m/s, path length %.4g m", speed_, arc_.back());
  return path_.description + buf;
}

Trajectory readTrajectoryCsv(const std::string& path) {
  const NumericCsv csv = readNumericCsv(path, {"t", "x", "y", "z"}, /*headerRequired=*/false);
  requirePositions(csv, path, 1);
  Trajectory tr;
  for (size_t r = 0; r < csv.rows(); ++r) {
    if (!tr.t.empty() && !(csv.at(r, 0) > tr.t.back())) {
      char t[32];
      std::snprintf(t, sizeof t, "%.10g", csv.at(r, 0));
      throwCsvError(csvDisplayName(path), csv.line[r],
                    std::string("time ") + t + " s is not greater than the previous row's");
    }
    tr.t.push_back(csv.at(r, 0));
    tr.p.emplace_back(csv.at(r, 1), csv.at(r, 2), csv.at(r, 3));
  }
  return tr;
}

ReplayDevice::ReplayDevice(Trajectory traj, std::string source) : traj_(std::move(traj)), source_(std::move(source)) {
  if (traj_.t.empty() || traj_.t.size() != traj_.p.size()) throw InputError("replay device: empty trajectory");
}

DeviceState ReplayDevice::read(double t) noexcept {
  const auto& ts = traj_.t;
  if (!(t > ts.front())) return {traj_.p.front(), 0};  // also NaN
  if (t >= ts.back()) return {traj_.p.back(), 0};
  const size_t i = static_cast<size_t>(std::upper_bound(ts.begin(), ts.end(), t) - ts.begin());
  const double u = (t - ts[i - 1]) / (ts[i] - ts[i - 1]);
  return {traj_.p[i - 1] + u * (traj_.p[i] - traj_.p[i - 1]), 0};
}

std::string ReplayDevice::describe() const {
  char buf[96];
  std::snprintf(buf, sizeof buf, "%zu samples over %.4g s", traj_.t.size(), traj_.t.back() - traj_.t.front());
  return "replay " + source_ + " (" + buf + ", linear interpolation, ends held)";
}

}  // namespace sf::rt
