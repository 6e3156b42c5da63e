#include "device.h"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <fstream>

#include "mesh.h"

namespace sf::rt {
namespace {

std::string fmtPoint(const Eigen::Vector3d& p) {
  char buf[96];
  std::snprintf(buf, sizeof buf, "(%.4g, %.4g, %.4g)", p.x(), p.y(), p.z());
  return buf;
}

std::string trim(const std::string& s) {
  const auto a = s.find_first_not_of(" \t\r");
  const auto b = s.find_last_not_of(" \t\r");
  return a == std::string::npos ? "" : s.substr(a, b - a + 1);
}

bool parseDouble(const std::string& field, double& out) {
  const std::string f = trim(field);
  if (f.empty()) return false;
  const auto r = std::from_chars(f.data(), f.data() + f.size(), out);
  return r.ec == std::errc() && r.ptr == f.data() + f.size();
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
  if (s <= 0) return path_.points.front();
  if (s >= arc_.back()) return path_.points.back();
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
  std::ifstream in(path);
  if (!in) throw InputError(path + ": cannot open");
  Trajectory tr;
  std::string line;
  int lineNo = 0;
  auto fail = [&](const std::string& what) { return InputError(path + ":" + std::to_string(lineNo) + ": " + what); };
  bool first = true;
  while (std::getline(in, line)) {
    ++lineNo;
    const std::string tl = trim(line);
    if (tl.empty() || tl[0] == '#') continue;
    std::vector<std::string> cols;
    size_t start = 0;
    for (size_t i = 0; i <= line.size(); ++i)
      if (i == line.size() || line[i] == ',') {
        cols.push_back(line.substr(start, i - start));
        start = i + 1;
      }
    if (first) {
      first = false;
      std::string h;
      for (char ch : tl)
        if (ch != ' ' && ch != '\t') h += ch;
      if (h == "t,x,y,z") continue;
    }
    if (cols.size() != 4) throw fail("expected 4 columns t,x,y,z, got " + std::to_string(cols.size()));
    double v[4];
    static const char* names[4] = {"t", "x", "y", "z"};
    for (int k = 0; k < 4; ++k)
      if (!parseDouble(cols[k], v[k]) || !std::isfinite(v[k]))
        throw fail(std::string(names[k]) + " is not a finite number: '" + trim(cols[k]) + "'");
    if (!tr.t.empty() && !(v[0] > tr.t.back()))
      throw fail("time " + trim(cols[0]) + " s is not greater than the previous row's");
    tr.t.push_back(v[0]);
    tr.p.emplace_back(v[1], v[2], v[3]);
  }
  if (tr.t.empty()) throw InputError(path + ": no samples (expected rows t,x,y,z)");
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
