// SPDX-License-Identifier: Apache-2.0
// End to end on the loopback address: `smoothforce loop --device udp:127.0.0.1:0` with the
// Python client (tools/udp_client.py) as the sender process: a normal run through a scene-file
// device transform, the sender stopping (the watchdog), a device-paced run; option errors.
#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <regex>
#include <sstream>
#include <vector>

#include <Eigen/Geometry>
#include <nlohmann/json.hpp>

#include "cli_test_support.h"

namespace {

namespace fs = std::filesystem;
using Eigen::Vector3d;
using sf::test::CliResult;
using sf::test::smoothforce;

const std::string kClient = std::string(SF_DATA_DIR) + "/../tools/udp_client.py";

/// Runs a shell command, capturing stdout and stderr.
CliResult shell(const std::string& cmd) {
  CliResult r;
  FILE* p = popen((cmd + " 2>&1").c_str(), "r");
  if (!p) return r;
  char buf[4096];
  size_t n;
  while ((n = fread(buf, 1, sizeof buf, p)) > 0) r.out.append(buf, n);
  const int st = pclose(p);
  r.status = WIFEXITED(st) ? WEXITSTATUS(st) : -1;
  return r;
}

/// `smoothforce loop ...` in the background: start() reads its output up to the device line
/// (printed once the socket is bound) and returns the port; finish() reads the rest.
class BackgroundLoop {
 public:
  int start(const std::string& args) {
    p_ = popen(("timeout 60 " + std::string(SF_CLI_PATH) + " loop " + args + " 2>&1").c_str(), "r");
    if (!p_) return -1;
    char line[1024];
    while (std::fgets(line, sizeof line, p_)) {
      out += line;
      std::smatch m;
      const std::string s(line);
      if (std::regex_search(s, m, std::regex(R"(^device: udp 127\.0\.0\.1:([0-9]+) )"))) return std::stoi(m[1]);
    }
    return -1;
  }
  CliResult finish() {
    CliResult r;
    if (!p_) return r;
    char buf[4096];
    size_t n;
    while ((n = fread(buf, 1, sizeof buf, p_)) > 0) out.append(buf, n);
    const int st = pclose(p_);
    p_ = nullptr;
    r.status = WIFEXITED(st) ? WEXITSTATUS(st) : -1;
    r.out = out;
    return r;
  }
  ~BackgroundLoop() {
    if (p_) finish();
  }
  std::string out;

 private:
  FILE* p_ = nullptr;
};

/// Rows of a numeric CSV with a header line.
std::vector<std::vector<double>> readCsv(const std::string& path, std::string* header = nullptr) {
  std::ifstream in(path);
  std::string line;
  std::vector<std::vector<double>> rows;
  if (!std::getline(in, line)) return rows;
  if (header) *header = line;
  while (std::getline(in, line)) {
    std::vector<double> row;
    std::stringstream ss(line);
    for (std::string cell; std::getline(ss, cell, ',');) row.push_back(std::stod(cell));
    rows.push_back(row);
  }
  return rows;
}

long long field(const std::string& text, const std::string& pattern) {
  std::smatch m;
  if (!std::regex_search(text, m, std::regex(pattern))) return -1;
  return std::stoll(m[1]);
}

class RuntimeUdpCli : public ::testing::Test {
 protected:
  void SetUp() override {
    ASSERT_EQ(shell("python3 --version").status, 0) << "python3 is needed for the UDP client";
    ASSERT_TRUE(fs::exists(kClient)) << kClient;
    dir = fs::temp_directory_path() / ("sf_rt_udp_cli_" + std::to_string(::getpid()));
    fs::create_directories(dir);
    std::ofstream(dir / "cube.obj") << "v -0.5 -0.5 -0.5\nv 0.5 -0.5 -0.5\nv -0.5 0.5 -0.5\nv 0.5 0.5 -0.5\n"
                                       "v -0.5 -0.5 0.5\nv 0.5 -0.5 0.5\nv -0.5 0.5 0.5\nv 0.5 0.5 0.5\n"
                                       "f 1 3 4 2\nf 5 6 8 7\nf 1 2 6 5\nf 3 7 8 4\nf 1 5 7 3\nf 2 4 8 6\n";
    // The device reports centimetre-sized motions, tilted and offset: world = t + 10 R device.
    std::ofstream(dir / "scene.json") << R"({"device": {"transform": {"translation": [0.02, -0.01, 0.45],
        "rotation": {"axis": [1, 0, 1], "angle": 0.4}, "scale": 10}},
      "objects": [{"mesh": "cube.obj", "method": "direct", "stiffness": 500}]})";
    r = Eigen::AngleAxisd(0.4, Vector3d(1, 0, 1).normalized()).toRotationMatrix();
    // Down onto the cube's top (z = 0.5) 3 mm deep, across it, up again; written in the device frame.
    const double key[4][4] = {
        {0, -0.1, 0.05, 0.52}, {0.15, -0.1, 0.05, 0.497}, {0.45, 0.1, -0.05, 0.497}, {0.6, 0.1, -0.05, 0.52}};
    std::ofstream traj(dir / "traj.csv");
    traj << "t,x,y,z\n";
    for (const auto& k : key) {
      const Vector3d d = toDevice(Vector3d(k[1], k[2], k[3]));
      char buf[160];
      std::snprintf(buf, sizeof buf, "%.17g,%.17g,%.17g,%.17g\n", k[0], d.x(), d.y(), d.z());
      traj << buf;
    }
  }
  void TearDown() override { fs::remove_all(dir); }
  Vector3d toWorld(const Vector3d& d) const { return Vector3d(0.02, -0.01, 0.45) + 10 * (r * d); }
  Vector3d toDevice(const Vector3d& w) const { return r.transpose() * (w - Vector3d(0.02, -0.01, 0.45)) / 10; }
  std::string path(const std::string& name) const { return (dir / name).string(); }
  CliResult client(int port, const std::string& args) {
    return shell("timeout 60 python3 " + kClient + " --port " + std::to_string(port) + " --trajectory " +
                 path("traj.csv") + " " + args);
  }
  fs::path dir;
  Eigen::Matrix3d r;
};

