#include <smoothforce/sweep/sweep_io.h>

#include <algorithm>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>

#include <smoothforce/force/force_method.h>

namespace sf {

namespace fs = std::filesystem;
using ojson = nlohmann::ordered_json;

namespace {

constexpr char kHipMagic[8] = {'S', 'F', 'S', 'W', 'H', 'I', 'P', '1'};
constexpr char kResMagic[8] = {'S', 'F', 'S', 'W', 'R', 'E', 'S', '1'};

ojson configJson(const SweepConfig& c) {
  return ojson{{"source", c.source},
               {"mesh_hash", c.meshHash},
               {"faces", c.faces},
               {"sample_on", c.sampleOn},
               {"samples", c.samples},
               {"seed", c.seed},
               {"level", c.level},
               {"methods", c.methods},
               {"stiffness", c.stiffness},
               {"approach", c.approach},
               {"refine", c.refine},
               {"angle_tolerance", c.angleTolerance},
               {"max_iterations", c.maxIterations},
               {"initial_guess", c.initialGuess},
               {"guess_level", c.guessLevel},
               {"preset", c.preset},
               {"backend", c.backend},
               {"reference", c.reference},
               {"analytic", c.analytic},
               {"knn", c.knn},
               {"threshold_deg", c.thresholdDeg},
               {"trajectories", c.trajectories},
               {"trajectory_step", c.trajectoryStep},
               {"diagonal", c.diagonal},
               {"area", c.area},
               {"hip_hash", c.hipHash},
               {"depth_labels", c.groupLabels},
               {"depths", c.groupDepths}};
}

SweepConfig configFrom(const ojson& j) {
  SweepConfig c;
  c.source = j.at("source");
  c.meshHash = j.at("mesh_hash");
  c.faces = j.at("faces");
  c.sampleOn = j.at("sample_on");
  c.samples = j.at("samples");
  c.seed = j.at("seed");
  c.level = j.at("level");
  c.methods = j.at("methods").get<std::vector<std::string>>();
  c.stiffness = j.at("stiffness");
  c.approach = j.at("approach");
  c.refine = j.at("refine");
  // absent in sweeps written before the presets: the defaults of that time
  c.angleTolerance = j.value("angle_tolerance", ForceOptions{}.angleTolerance);
  c.maxIterations = j.value("max_iterations", ForceOptions{}.maxIterations);
  c.initialGuess = j.value("initial_guess", std::string("polygon"));
  c.guessLevel = j.value("guess_level", ForceOptions{}.tessellationLevel);
  c.preset = j.value("preset", std::string());
  c.backend = j.at("backend");
  c.reference = j.at("reference");
  c.analytic = j.at("analytic");
  c.knn = j.at("knn");
  c.thresholdDeg = j.at("threshold_deg");
  c.trajectories = j.at("trajectories").get<std::vector<std::string>>();
  c.trajectoryStep = j.at("trajectory_step");
  c.diagonal = j.at("diagonal");
  c.area = j.at("area");
  c.hipHash = j.at("hip_hash");
  c.groupLabels = j.at("depth_labels").get<std::vector<std::string>>();
  c.groupDepths = j.at("depths").get<std::vector<double>>();
  return c;
}

void writeText(const std::string& path, const std::string& text) {
  std::ofstream o(path, std::ios::binary);
  o << text;
  o.close();
  if (!o) throw InputError(path + ": write failed");
}

void writeBlock(const std::string& path, const char magic[8], uint64_t begin, uint64_t end, const void* data,
                size_t bytes) {
  std::FILE* f = std::fopen(path.c_str(), "wb");
  if (!f) throw InputError(path + ": cannot open for writing");
  const uint64_t head[3] = {begin, end, 0};
  bool ok = std::fwrite(magic, 1, 8, f) == 8 && std::fwrite(head, sizeof head, 1, f) == 1;
  if (bytes) ok = ok && std::fwrite(data, 1, bytes, f) == bytes;
  if (std::fclose(f) != 0 || !ok) throw InputError(path + ": write failed");
}

template <class T>
std::vector<T> readBlock(const std::string& path, const char magic[8], uint64_t begin, uint64_t end, size_t perHip) {
  std::FILE* f = std::fopen(path.c_str(), "rb");
  if (!f) throw InputError(path + ": cannot open");
  char m[8];
  uint64_t head[3];
  const bool okHead = std::fread(m, 1, 8, f) == 8 && std::fread(head, sizeof head, 1, f) == 1;
  if (!okHead || std::memcmp(m, magic, 8) != 0) {
    std::fclose(f);
    throw InputError(path + ": not a sweep data file");
  }
  if (head[0] != begin || head[1] != end) {
    std::fclose(f);
    throw InputError(path + ": HIP range differs from sweep.json");
  }
  std::vector<T> v((end - begin) * perHip);
  const bool ok = v.empty() || std::fread(v.data(), sizeof(T), v.size(), f) == v.size();
  char extra;
  const bool tail = std::fread(&extra, 1, 1, f) == 0;
  std::fclose(f);
  if (!ok || !tail) throw InputError(path + ": truncated or oversized");
  return v;
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

void writeSweepData(const SweepData& d, const std::string& dir) {
  fs::create_directories(dir);
  const uint64_t n = d.end - d.begin;
  ojson j{{"smoothforce_sweep_data", 1},
          {"config", configJson(d.config)},
          {"shard", {{"index", d.shardIndex}, {"count", d.shardCount}, {"begin", d.begin}, {"end", d.end}}},
          {"total", d.total()},
          {"interrupted", d.interrupted}};
  writeText(dir + "/sweep.json", j.dump(2) + "\n");
  std::vector<double> xyz;
  xyz.reserve(3 * n);
  for (const auto& h : d.hips) xyz.insert(xyz.end(), {h.x(), h.y(), h.z()});
  writeBlock(dir + "/hips.bin", kHipMagic, d.begin, d.end, xyz.data(), xyz.size() * sizeof(double));
  for (size_t m = 0; m < d.config.methods.size(); ++m)
    writeBlock(dir + "/results_" + d.config.methods[m] + ".bin", kResMagic, d.begin, d.end, d.results[m].data(),
               d.results[m].size() * sizeof(HipResult));
  ojson tr = ojson::array();
  for (const auto& t : d.trajectories)
    tr.push_back(ojson{{"trajectory", t.trajectory},
                       {"method", t.method},
                       {"depth_label", t.depthLabel},
                       {"depth", t.depth},
                       {"step", t.step},
                       {"half", t.half},
                       {"force", t.force},
                       {"contact", t.contact}});
  writeText(dir + "/trajectories.json", tr.dump() + "\n");
}

SweepData readSweepData(const std::string& dir) {
  SweepData d;
  const std::string meta = dir + "/sweep.json";
  std::ifstream in(meta);
  if (!in) throw InputError(meta + ": cannot open (not a sweep output directory?)");
  try {
    const ojson j = ojson::parse(in);
    d.config = configFrom(j.at("config"));
    d.shardIndex = j.at("shard").at("index");
    d.shardCount = j.at("shard").at("count");
    d.begin = j.at("shard").at("begin");
    d.end = j.at("shard").at("end");
    d.interrupted = j.at("interrupted");
    if (d.begin > d.end || d.end > d.total()) throw InputError(meta + ": HIP range outside the sweep");
    std::ifstream tin(dir + "/trajectories.json");
    if (!tin) throw InputError(dir + "/trajectories.json: cannot open");
    for (const auto& t : ojson::parse(tin)) {
      TrajectorySeries s;
      s.trajectory = t.at("trajectory");
      s.method = t.at("method");
      s.depthLabel = t.at("depth_label");
      s.depth = t.at("depth");
      s.step = t.at("step");
      s.half = t.at("half");
      s.force = t.at("force").get<std::vector<float>>();
      s.contact = t.at("contact").get<std::vector<uint8_t>>();
      d.trajectories.push_back(std::move(s));
    }
  } catch (const nlohmann::json::exception& e) {
    throw InputError(dir + ": malformed sweep metadata: " + e.what());
  }
  const auto xyz = readBlock<double>(dir + "/hips.bin", kHipMagic, d.begin, d.end, 3);
  for (size_t i = 0; i < xyz.size(); i += 3) d.hips.emplace_back(xyz[i], xyz[i + 1], xyz[i + 2]);
  for (const auto& m : d.config.methods)
    d.results.push_back(readBlock<HipResult>(dir + "/results_" + m + ".bin", kResMagic, d.begin, d.end, 1));
  return d;
}

SweepData mergeSweepData(std::vector<SweepData> shards) {
  if (shards.empty()) throw InputError("sweep-merge: no inputs");
  std::sort(shards.begin(), shards.end(), [](const SweepData& a, const SweepData& b) { return a.begin < b.begin; });
  // The source path may differ between machines; the mesh and HIP hashes pin the input.
  auto key = [](const SweepConfig& c) {
    ojson j = configJson(c);
    j.erase("source");
    return j.dump();
  };
  const std::string cfg = key(shards[0].config);
  SweepData out;
  out.config = shards[0].config;
  out.begin = 0;
  out.end = out.total();
  out.results.resize(out.config.methods.size());
  uint64_t next = 0;
  for (auto& s : shards) {
    if (key(s.config) != cfg)
      throw InputError("sweep-merge: shard " + std::to_string(s.shardIndex) + "/" + std::to_string(s.shardCount) +
                       " was run with a different configuration or HIP list");
    if (s.begin != next)
      throw InputError("sweep-merge: HIPs " + std::to_string(std::min(next, s.begin)) + ".." +
                       std::to_string(std::max(next, s.begin)) +
                       (s.begin < next ? " are in two shards" : " are missing"));
    next = s.end;
    out.interrupted = out.interrupted || s.interrupted;
    out.hips.insert(out.hips.end(), s.hips.begin(), s.hips.end());
    for (size_t m = 0; m < out.results.size(); ++m)
      out.results[m].insert(out.results[m].end(), s.results[m].begin(), s.results[m].end());
    if (out.trajectories.empty()) out.trajectories = std::move(s.trajectories);
  }
  if (next != out.total())
    throw InputError("sweep-merge: HIPs " + std::to_string(next) + ".." + std::to_string(out.total()) + " are missing");
  return out;
}

}  // namespace sf
