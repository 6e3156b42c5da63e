// SPDX-License-Identifier: Apache-2.0
// writeSweepSummary (sweep_io.h): metrics, summary.json, PLY point clouds, the printed table.
#include <tbb/parallel_for.h>
#include <tbb/parallel_invoke.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <nlohmann/json.hpp>
#include <numbers>

#include <smoothforce/base/status.h>
#include <smoothforce/sweep/sweep_io.h>
#include <smoothforce/sweep/sweep_metrics.h>
#include <smoothforce/sweep/sweep_outputs.h>

#include "json_text.h"
#include "sweep_config_json.h"

namespace sf {

using ojson = nlohmann::ordered_json;

namespace {

constexpr int kHistBins = 60;
constexpr double kHistLo = -4, kHistHi = 2;  // log10(local * spacing / threshold)

ojson num(double x) { return std::isfinite(x) ? ojson(x) : ojson(nullptr); }

ojson pctJson(const Percentiles& p, bool p999 = true) {
  ojson j{{"count", p.count}, {"p50", num(p.p50)}, {"p99", num(p.p99)}};
  if (p999) j["p999"] = num(p.p999);
  j["max"] = num(p.max);
  return j;
}

/// One point cloud to write once every method's discontinuity of its depth is known.
struct CloudJob {
  std::string tag;
  size_t group;
  HipCloud cloud;
};

std::string fmt(const char* f, double x) {
  if (!std::isfinite(x)) return "-";
  char b[64];
  std::snprintf(b, sizeof b, f, x);
  return b;
}

/// One method and depth's probes, tallied (the HIPs done, in HIP order).
struct GroupTally {
  std::vector<Eigen::Vector3d> pos, fdir, nrm;  ///< HIPs, forces, sample normals (when the sweep has them)
  std::vector<char> valid;                      ///< in contact with a nonzero force
  std::vector<uint64_t> index;                  ///< each one's index in the whole run
  std::vector<double> acc, fmag, iters;         ///< in contact: reference distance, |F|; iterations of all
  std::map<uint32_t, size_t> bits;              ///< status bit -> HIPs that have it
  size_t done = 0, contact = 0;
  size_t missed = 0, spurious = 0, undecided = 0;  ///< by the sweep's inside test (SF_PROBE_*)
  size_t missedOnFaults = 0;                       ///< of the missed, within reach of a surface fault
};

GroupTally tallyGroup(const SweepData& d, size_t m, size_t g) {
  const size_t N = d.config.samples;
  GroupTally t;
  for (size_t s = 0; s < N; ++s) {
    const HipResult& r = d.results[m][g * N + s];
    if (!r.done) continue;
    ++t.done;
    const Eigen::Vector3d F(r.force[0], r.force[1], r.force[2]);
    t.pos.push_back(d.hips[g * N + s]);
    if (d.normals.size() == d.hips.size()) t.nrm.push_back(d.normals[g * N + s]);
    if (r.status & SF_PROBE_UNDECIDED)
      ++t.undecided;
    else if ((r.status & SF_PROBE_INSIDE) && !r.contact)
      ++t.missed, t.missedOnFaults += (r.status & SF_PROBE_ON_FAULT) != 0;
    else if (!(r.status & SF_PROBE_INSIDE) && r.contact)
      ++t.spurious;
    t.index.push_back(g * N + s);
    t.fdir.push_back(F);
    t.valid.push_back(r.contact && F.norm() > 0 ? 1 : 0);
    t.contact += r.contact;
    if (r.contact) {
      t.acc.push_back(r.refDistance);
      t.fmag.push_back(F.norm());
    }
    t.iters.push_back(r.iterations);
    for (int b = 0; b < 32; ++b)
      if (r.status & (1u << b)) ++t.bits[1u << b];
  }
  return t;
}

/// Counts of the local discontinuity per bin of log10(local * spacing / threshold): kHistBins
/// bins over [kHistLo, kHistHi), with one below and one above.
std::vector<size_t> discontinuityHistogram(const std::vector<double>& local, double spacing, double thr) {
  std::vector<size_t> hist(kHistBins + 2, 0);
  for (double x : local) {
    if (!std::isfinite(x)) continue;
    const double u = x > 0 ? std::log10(x * spacing / thr) : -1e300;
    const double b = std::floor((u - kHistLo) / (kHistHi - kHistLo) * kHistBins);
    ++hist[b < 0 ? 0 : b >= kHistBins ? kHistBins + 1 : static_cast<size_t>(b) + 1];
  }
  return hist;
}

/// summary.json's entry of one method and depth.
ojson resultJson(const SweepConfig& c, size_t m, size_t g, const GroupTally& t, const Discontinuity& disc,
                 double spacing, double thr, const std::string& tag) {
  double itMean = 0;
  for (double x : t.iters) itMean += x;
  itMean = t.iters.empty() ? 0 : itMean / static_cast<double>(t.iters.size());
  ojson bitJson = ojson::object();
  for (const auto& [b, n] : t.bits) {
    char k[16];
    std::snprintf(k, sizeof k, "0x%08x", b);
    bitJson[k] = n;
  }
  const bool hasRef = !c.reference.empty() || !c.analytic.empty();
  return ojson{{"method", c.methods[m]},
               {"depth", c.groupLabels[g]},
               {"depth_m", c.groupDepths[g]},
               {"hips", c.samples},
               {"done", t.done},
               {"contact", t.contact},
               {"inside_test",
                {{"missed", t.missed},
                 {"missed_on_surface_faults", t.missedOnFaults},
                 {"spurious", t.spurious},
                 {"undecided", t.undecided},
                 {"of",
                  "HIPs inside (outside) the method's surface by the sweep's inside test, without (with) "
                  "contact; missed_on_surface_faults: of the missed, those with patch surface that folds or "
                  "overlaps itself (cache info --faults) no farther from the HIP than its depth; undecided: open "
                  "surface or within the test's error band"}}},
               {"discontinuity",
                {{"unit", "rad/m"},
                 {"count", disc.stats.count},
                 {"p50", num(disc.stats.p50)},
                 {"p99", num(disc.stats.p99)},
                 {"p999", num(disc.stats.p999)},
                 {"max", num(disc.stats.max)},
                 {"flagged_pairs", disc.flaggedPairs},
                 {"left_out_pairs", disc.leftOutPairs},
                 {"sample_normals", t.nrm.size() == t.pos.size()},
                 {"max_neighbour_angle_deg", disc.maxAngle * 180 / std::numbers::pi}}},
               {"accuracy", hasRef ? pctJson(percentiles(t.acc), false) : ojson(nullptr)},
               {"force_N", pctJson(percentiles(t.fmag), false)},
               {"iterations_mean", itMean},
               {"status_bits", bitJson},
               {"histogram",
                {{"of", "log10(local * spacing / threshold)"},
                 {"lo", kHistLo},
                 {"hi", kHistHi},
                 {"bins", kHistBins},
                 {"counts_below_bins_above", discontinuityHistogram(disc.local, spacing, thr)}}},
               {"ply", tag + ".ply"},
               {"vtp", tag + ".vtp"}};
}

/// The largest consecutive force difference of a series (N; NaN for fewer than two points).
double maxDifference(const TrajectorySeries& t) {
  const auto diffs = consecutiveDifferences(t.force);
  return diffs.empty() ? NAN : *std::max_element(diffs.begin(), diffs.end());
}

/// The half-step series of series t (the same path at half the step), or null.
const TrajectorySeries* halfStepOf(const SweepData& d, const TrajectorySeries& t) {
  const TrajectorySeries* half = nullptr;
  for (const auto& h : d.trajectories)
    if (h.half && h.trajectory == t.trajectory && h.method == t.method && h.depthLabel == t.depthLabel) half = &h;
  return half;
}

/// The table's traj|dF| and ratio of one method and depth: its worst trajectory's largest
/// difference, and that series' half-step largest difference over it (NaN: none).
std::array<double, 2> worstTrajectory(const SweepData& d, const std::string& method, const std::string& label) {
  double trajMax = NAN, ratio = NAN;
  for (const auto& t : d.trajectories) {
    if (t.method != method || t.depthLabel != label || t.half) continue;
    const double mx = maxDifference(t);
    if (std::isnan(mx)) continue;  // one point: nothing measured (runSweep refuses such a series)
    const TrajectorySeries* h = halfStepOf(d, t);
    const double mh = h ? maxDifference(*h) : NAN;
    if (!(mx <= trajMax)) {
      trajMax = mx;
      ratio = mh / mx;
    }
  }
  return {trajMax, ratio};
}

/// The rows of the printed table's closing notes, gathered per trajectory series.
struct TrajectoryNotes {
  std::string medialRows;  ///< series with points past the medial axis
  std::string creaseRows;  ///< series that cross creases
};

/// summary.json's "trajectories": one entry per full-step series.
ojson trajectoriesJson(const SweepData& d, TrajectoryNotes& notes) {
  ojson trajs = ojson::array();
  for (const auto& t : d.trajectories) {
    if (t.half) continue;
    const auto diffs = consecutiveDifferences(t.force);
    double mx = 0, mean = 0, mh = NAN;
    for (double x : diffs) {
      mx = std::max(mx, x);
      mean += x;
    }
    mean /= static_cast<double>(diffs.size());
    if (diffs.empty()) mx = NAN;  // one point: not measured (null), not a smooth 0 N
    if (const TrajectorySeries* h = halfStepOf(d, t)) {
      mh = 0;
      for (double x : consecutiveDifferences(h->force)) mh = std::max(mh, x);
    }
    size_t inContact = 0;
    for (auto x : t.contact) inContact += x;
    size_t past = 0;
    for (auto x : t.pastMedialAxis) past += x;
    if (past > 0)
      notes.medialRows += (notes.medialRows.empty() ? "" : ", ") + t.method + " " + t.depthLabel + " " +
                          std::to_string(past) + " of " + std::to_string(t.contact.size());
    size_t crossings = 0;
    for (auto x : t.crease) crossings += x;
    // a crease's force jump lies where the nearest point switches sides: up to about 2 depths
    // along the path from where the path crosses it
    const auto byCrease = maxDifferenceByCreases(t, static_cast<size_t>(std::ceil(2 * t.depth / t.step)) + 1);
    if (crossings > 0)
      notes.creaseRows += (notes.creaseRows.empty() ? "" : ", ") + t.method + " " + t.depthLabel + " " +
                          std::to_string(crossings) + " (max |dF| " + fmt("%.3g", byCrease[1]) + " N at them, " +
                          fmt("%.3g", byCrease[0]) + " N elsewhere)";
    trajs.push_back(ojson{{"trajectory", t.trajectory},
                          {"method", t.method},
                          {"depth", t.depthLabel},
                          {"points", t.contact.size()},
                          {"contact", inContact},
                          {"step_m", t.step},
                          {"max_diff_N", num(mx)},
                          {"mean_diff_N", num(mean)},
                          {"max_diff_half_step_N", num(mh)},
                          {"half_to_full_ratio", num(mh / mx)},
                          {"past_medial_axis", t.pastMedialAxis.empty() ? ojson(nullptr) : ojson(past)},
                          {"crease_crossings", t.crease.empty() ? ojson(nullptr) : ojson(crossings)},
                          {"max_diff_near_creases_N", num(byCrease[1])},
                          {"max_diff_away_from_creases_N", num(byCrease[0])}});
  }
  return trajs;
}

/// The point clouds (.ply, .vtp) and the .npy files, side by side (independent files; 1.6 GB for
/// 10^6 samples at two depths and three methods, 3.8 s one after the other).
void writeClouds(const SweepData& d, const std::vector<CloudJob>& clouds, const std::vector<double>& colourRef,
                 const std::vector<std::vector<double>>& hipDisc, double spacing, double thr, const std::string& dir) {
  tbb::parallel_invoke(
      [&] {
        tbb::parallel_for(size_t(0), 2 * clouds.size(), [&](size_t k) {
          const CloudJob& j = clouds[k / 2];
          const double ref = colourRef[j.group] > 0 ? colourRef[j.group] : thr / std::max(spacing, 1e-300);
          if (k % 2 == 0)
            writeHipPly(dir + "/" + j.tag + ".ply", j.cloud, ref);
          else
            writeHipVtp(dir + "/" + j.tag + ".vtp", j.cloud);
        });
      },
      [&] { writeSweepNpy(d, hipDisc, dir); });
}

/// The printed table's closing lines: what the columns mean, and the notes.
std::string tableNotes(const SweepConfig& c, const TrajectoryNotes& notes, const std::string& faultRows,
                       double spacing, bool complete) {
  std::string table =
      "missed: HIPs inside the method's surface (the sweep's inside test: patch tessellation at twice the "
      "query's level, or the polygons) without contact\n";
  if (!notes.medialRows.empty())
    table += "trajectory points past the medial axis (nearer to another part of the surface than the depth: the "
             "depth exceeds the local feature size there, and |F|, traj|dF| and ratio measure the loop, not the "
             "method): " + notes.medialRows + "\n";
  if (!notes.creaseRows.empty())
    table += "trajectory crease crossings (the force direction jumps where a ridge's nearer side changes, "
             "within 2 depths of the crossing): " + notes.creaseRows + "\n";
  if (!faultRows.empty())
    table += "missed within reach of surface faults (patch surface that folds or overlaps itself no farther from "
             "the HIP than its depth; cache info --faults): " + faultRows + "\n";
  table += "discontinuity: max over the " + std::to_string(c.knn) +
           " nearest HIPs of (angle between force directions) / distance, rad/m; flagged: pairs with angle > " +
           fmt("%g", c.thresholdDeg) + " deg closer than the spacing " + fmt("%.3g", spacing) +
           " m\naccuracy: |SCP - reference|, m; traj|dF|: max |F_{i+1} - F_i| along a trajectory, N; ratio: the same "
           "at half the step / at the step (~0.5 smooth, ~1 a jump)\n";
  if (!complete) table += "PARTIAL: not every HIP was computed (interrupted); metrics cover the HIPs done\n";
  return table;
}

}  // namespace

std::string writeSweepSummary(const SweepData& d, const std::string& dir) {
  if (d.begin != 0 || d.end != d.total())
    throw InputError("sweep summary: only a whole run (or merged shards) can be summarised");
  std::filesystem::create_directories(dir);
  const SweepConfig& c = d.config;
  const size_t N = c.samples;
  const double spacing = N ? std::sqrt(c.area / static_cast<double>(N)) : 0;
  const double thr = c.thresholdDeg * std::numbers::pi / 180;
  bool complete = !d.interrupted;
  ojson results = ojson::array();
  char line[512];
  std::string table;
  std::snprintf(line, sizeof line, "%-8s %-8s %8s %8s %7s | %9s %9s %9s %9s %7s | %9s %9s %9s | %9s %6s\n", "method",
                "depth", "HIPs run", "contact", "missed", "disc p50", "p99", "p99.9", "max", "flagged", "acc p50",
                "p99", "max", "traj|dF|", "ratio");
  table += line;
  std::vector<CloudJob> clouds;
  std::string faultRows;  // per row with missed contacts: how many were pressed in from surface faults
  // Per method, per HIP of the whole run: the discontinuity for the .npy files (NaN: none).
  std::vector<std::vector<double>> hipDisc(c.methods.size(), std::vector<double>(d.hips.size(), NAN));
  std::vector<double> colourRef(c.groupLabels.size(), 0.0);
  for (size_t m = 0; m < c.methods.size(); ++m)
    for (size_t g = 0; g < c.groupLabels.size(); ++g) {
      GroupTally t = tallyGroup(d, m, g);
      if (t.done < N) complete = false;
      const Discontinuity disc = forceDiscontinuity(t.pos, t.fdir, t.valid, c.knn, thr, spacing, 0,
                                                    t.nrm.size() == t.pos.size() ? &t.nrm : nullptr);
      const std::string tag = c.methods[m] + "_" + depthTag(c.groupLabels[g]);
      if (std::isfinite(disc.stats.p50)) colourRef[g] = std::max(colourRef[g], disc.stats.p50);
      results.push_back(resultJson(c, m, g, t, disc, spacing, thr, tag));
      if (t.missed > 0)
        faultRows += (faultRows.empty() ? "" : ", ") + c.methods[m] + " " + c.groupLabels[g] + " " +
                     std::to_string(t.missedOnFaults) + " of " + std::to_string(t.missed);
      const Percentiles accP = percentiles(t.acc);
      const auto [trajMax, ratio] = worstTrajectory(d, c.methods[m], c.groupLabels[g]);
      std::snprintf(line, sizeof line, "%-8s %-8s %8zu %8zu %7zu | %9s %9s %9s %9s %7zu | %9s %9s %9s | %9s %6s\n",
                    c.methods[m].c_str(), c.groupLabels[g].c_str(), t.done, t.contact, t.missed,
                    fmt("%.3g", disc.stats.p50).c_str(), fmt("%.3g", disc.stats.p99).c_str(),
                    fmt("%.3g", disc.stats.p999).c_str(), fmt("%.3g", disc.stats.max).c_str(), disc.flaggedPairs,
                    fmt("%.3g", accP.p50).c_str(), fmt("%.3g", accP.p99).c_str(), fmt("%.3g", accP.max).c_str(),
                    fmt("%.3g", trajMax).c_str(), fmt("%.2f", ratio).c_str());
      table += line;
      for (size_t i = 0; i < t.index.size(); ++i) hipDisc[m][t.index[i]] = disc.local[i];
      clouds.push_back(CloudJob{tag, g, HipCloud{&d, m, std::move(t.index), disc.local}});
    }
  writeClouds(d, clouds, colourRef, hipDisc, spacing, thr, dir);
  TrajectoryNotes notes;
  ojson trajs = trajectoriesJson(d, notes);
  ojson s{{"smoothforce_sweep_summary", 1},
          {"complete", complete},
          {"interrupted", d.interrupted},
          {"hips_total", d.total()},
          {"samples_per_depth", N},
          {"spacing_m", spacing},
          {"config", sweepConfigJson(c)},
          {"results", results},
          {"trajectories", trajs}};
  std::ofstream o(dir + "/summary.json", std::ios::binary);
  o << jsonText(s, 2) << "\n";
  o.close();
  if (!o) throw InputError(dir + "/summary.json: write failed");
  return table + tableNotes(c, notes, faultRows, spacing, complete);
}

}  // namespace sf