TEST_F(RuntimeUdpCli, NormalRunThroughTheSceneDeviceTransform) {
  BackgroundLoop loop;
  const int port = loop.start("--scene " + path("scene.json") +
                              " --device udp:127.0.0.1:0 --duration 3 --ramp 0 --max-force-step 100 "
                              "--max-missed 1000000 --watchdog-ms 10000");
  ASSERT_GT(port, 0) << loop.finish().out;
  const CliResult c = client(port, "--rate 1000 --out " + path("forces.csv"));
  const CliResult l = loop.finish();
  ASSERT_EQ(c.status, 0) << c.out;
  ASSERT_EQ(l.status, 0) << l.out;
  EXPECT_NE(l.out.find("device transform: scale 10, rotation 0.4 rad"), std::string::npos) << l.out;
  EXPECT_NE(l.out.find(" of 3000 ticks at 1000 Hz"), std::string::npos) << l.out;
  EXPECT_NE(l.out.find("fault: none"), std::string::npos) << l.out;
  const long long accepted = field(l.out, R"(([0-9]+) samples accepted)");
  EXPECT_GE(accepted, 0.95 * 601) << l.out;  // 0.6 s at 1 kHz: 601 samples, on the loopback
  EXPECT_EQ(field(l.out, R"(([0-9]+) datagrams)"), accepted) << l.out;
  EXPECT_EQ(field(l.out, R"(([0-9]+) malformed)"), 0) << l.out;
  EXPECT_NE(c.out.find("sent 601 HIP samples"), std::string::npos) << c.out;

  std::string header;
  const auto rows = readCsv(path("forces.csv"), &header);
  EXPECT_EQ(header, "seq,sent_t,recv_t,x,y,z,loop_t,fx,fy,fz,status,fault");
  ASSERT_GT(rows.size(), 300u) << c.out;  // about 800 (0.8 s at 1 kHz) less the ticks a loaded machine skips
  int contact = 0;
  for (const auto& row : rows) {
    ASSERT_EQ(row.size(), 12u);
    // The god-object on the top face: F = k (0.5 - z) +z in the world, rotated (not scaled) back.
    const Vector3d w = toWorld(Vector3d(row[3], row[4], row[5]));
    const double depth = std::max(0.0, 0.5 - w.z());
    const Vector3d want = r.transpose() * Vector3d(0, 0, 500 * depth);
    ASSERT_LT((Vector3d(row[7], row[8], row[9]) - want).norm(), 1e-9) << "seq " << row[0];
    ASSERT_EQ(int(row[10]) & 1, depth > 0 ? 1 : 0) << "contact bit, seq " << row[0];
    ASSERT_EQ(row[11], 0);
    contact += depth > 0;
  }
  EXPECT_GT(contact, 100);  // 0.3 s of the slide at 3 mm (about 300 steps)
}

