// SPDX-License-Identifier: Apache-2.0
#include <smoothforce/sweep/sweep_io.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>

#include <unistd.h>

#include <smoothforce/base/coordinate_range.h>
#include <smoothforce/base/hash.h>
#include <smoothforce/base/staged_output.h>
#include <smoothforce/force/force_option_text.h>
#include <smoothforce/sweep/sweep_option_text.h>

#include "json_text.h"
#include "sweep_config_json.h"

namespace sf {

namespace fs = std::filesystem;
using ojson = nlohmann::ordered_json;

namespace {

constexpr char kHipMagic[8] = {'S', 'F', 'S', 'W', 'H', 'I', 'P', '1'};
constexpr char kResMagic[8] = {'S', 'F', 'S', 'W', 'R', 'E', 'S', '1'};
constexpr char kNrmMagic[8] = {'S', 'F', 'S', 'W', 'N', 'R', 'M', '1'};

/// The one description of a sweep's configuration as JSON: every key in the order written (the
/// configuration hash is over this text, so the order and the keys stay), what a reader takes
/// when a key is absent (sweeps written before it existed), and when a writer leaves it out.
/// `io` is ConfigWriter or ConfigReader; the force options go through force_option_text.h.
template <class Config, class Io>
void describeConfig(Config& c, Io& io) {
  io.field("source", c.source);
  io.field("mesh_hash", c.meshHash);
  io.field("faces", c.faces);
  io.field("sample_on", c.sampleOn);
  io.field("samples", c.samples);
  io.field("seed", c.seed);
  io.field("level", c.level);
  io.field("methods", c.methods);
  io.force("stiffness", c, true);
  io.field("approach", c.approach);
  io.force("refine", c, true);
  // absent in sweeps written before the presets: the defaults of that time (ForceOptions{})
  io.force("angle_tolerance", c, false);
  io.force("max_iterations", c, false);
  io.force("position_tolerance", c, false);
  io.force("initial_guess", c, false);
  io.force("guess_level", c, false);
  io.optional("preset", c.preset, std::string());
  io.field("backend", c.backend);
  io.field("reference", c.reference);
  io.field("analytic", c.analytic);
  io.field("knn", c.knn);
  io.field("threshold_deg", c.thresholdDeg);
  io.field("trajectories", c.trajectories);
  io.field("trajectory_step", c.trajectoryStep);
  io.field("diagonal", c.diagonal);
  io.field("area", c.area);
  io.field("hip_hash", c.hipHash);
  io.field("depth_labels", c.groupLabels);
  io.field("depths", c.groupDepths);
  // only where there are files: a sweep without them keeps the configuration (and hash) it had
  // before the contents were recorded
  io.unlessEmpty("trajectory_hashes", c.trajectoryHashes);
  io.unlessEmpty("reference_hash", c.referenceHash);
  // only where not the default: a sweep of evaluated final steps keeps the configuration (and
  // hash) it had before the option existed
  io.forceUnlessDefault("final_step", c);
  // only with the bounds index: a sweep on the tessellation (auto resolves to it for a batch, as
  // every sweep before the option existed) keeps its configuration and hash
  io.forceIf("surface_index", c, c.force.surfaceIndex == SurfaceIndex::Bounds);
}

ForceSettings forceSettings(const SweepConfig& c) { return ForceSettings{ForceMethod::Patch, c.force, c.preset}; }

struct ConfigWriter {
  ojson j = ojson::object();
  template <class T>
  void field(const char* key, const T& v) {
    j[key] = v;
  }
  template <class T>
  void optional(const char* key, const T& v, const T&) {
    j[key] = v;
  }
  template <class T>
  void unlessEmpty(const char* key, const T& v) {
    if (!v.empty()) j[key] = v;
  }
  /// A force option as its type: text, a real number or an integer.
  void force(const char* key, const SweepConfig& c, bool) {
    const OptionSpec* spec = findOptionSpec(kForceOptionSpecs, std::size(kForceOptionSpecs), key);
    const std::string text = forceOptionValue(forceSettings(c), key);
    if (spec->type == OptionType::Text)
      j[key] = text;
    else if (spec->type == OptionType::Integer)
      j[key] = std::stoll(text);
    else
      j[key] = std::strtod(text.c_str(), nullptr);
  }
  void forceUnlessDefault(const char* key, const SweepConfig& c) {
    forceIf(key, c, forceOptionValue(forceSettings(c), key) != forceOptionValue(ForceSettings{}, key));
  }
  void forceIf(const char* key, const SweepConfig& c, bool write) {
    if (write) force(key, c, false);
  }
};

struct ConfigReader {
  const ojson& j;
  ForceSettings settings;
  template <class T>
  void field(const char* key, T& v) {
    v = j.at(key).get<T>();
  }
  template <class T>
  void optional(const char* key, T& v, const T& absent) {
    v = j.contains(key) ? j.at(key).get<T>() : absent;
  }
  template <class T>
  void unlessEmpty(const char* key, T& v) {
    if (j.contains(key)) v = j.at(key).get<T>();
  }
  /// A force option through the shared reader: its checks and its message, by key.
  void force(const char* key, SweepConfig&, bool required) {
    if (!j.contains(key)) {
      if (required) (void)j.at(key);  // throws naming the key
      return;
    }
    const ojson& v = j.at(key);
    if (v.is_number())
      setForceOption(settings, key, v.get<double>());
    else
      setForceOption(settings, key, v.get<std::string>());
  }
  void forceUnlessDefault(const char* key, SweepConfig& c) { force(key, c, false); }
  void forceIf(const char* key, SweepConfig& c, bool) { force(key, c, false); }
};

ojson configJson(const SweepConfig& c) {
  ConfigWriter w;
  describeConfig(c, w);
  return w.j;
}

SweepConfig configFrom(const ojson& j) {
  SweepConfig c;
  ConfigReader r{j, {}};
  describeConfig(c, r);
  c.force = r.settings.options;
  checkSweepOptions(c);  // the shared reader's checks, as every front end's
  return c;
}

}  // namespace

ojson sweepConfigJson(const SweepConfig& c) { return configJson(c); }

namespace {

/// Writes through PATH.tmp.PID: data, flush, fsync, close, rename over PATH.
template <class F>
void writeAtomically(const std::string& path, F&& fill) {
  const std::string tmp = stagingPath(path);
  std::FILE* f = std::fopen(tmp.c_str(), "wb");
  if (!f) throw InputError(path + ": cannot open for writing");
  bool ok = fill(f);
  ok = std::fflush(f) == 0 && ok;
  ok = ::fsync(::fileno(f)) == 0 && ok;
  ok = std::fclose(f) == 0 && ok;
  if (!ok || std::rename(tmp.c_str(), path.c_str()) != 0) {
    discardStaging(tmp, path);
    throw InputError(path + ": write failed");
  }
}

void writeText(const std::string& path, const std::string& text) {
  writeAtomically(path, [&](std::FILE* f) { return std::fwrite(text.data(), 1, text.size(), f) == text.size(); });
}

/// Header: magic, begin, end, sweepConfigHash.
void writeBlock(const std::string& path, const char magic[8], uint64_t begin, uint64_t end, uint64_t config,
                const void* data, size_t bytes) {
  writeAtomically(path, [&](std::FILE* f) {
    const uint64_t head[3] = {begin, end, config};
    bool ok = std::fwrite(magic, 1, 8, f) == 8 && std::fwrite(head, sizeof head, 1, f) == 1;
    return ok && (bytes == 0 || std::fwrite(data, 1, bytes, f) == bytes);
  });
}

/// Reads a block written by writeBlock; a header hash of 0 (files older than the hash) is accepted.
template <class T>
std::vector<T> readBlock(const std::string& path, const char magic[8], uint64_t begin, uint64_t end, uint64_t config,
                         size_t perHip) {
  std::FILE* f = std::fopen(path.c_str(), "rb");
  if (!f) throw InputError(path + ": cannot open");
  char m[8];
  uint64_t head[3];
  const bool okHead = std::fread(m, 1, 8, f) == 8 && std::fread(head, sizeof head, 1, f) == 1;
  if (!okHead || std::memcmp(m, magic, 8) != 0) {
    std::fclose(f);
    throw InputError(path + ": not a sweep data file");
  }
  if (head[0] != begin || head[1] != end || (head[2] != 0 && head[2] != config)) {
    std::fclose(f);
    throw InputError(path + (head[2] != 0 && head[2] != config ? ": written by another sweep than sweep.json"
                                                               : ": HIP range differs from sweep.json"));
  }
  std::vector<T> v((end - begin) * perHip);
  const bool ok = v.empty() || std::fread(v.data(), sizeof(T), v.size(), f) == v.size();
  char extra;
  const bool tail = std::fread(&extra, 1, 1, f) == 0;
  std::fclose(f);
  if (!ok || !tail) throw InputError(path + ": truncated or oversized");
  return v;
}

/// The configuration as shards and resumed runs must share it (no `source`).
ojson configKey(const SweepConfig& c) {
  ojson j = configJson(c);
  j.erase("source");
  return j;
}

std::string metaJson(const SweepData& d) {
  ojson done = ojson::object();
  const std::vector<uint64_t> counts = d.doneCounts();
  for (size_t m = 0; m < d.config.methods.size(); ++m) done[d.config.methods[m]] = counts[m];
  ojson j{{"smoothforce_sweep_data", kSweepDataVersion},
          {"config", configJson(d.config)},
          {"shard", {{"index", d.shardIndex}, {"count", d.shardCount}, {"begin", d.begin}, {"end", d.end}}},
          {"total", d.total()},
          {"complete", d.complete()},
          {"interrupted", d.interrupted},
          {"done", done},
          {"trajectory_series",
           {{"total", d.trajectoryTotal},
            {"begin", d.trajectoryBegin},
            {"end", d.trajectoryEnd},
            {"done", d.trajectories.size()}}}};
  return jsonText(j, 2) + "\n";
}

std::string trajectoriesJson(const SweepData& d) {
  ojson tr = ojson::array();
  for (const auto& t : d.trajectories)
    tr.push_back(ojson{{"index", t.index},
                       {"trajectory", t.trajectory},
                       {"method", t.method},
                       {"depth_label", t.depthLabel},
                       {"depth", t.depth},
                       {"step", t.step},
                       {"half", t.half},
                       {"force", t.force},
                       {"contact", t.contact},
                       {"past_medial_axis", t.pastMedialAxis},
                       {"crease", t.crease}});
  return jsonText(ojson{{"config_hash", hexHash(sweepConfigHash(d.config))}, {"series", tr}}) + "\n";
}

}  // namespace

void shardRange(uint64_t total, int index, int count, uint64_t& begin, uint64_t& end) {
  begin = total * static_cast<uint64_t>(index) / static_cast<uint64_t>(count);
  end = total * static_cast<uint64_t>(index + 1) / static_cast<uint64_t>(count);
}

void parseShard(const std::string& text, int& index, int& count) {
  const auto slash = text.find('/');
  bool ok = slash != std::string::npos;
  if (ok) {
    try {
      size_t a = 0, b = 0;
      index = std::stoi(text.substr(0, slash), &a);
      count = std::stoi(text.substr(slash + 1), &b);
      ok = a == slash && b == text.size() - slash - 1 && count >= 1 && index >= 0 && index < count;
    } catch (const std::exception&) {
      ok = false;
    }
  }
  if (!ok) throw InputError("--shard: expected I/N with 0 <= I < N, got '" + text + "'");
}

std::vector<uint64_t> SweepData::doneCounts() const {
  std::vector<uint64_t> n(config.methods.size(), 0);
  for (size_t m = 0; m < n.size() && m < results.size(); ++m)
    for (const HipResult& r : results[m]) n[m] += r.done;
  return n;
}

bool SweepData::complete() const {
  if (results.size() != config.methods.size()) return false;
  for (uint64_t n : doneCounts())
    if (n != end - begin) return false;
  return trajectories.size() == trajectoryEnd - trajectoryBegin;
}

std::string SweepData::label() const {
  return "shard " + std::to_string(shardIndex) + "/" + std::to_string(shardCount) +
         (directory.empty() ? "" : " (" + directory + ")");
}

uint64_t sweepConfigHash(const SweepConfig& c) {
  const std::string k = jsonText(configKey(c));
  return hashBytes(k.data(), k.size());
}

namespace {

/// The difference of the recorded file contents, naming the file; "" when they agree.
std::string fileContentDifference(const SweepConfig& a, const SweepConfig& b) {
  const bool aOld = !a.trajectories.empty() && a.trajectoryHashes.empty(),
             bOld = !b.trajectories.empty() && b.trajectoryHashes.empty();
  const bool aRefOld = !a.reference.empty() && a.referenceHash.empty(),
             bRefOld = !b.reference.empty() && b.referenceHash.empty();
  if (aOld != bOld || aRefOld != bRefOld)
    return "the contents of the --trajectory and --reference files: recorded in one, not in the other (written "
           "before SmoothForce recorded them); run that one again";
  if (a.trajectories == b.trajectories && a.trajectoryHashes.size() == b.trajectoryHashes.size())
    for (size_t i = 0; i < a.trajectoryHashes.size(); ++i)
      if (a.trajectoryHashes[i] != b.trajectoryHashes[i])
        return "the contents of --trajectory " + a.trajectories[i] + " (XXH64 of its points " + a.trajectoryHashes[i] +
               " vs " + b.trajectoryHashes[i] + "): the file changed";
  if (a.reference == b.reference && a.referenceHash != b.referenceHash)
    return "the contents of --reference " + a.reference + " (XXH64 of the mesh " + a.referenceHash + " vs " +
           b.referenceHash + "): the file changed";
  return "";
}

}  // namespace

std::string sweepConfigDifference(const SweepConfig& a, const SweepConfig& b) {
  if (std::string d = fileContentDifference(a, b); !d.empty()) return d;
  const ojson ja = configKey(a), jb = configKey(b);
  for (const auto& [key, value] : ja.items())
    if (!jb.contains(key) || jb.at(key) != value)
      return key + " (" + jsonText(value) + " vs " + (jb.contains(key) ? jsonText(jb.at(key)) : "none") + ")";
  for (const auto& [key, value] : jb.items())
    if (!ja.contains(key)) return key + " (none vs " + jsonText(value) + ")";
  return "";
}

void SweepWriter::write(const SweepData& d) {
  fs::create_directories(dir_);
  const uint64_t config = sweepConfigHash(d.config);
  if (first_) {
    std::vector<double> xyz;
    xyz.reserve(3 * d.hips.size());
    for (const auto& h : d.hips) xyz.insert(xyz.end(), {h.x(), h.y(), h.z()});
    writeBlock(dir_ + "/hips.bin", kHipMagic, d.begin, d.end, config, xyz.data(), xyz.size() * sizeof(double));
    if (d.normals.size() == d.hips.size() && !d.normals.empty()) {
      std::vector<double> nrm;
      nrm.reserve(3 * d.normals.size());
      for (const auto& v : d.normals) nrm.insert(nrm.end(), {v.x(), v.y(), v.z()});
      writeBlock(dir_ + "/normals.bin", kNrmMagic, d.begin, d.end, config, nrm.data(), nrm.size() * sizeof(double));
    }
  }
  const std::vector<uint64_t> done = d.doneCounts();
  for (size_t m = 0; m < d.config.methods.size(); ++m)
    if (first_ || done[m] != done_[m])
      writeBlock(dir_ + "/results_" + d.config.methods[m] + ".bin", kResMagic, d.begin, d.end, config,
                 d.results[m].data(), d.results[m].size() * sizeof(HipResult));
  if (first_ || d.trajectories.size() != series_) writeText(dir_ + "/trajectories.json", trajectoriesJson(d));
  writeText(dir_ + "/sweep.json", metaJson(d));
  first_ = false;
  done_ = done;
  series_ = d.trajectories.size();
}

void writeSweepData(const SweepData& d, const std::string& dir) { SweepWriter(dir).write(d); }

namespace {
/// The per-HIP records a sweep writes hold finite HIPs within the coordinate range, flags 0 or 1
/// (contact only where done), finite forces where done, finite SCPs where in contact and faces of
/// the mesh: a record edited or damaged behind a valid header is refused, naming it, instead of
/// merging a NaN or a contact count above the HIP count into the summary.
void checkRecords(const std::string& dir, const SweepData& d) {
  for (size_t i = 0; i < d.hips.size(); ++i)
    if (!inCoordinateRange(d.hips[i]))
      throw InputError(dir + "/hips.bin: HIP " + std::to_string(d.begin + i) +
                       " is not finite or beyond the coordinate range (1e15 m)");
  for (size_t m = 0; m < d.results.size(); ++m) {
    const std::string file = dir + "/results_" + d.config.methods[m] + ".bin";
    for (size_t i = 0; i < d.results[m].size(); ++i) {
      const HipResult& r = d.results[m][i];
      auto bad = [&](const char* what) {
        throw InputError(file + ": HIP " + std::to_string(d.begin + i) + ": " + what);
      };
      if (r.done > 1 || r.contact > 1) bad("done and contact must be 0 or 1");
      if (r.contact && !r.done) bad("in contact but not done");
      if (!r.done) continue;
      if (!(std::isfinite(r.force[0]) && std::isfinite(r.force[1]) && std::isfinite(r.force[2])))
        bad("force is not finite");
      if (r.contact && !(std::isfinite(r.scp[0]) && std::isfinite(r.scp[1]) && std::isfinite(r.scp[2])))
        bad("SCP of a contact is not finite");
      if (r.face < -1 || (d.config.faces > 0 && r.face >= d.config.faces))
        bad(("face " + std::to_string(r.face) + " outside the mesh's " + std::to_string(d.config.faces)).c_str());
    }
  }
}
}  // namespace

SweepData readSweepData(const std::string& dir) {
  SweepData d;
  d.directory = dir;
  const std::string meta = dir + "/sweep.json";
  std::ifstream in(meta);
  if (!in) throw InputError(meta + ": cannot open (not a sweep output directory?)");
  try {
    const ojson j = ojson::parse(in);
    // another layout would be misread (its per-HIP files included): refused before any field
    const ojson version = j.is_object() ? j.value("smoothforce_sweep_data", ojson()) : ojson();
    if (version != kSweepDataVersion)
      throw InputError(meta + ": sweep data format version " + (version.is_null() ? "(none)" : jsonText(version)) +
                       "; this SmoothForce reads version " + std::to_string(kSweepDataVersion));
    d.config = configFrom(j.at("config"));
    // integers within their ranges (a hand-edited 1e308 or -1 converted to anything)
    auto integer = [&](const char* key, double lo, double hi) {
      const ojson& v = j.at("shard").at(key);
      if (!v.is_number_integer() || !(v.get<double>() >= lo && v.get<double>() <= hi))
        throw InputError(meta + ": shard." + key + ": expected an integer in [" + std::to_string(uint64_t(lo)) + ", " +
                         std::to_string(uint64_t(hi)) + "], got " + jsonText(v));
      return v;
    };
    d.shardCount = integer("count", 1, 1e9);
    d.shardIndex = integer("index", 0, double(d.shardCount) - 1);
    d.begin = integer("begin", 0, 1.8e19);
    d.end = integer("end", 0, 1.8e19);
    d.interrupted = j.at("interrupted");
    if (d.begin > d.end || d.end > d.total()) throw InputError(meta + ": HIP range outside the sweep");
    const std::string tpath = dir + "/trajectories.json";
    std::ifstream tin(tpath);
    if (!tin) throw InputError(tpath + ": cannot open");
    const ojson tj = ojson::parse(tin);
    if (tj.is_object() && tj.at("config_hash") != hexHash(sweepConfigHash(d.config)))
      throw InputError(tpath + ": written by another sweep than sweep.json");
    const ojson& list = tj.is_object() ? tj.at("series") : tj;  // an array: written before checkpoints
    for (const auto& t : list) {
      TrajectorySeries s;
      s.index = t.value("index", static_cast<uint64_t>(d.trajectories.size()));
      s.trajectory = t.at("trajectory");
      s.method = t.at("method");
      s.depthLabel = t.at("depth_label");
      s.depth = t.at("depth");
      s.step = t.at("step");
      s.half = t.at("half");
      s.force = t.at("force").get<std::vector<float>>();
      s.contact = t.at("contact").get<std::vector<uint8_t>>();
      if (t.contains("past_medial_axis")) s.pastMedialAxis = t.at("past_medial_axis").get<std::vector<uint8_t>>();
      if (t.contains("crease")) s.crease = t.at("crease").get<std::vector<uint8_t>>();
      d.trajectories.push_back(std::move(s));
    }
    if (j.contains("trajectory_series")) {
      const ojson& ts = j.at("trajectory_series");
      d.trajectoryTotal = ts.at("total");
      d.trajectoryBegin = ts.at("begin");
      d.trajectoryEnd = ts.at("end");
    } else {  // before checkpoints: shard 0 (or the whole run) ran every series
      d.trajectoryTotal = d.trajectoryEnd = d.trajectories.size();
    }
    if (d.trajectoryBegin > d.trajectoryEnd || d.trajectoryEnd > d.trajectoryTotal)
      throw InputError(meta + ": trajectory series range outside the sweep");
    for (size_t i = 0; i < d.trajectories.size(); ++i) {
      const uint64_t k = d.trajectories[i].index;
      if (k < d.trajectoryBegin || k >= d.trajectoryEnd || (i > 0 && k <= d.trajectories[i - 1].index))
        throw InputError(tpath + ": series " + std::to_string(k) + " outside the shard's range or out of order");
    }
  } catch (const nlohmann::json::exception& e) {
    throw InputError(dir + ": malformed sweep metadata: " + e.what());
  }
  const uint64_t config = sweepConfigHash(d.config);
  const auto xyz = readBlock<double>(dir + "/hips.bin", kHipMagic, d.begin, d.end, config, 3);
  for (size_t i = 0; i < xyz.size(); i += 3) d.hips.emplace_back(xyz[i], xyz[i + 1], xyz[i + 2]);
  if (fs::exists(dir + "/normals.bin")) {  // optional: directories written before it existed lack it
    const auto nrm = readBlock<double>(dir + "/normals.bin", kNrmMagic, d.begin, d.end, config, 3);
    for (size_t i = 0; i < nrm.size(); i += 3) d.normals.emplace_back(nrm[i], nrm[i + 1], nrm[i + 2]);
  }
  for (const auto& m : d.config.methods)
    d.results.push_back(readBlock<HipResult>(dir + "/results_" + m + ".bin", kResMagic, d.begin, d.end, config, 1));
  checkRecords(dir, d);
  return d;
}

SweepData mergeSweepData(std::vector<SweepData> shards) {
  if (shards.empty()) throw InputError("sweep-merge: no inputs");
  std::string incomplete;
  for (const SweepData& s : shards) {
    if (s.complete()) continue;
    std::string what;
    const std::vector<uint64_t> done = s.doneCounts();
    for (size_t m = 0; m < done.size(); ++m)
      what += (what.empty() ? "" : ", ") + s.config.methods[m] + " " + std::to_string(done[m]) + " of " +
              std::to_string(s.end - s.begin) + " HIPs";
    what += ", trajectory series " + std::to_string(s.trajectories.size()) + " of " +
            std::to_string(s.trajectoryEnd - s.trajectoryBegin);
    incomplete += (incomplete.empty() ? "" : "; ") + s.label() + ": " + what;
  }
  if (!incomplete.empty())
    throw InputError("sweep-merge: incomplete shards (continue each with sweep --resume): " + incomplete);
  std::sort(shards.begin(), shards.end(), [](const SweepData& a, const SweepData& b) { return a.begin < b.begin; });
  // The source path may differ between machines; the mesh and HIP hashes pin the input.
  SweepData out;
  out.config = shards[0].config;
  out.begin = 0;
  out.end = out.total();
  out.results.resize(out.config.methods.size());
  uint64_t next = 0;
  bool allNormals = true;
  std::vector<std::pair<uint64_t, std::string>> owners;  // (series index, shard label)
  for (size_t k = 0; k < shards.size(); ++k) {
    SweepData& s = shards[k];
    const std::string diff = sweepConfigDifference(shards[0].config, s.config);
    if (!diff.empty())
      throw InputError("sweep-merge: " + s.label() + " was run with a different configuration or HIP list than " +
                       shards[0].label() + ": " + diff);
    if (s.begin != next)
      throw InputError(
          "sweep-merge: HIPs " + std::to_string(std::min(next, s.begin)) + ".." +
          std::to_string(std::max(next, s.begin)) +
          (s.begin < next ? " are in two shards: " + shards[k - 1].label() + " and " + s.label() : " are missing"));
    next = s.end;
    out.hips.insert(out.hips.end(), s.hips.begin(), s.hips.end());
    allNormals = allNormals && s.normals.size() == s.hips.size();
    out.normals.insert(out.normals.end(), s.normals.begin(), s.normals.end());
    for (size_t m = 0; m < out.results.size(); ++m)
      out.results[m].insert(out.results[m].end(), s.results[m].begin(), s.results[m].end());
    out.trajectoryTotal = std::max(out.trajectoryTotal, s.trajectoryTotal);
    for (auto& t : s.trajectories) {
      owners.emplace_back(t.index, s.label());
      out.trajectories.push_back(std::move(t));
    }
  }
  if (next != out.total())
    throw InputError("sweep-merge: HIPs " + std::to_string(next) + ".." + std::to_string(out.total()) + " are missing");
  std::stable_sort(out.trajectories.begin(), out.trajectories.end(),
                   [](const TrajectorySeries& a, const TrajectorySeries& b) { return a.index < b.index; });
  std::stable_sort(owners.begin(), owners.end(), [](const auto& a, const auto& b) { return a.first < b.first; });
  for (size_t i = 0; i < out.trajectories.size(); ++i)
    if (out.trajectories[i].index != i)
      throw InputError(
          "sweep-merge: trajectory series " + std::to_string(std::min<uint64_t>(i, out.trajectories[i].index)) +
          (out.trajectories[i].index < i ? " is in two shards: " + owners[i - 1].second + " and " + owners[i].second
                                         : " is missing"));
  if (out.trajectories.size() != out.trajectoryTotal)
    throw InputError("sweep-merge: trajectory series " + std::to_string(out.trajectories.size()) + ".." +
                     std::to_string(out.trajectoryTotal) + " are missing");
  if (!allNormals) out.normals.clear();  // a shard from before normals.bin: none
  out.trajectoryEnd = out.trajectoryTotal;
  return out;
}

}  // namespace sf