TEST_F(RuntimeUdpCli, SenderStoppedLatchesTheStaleFaultAndZeroForce) {
  BackgroundLoop loop;
  const int port = loop.start("--scene " + path("scene.json") +
                              " --device udp:127.0.0.1:0 --duration 2.5 --ramp 0 --watchdog-ms 200 "
                              "--max-missed 1000000 --record " +
                              path("rec.csv"));
  ASSERT_GT(port, 0) << loop.finish().out;
  const CliResult c = client(port, "--duration 0.3 --linger 0 --out " + path("forces.csv"));
  const CliResult l = loop.finish();
  ASSERT_EQ(c.status, 0) << c.out;
  ASSERT_EQ(l.status, 3) << l.out;  // the CLI contract: a latched safety fault exits 3
  EXPECT_NE(l.out.find("fault: stale device (no sample within the watchdog time) at "), std::string::npos) << l.out;
  std::string header;
  const auto rec = readCsv(path("rec.csv"), &header);
  ASSERT_EQ(header, "tick,t,x,y,z,fx,fy,fz,rfx,rfy,rfz,contact,compute_us,lateness_us,flags,sample,age_us");
  ASSERT_EQ((long long)rec.size(), field(l.out, R"(steps: ([0-9]+) of 2500 ticks)")) << l.out;
  size_t first = 0, stale = 0;
  while (first < rec.size() && (int(rec[first][14]) & (1 << 8))) ++first;  // no sample yet
  stale = first;
  while (stale < rec.size() && !(int(rec[stale][14]) & (1 << 9))) ++stale;
  ASSERT_LT(first, stale);
  ASSERT_LT(stale, rec.size());
  EXPECT_EQ(rec[stale][15], 301) << "the last sample of 0.3 s at 1 kHz";
  EXPECT_GE(rec[stale][16], 200e3);  // its age at the first stale step, us
  EXPECT_LT(rec[stale - 1][16], 200e3);
  for (size_t i = first; i < stale; ++i) ASSERT_EQ(int(rec[i][14]) & (1 << 3), 0) << "faulted early, row " << i;
  for (size_t i = stale; i < rec.size(); ++i) {
    ASSERT_NE(int(rec[i][14]) & (1 << 3), 0) << i;
    ASSERT_EQ(rec[i][5], 0);
    ASSERT_EQ(rec[i][6], 0);
    ASSERT_EQ(rec[i][7], 0);
  }
  std::printf("first stale step %.1f ms after the last sample arrived (watchdog 200 ms)\n", rec[stale][16] * 1e-3);
}

// `loop --json`: a latched fault exits 3 with the fault in "safety" (the CLI contract), and the
// udp device's datagram counters are in "udp" (they were on stderr only).
TEST_F(RuntimeUdpCli, JsonReportCarriesTheFaultAndTheUdpCounters) {
  BackgroundLoop loop;
  const int port = loop.start("--scene " + path("scene.json") +
                              " --device udp:127.0.0.1:0 --duration 1.5 --ramp 0 --watchdog-ms 200 "
                              "--max-missed 1000000 --json");
  ASSERT_GT(port, 0) << loop.finish().out;
  const CliResult c = client(port, "--duration 0.3 --linger 0 --out " + path("forces.csv"));
  const CliResult l = loop.finish();
  ASSERT_EQ(c.status, 0) << c.out;
  ASSERT_EQ(l.status, 3) << l.out;
  EXPECT_NE(l.out.find("smoothforce: loop: safety fault: stale device"), std::string::npos) << l.out;
  const size_t begin = l.out.find("\n{\n"), end = l.out.find("\n}\n", begin);  // stdout, amid stderr's lines
  ASSERT_NE(end, std::string::npos) << l.out;
  const nlohmann::json j = nlohmann::json::parse(l.out.substr(begin + 1, end + 2 - begin - 1));
  EXPECT_EQ(j["exit_status"], 3);
  EXPECT_EQ(j["safety"]["fault"], "stale device (no sample within the watchdog time)");
  const nlohmann::json& u = j["udp"];
  ASSERT_TRUE(u.is_object()) << j.dump(2);
  const long long accepted = u["accepted"].get<long long>();
  EXPECT_GE(accepted, 0.95 * 301) << "0.3 s at 1 kHz";
  EXPECT_LE(accepted, 301);
  EXPECT_EQ(u["datagrams"], accepted);
  for (const char* k : {"duplicates", "out_of_order", "resyncs", "foreign", "wrong_version", "send_errors"})
    EXPECT_EQ(u[k], 0) << k;
  int kinds = 0;
  for (const char* k : {"size", "magic", "type", "reserved", "non_finite", "out_of_range"}) {
    EXPECT_EQ(u["malformed"][k], 0) << k;
    ++kinds;
  }
  EXPECT_EQ(kinds, 6);
  EXPECT_GT(u["forces_sent"].get<long long>(), 0);
  EXPECT_LE(u["superseded"].get<long long>(), 301);
}

TEST_F(RuntimeUdpCli, DevicePacedRunStepsOncePerSample) {
  BackgroundLoop loop;
  const int port = loop.start("--scene " + path("scene.json") +
                              " --device udp:127.0.0.1:0 --paced --rate 500 --duration 3 --ramp 0 "
                              "--max-force-step 100 --max-missed 1000000 --watchdog-ms 5000");
  ASSERT_GT(port, 0) << loop.finish().out;
  const CliResult c = client(port, "--rate 500 --duration 0.5 --out " + path("forces.csv"));
  const CliResult l = loop.finish();
  ASSERT_EQ(c.status, 0) << c.out;
  ASSERT_EQ(l.status, 0) << l.out;
  EXPECT_NE(l.out.find("loop: device-paced"), std::string::npos) << l.out;
  const long long steps = field(l.out, R"(steps: ([0-9]+) device-paced)");
  const long long accepted = field(l.out, R"(([0-9]+) samples accepted)");
  const long long superseded = field(l.out, R"(\(([0-9]+) superseded)");
  ASSERT_GE(steps, 0) << l.out;
  EXPECT_EQ(steps + superseded, accepted) << l.out;
  EXPECT_GE(accepted, 0.95 * 251) << l.out;  // 0.5 s at 500 Hz
  EXPECT_GE(steps, accepted / 2) << l.out;
  EXPECT_LE(steps, 251) << "a fixed 500 Hz loop would run 1500 steps in 3 s";
  const auto rows = readCsv(path("forces.csv"));
  EXPECT_GE(double(rows.size()), 0.98 * double(steps)) << c.out;
  EXPECT_LE(rows.size(), size_t(steps));
  double prev = 0;
  for (const auto& row : rows) {
    ASSERT_GT(row[0], prev) << "one FORCE packet per sample, each echoing a new one";
    prev = row[0];
  }
}

TEST_F(RuntimeUdpCli, OptionAndClientErrorsAreOneLine) {
  auto one = [&](const std::string& args, const std::string& want) {
    const CliResult e = smoothforce("loop --scene " + path("scene.json") + " --duration 0.05 " + args);
    EXPECT_NE(e.status, 0) << args;
    EXPECT_NE(e.out.find(want), std::string::npos) << args << "\n" << e.out;
    EXPECT_EQ(e.out.find('\n'), e.out.size() - 1) << "not one line: " << e.out;
  };
  one("--device scripted --paced", "--paced: only a udp:[HOST:]PORT device paces the loop, got 'scripted'");
  one("--device udp:70000", "--device udp:[HOST:]PORT: expected");
  one("--device udp:127.0.0.1:0 --watchdog-ms 0", "--watchdog-ms: expected a finite time > 0 ms");
  std::ofstream(path("bad.csv")) << "t,x,y,z\n0,0,0,0\n0,1,1,1\n";
  const CliResult c =
      shell("python3 " + kClient + " --port 9 --trajectory " + path("bad.csv") + " --out " + path("f.csv"));
  EXPECT_EQ(c.status, 1);
  EXPECT_NE(c.out.find("bad.csv:3: time 0 s is not greater than the previous row's"), std::string::npos) << c.out;
  EXPECT_EQ(c.out.find('\n'), c.out.size() - 1) << c.out;
}

}  // namespace
