// SPDX-License-Identifier: Apache-2.0
// The command line's contract for scripts: exit status per subcommand and
// kind of mistake, results on stdout and diagnostics on stderr, --json, `-` for standard
// input and output, one CSV reader (NumPy `# x,y,z` headers), --cl-device.
#include <gtest/gtest.h>
#include <sys/wait.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <set>
#include <sstream>

#include <smoothforce/config.h>
#include "cli_contract_support.h"

namespace {

namespace fs = std::filesystem;
using sf::test::CliStreams;
using sf::test::fileBytes;
using json = nlohmann::json;

class CliContract : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    dir = fs::temp_directory_path() / ("sf_contract_" + std::to_string(::getpid()));
    fs::create_directories(dir);
    const CliStreams r = sf::test::runStreams(dir, "cache build " + mesh + " -o " + (dir / "spot.sfcache").string());
    ASSERT_EQ(r.status, 0) << r.err;
  }
  static void TearDownTestSuite() { fs::remove_all(dir); }
  CliStreams run(const std::string& args, const std::string& input = "") const {
    return sf::test::runStreams(dir, args, input);
  }
  static std::string file(const std::string& name, const std::string& content = "") {
    const std::string p = (dir / name).string();
    if (!content.empty()) std::ofstream(p, std::ios::binary) << content;
    return p;
  }
  static std::string cache() { return (dir / "spot.sfcache").string(); }
  static inline fs::path dir;
  static inline const std::string mesh = std::string(SF_DATA_DIR) + "/spot_control_mesh.obj";
  static inline const std::string sphere = std::string(SF_SHARED_MESHES) + "/polygon_laplacian/quad-sphere.off";
};

/// x,y,z rows approaching the quad-sphere (radius 1) along +z, pressing in and sliding.
std::string sphereHips(const char* header = "x,y,z") {
  std::string s = std::string(header) + "\n";
  char b[96];
  for (int i = 0; i <= 40; ++i) {
    std::snprintf(b, sizeof b, "%.17g,0.02,%.17g\n", 0.3 * std::sin(0.02 * i), 1.05 - 0.004 * i);
    s += b;
  }
  return s;
}

std::vector<std::string> cells(const std::string& line) {
  std::vector<std::string> c;
  std::istringstream in(line);
  for (std::string f; std::getline(in, f, ',');) c.push_back(f);
  return c;
}

/// The numbers of a CSV file's rows (header dropped).
std::vector<double> numbers(const std::string& text) {
  std::istringstream in(text);
  std::string line;
  std::getline(in, line);
  std::vector<double> v;
  while (std::getline(in, line))
    for (const auto& c : cells(line)) v.push_back(std::stod(c));
  return v;
}

TEST_F(CliContract, ExitStatusPerSubcommandAndKindOfMistake) {
  const std::string c = cache(), o = file("o.csv"), pts = file("pts.csv", "face,xi,eta\n0,0,0\n");
  const std::string hips = file("hips.csv", sphereHips());
  const std::string bad = file("bad.csv", "x,y,z\n1,abc,3\n");
  const std::string outside = file("outside.csv", "face,xi,eta\n0,0.99,0.5\n");
  const std::string garbage = file("garbage.sfcache", std::string(300, 'z'));
  const std::string badObj = file("bad.obj", "v 0 0 0\nv 1 0 0\nf 1 2 9\n");
  const std::string badScene = file("scene.json", R"({"objects": [{"mesh": "none.obj"}]})");
  const std::string far = file("far.csv", "x,y,z\n0,0,0\n1e14,0,0\n");
  const std::string beyond = file("beyond.csv", "x,y,z\n0,0,0\n1e200,0,0\n");
  const std::string justBeyond = file("just.csv", "x,y,z\n0,0,0\n1.0000001e15,0,0\n");
  const std::string plusMinus = file("pm.csv", "x,y,z\n+-1,0,0\n");
  const std::string utf16 = file("u16.csv", std::string("\xff\xfex\0,\0y\0,\0z\0\n\0", 14));
  const std::string onePoint = file("one.csv", "x,y,z\n0,0,0.5\n");
  const std::string samePoints = file("same.csv", "x,y,z\n0,0,0.5\n0,0,0.5\n0,0,0.5\n");
  const std::string path = file("path.csv", "x,y,z\n0,0,0.5\n0.1,0,0.5\n");
  const std::string sw = "sweep --cache " + c + " --samples 10 --no-plots ";
  struct Case {
    std::string args;
    int status;
    std::string message;  ///< a part of the one line on stderr
  };
  const std::vector<Case> cases = {
      // 2: the command line
      {"", 2, "A subcommand is required"},
      {"frobnicate", 2, "A subcommand is required"},
      {"cache build", 2, "MESH is required"},
      {"cache build " + mesh + " --precision half", 2, "--precision"},
      {"cache info", 2, "CACHE is required"},
      {"eval " + c + " -o " + o, 2, "--points is required"},
      {"eval " + c + " --points " + pts + " -o " + o + " --bogus", 2, "--bogus"},
      {"export " + c + " --level 0 -o " + file("x.obj"), 2, "--level"},
      {"trace --hips " + hips + " -o " + o, 2, "give exactly one of --cache and --mesh"},
      {"trace --mesh " + sphere + " --cache " + c + " --hips " + hips + " -o " + o, 2, "excludes"},
      {"trace --mesh " + sphere + " --stiffness -5 --hips " + hips + " -o " + o, 2, "stiffness"},
      {"trace --mesh " + sphere + " --preset turbo --hips " + hips + " -o " + o, 2, "turbo"},
      {"loop --duration 0.05", 2, "give exactly one of --scene, --cache, --mesh"},
      {"loop --mesh " + sphere + " --rate 0", 2, "--rate: expected a rate"},
      {"loop --mesh " + sphere + " --device warp", 2, "--device: expected null, scripted"},
      {"loop --mesh " + sphere + " --normals weird", 2, "--normals"},
      {"loop --mesh " + sphere + " --cl-device 0", 2, "--cl-device"},
      {"loop --mesh " + sphere + " --record -", 2, "--record: give a file"},
      {"sweep --mesh " + sphere + " --samples 10 -o " + file("s"), 2, "give exactly one of --depth and --hips"},
      {"sweep --mesh " + sphere + " --depth 2% --shard 3/3 -o " + file("s"), 2, "--shard"},
      {"sweep --mesh " + sphere + " --depth 2%x -o " + file("s"), 2, "2%x"},
      {"sweep --mesh " + sphere + " --depth 2% --methods patch,nope -o " + file("s"), 2, "nope"},
      {"sweep --mesh " + sphere + " --depth 2% --methods patch,direct,patch -o " + file("s"), 2,
       "--methods: 'patch' is listed twice (items 1 and 3)"},
      {"sweep --mesh " + sphere + " --depth 2% --analytic cube:1 -o " + file("s"), 2, "cube:1"},
      {"sweep --mesh " + sphere + " --depth 2% --analytic sphere:1e300 -o " + file("s"), 2,
       "sphere:1e300: every value must be within the coordinate range (1e15 m)"},
      {"sweep --mesh " + sphere + " --depth 2% --checkpoint-every 0 -o " + file("s"), 2, "--checkpoint-every"},
      {"sweep --mesh " + sphere + " --depth 2% --progress-every nan -o " + file("s"), 2, "--progress-every"},
      {"sweep --mesh " + sphere + " --depth 2% --progress-every -5 -o " + file("s"), 2, "--progress-every"},
      {"sweep --mesh " + sphere + " --depth 2% --methods patch, -o " + file("s"), 2,
       "--methods: an empty item in 'patch,'"},
      {"trace --mesh " + sphere + " --preset '' --hips " + hips + " -o " + o, 2, "got ''"},
      {"sweep --mesh " + sphere + " --depth 2% --trajectory-step -1 -o " + file("s"), 2, "--trajectory-step: '-1'"},
      {"sweep-merge -o " + file("m"), 2, "DIRS is required"},
      {"generate torus --R 1 --r 2 -o " + file("t.obj"), 2, "0 < r < R"},
      {"generate torus-knot --turns nan --trajectory-out " + file("t.csv") + " -o " + file("t.obj"), 2, "--turns"},
      {"trace --mesh " + sphere + " --stiffness 1e308 --hips " + hips + " -o " + o, 2,
       "--stiffness: expected a stiffness in (0, 1e12] N/m, got '1e+308'"},
      // an option value out of range is a usage error, also where the mesh decides it (the depth
      // or approach factor puts HIPs beyond the coordinate range) and for nan
      {sw + "--depth 2% --approach nan -o " + file("s"), 2, "--approach: expected a finite factor > 0, got 'nan'"},
      {sw + "--depth 1e308 -o " + file("s"), 2, "--depth 1e308: HIP 0 lies beyond the coordinate range"},
      {sw + "--depth 2% --approach 1e308 -o " + file("s"), 2, "--approach 1e+308: the approach point of HIP 0"},
      {sw + "--depth 2% --threshold-deg nan -o " + file("s"), 2, "--threshold-deg: expected an angle in (0, 180]"},
      {sw + "--depth 2% --threshold-deg -5 -o " + file("s"), 2, "degrees, got '-5'"},
      {sw + "--depth 2% --threshold-deg 1e308 -o " + file("s"), 2, "degrees, got '1e+308'"},
      {sw + "--depth 0x10 -o " + file("s"), 2, "--depth: '0x10' is not a positive length"},
      {sw + "--depth 2% --seed -1 -o " + file("s"), 2, "--seed: expected an integer in [0, 18446744073709551615]"},
      {sw + "--depth 2% --seed 99999999999999999999999 -o " + file("s"), 2, "got '99999999999999999999999'"},
      {sw + "--depth 1%,2%,1% -o " + file("s"), 2, "--depth: '1%' is listed twice (items 1 and 3)"},
      {sw + "--hips " + hips + " --trajectory " + path + " -o " + file("s"), 2, "--hips with --trajectory"},
      {sw + "--depth 2% --trajectory-step 1e308 -o " + file("s"), 2,
       "--trajectory-step 1e+308 m is longer than the default trajectory"},
      // and too fine for the default loop, and a scripted depth beyond the scene
      {"sweep --cache " + c + " --depth 2% --samples 10 --trajectory-step 1e-12 -o " + file("s"), 2,
       "the default trajectory (a section loop): the polyline is"},
      {"loop --mesh " + sphere + " --depth 1e308 --duration 0.05", 2, "--depth: 1e+308 m is deeper than the scene's"},
      {"generate sphere --radius 1e300 -o " + file("g.obj"), 2, "--radius 1e+300 puts vertices up to 1e+300 m"},
      {"generate torus --R 1e300 --r 1 -o " + file("g.obj"), 2, "beyond the coordinate range +-1e15 m"},
      {"generate torus-knot --p 2000000000 -o " + file("g.obj"), 2, "give --segments >= 4 (|p| + |q|)"},
      {"sweep-merge " + file("m") + " -o " + file("m"), 2, "the output directory " + file("m") + " is the input"},
      {"sweep-merge " + file("m") + " " + file("n") + " " + file("m") + " -o " + file("x"), 2,
       "is listed twice (items 1 and 3)"},
      // 1: a file or its values
      {"sweep --cache " + c + " --hips " + plusMinus + " -o " + file("s"), 1,
       "pm.csv:2: x is not a finite number: '+-1'"},
      {"sweep --cache " + c + " --hips " + justBeyond + " -o " + file("s"), 1,
       "just.csv:3: x = 1.0000001e+15 m is beyond"},
      {"sweep --cache " + c + " --hips " + utf16 + " -o " + file("s"), 1, "u16.csv: is UTF-16 encoded"},
      {sw + "--depth 2% --trajectory " + onePoint + " -o " + file("s"), 1,
       "one.csv: the trajectory has no length (1 point)"},
      {sw + "--depth 2% --trajectory " + samePoints + " -o " + file("s"), 1, "(3 points, all at one place)"},
      {"cache build " + file("nothere.obj") + " -o " + file("n.sfcache"), 1, "nothere.obj"},
      {"cache build " + badObj + " -o " + file("n.sfcache"), 1, "bad.obj:3"},
      {"cache info " + garbage, 1, "not a SmoothForce patch cache"},
      // an export that cannot fit where it goes is refused before any work (/proc: no free space)
      {"export " + c + " --level 2 -o /proc/sf_export.ply", 1, "/proc/sf_export.ply: level 2 needs at least"},
      {"eval " + c + " --points " + outside + " -o " + o, 1, "outside.csv:2"},
      {"eval " + c + " --points " + pts + " -o " + (dir / "no" / "dir" / "o.csv").string(), 1,
       "cannot open for writing"},
      {"trace --cache " + sphere + " --hips " + hips + " -o " + o, 1, "not a patch cache"},
      {"trace --mesh " + sphere + " --hips " + bad + " -o " + o, 1, "bad.csv:2: y is not a finite number"},
      {"loop --cache " + garbage + " --duration 0.05", 1, "not a SmoothForce patch cache"},
      {"loop --mesh " + sphere + " --device replay:" + file("none.csv") + " --duration 0.05", 1, "cannot open"},
      {"loop --scene " + badScene + " --duration 0.05", 1, "/objects/0/mesh"},
      {"sweep --cache " + sphere + " --depth 2% -o " + file("s"), 1, "not a patch cache"},
      // a trajectory too long for its step: refused before any probe, naming the file
      {"sweep --cache " + c + " --depth 2% --samples 10 --trajectory " + far + " -o " + file("s"), 1,
       "far.csv: the polyline is 1e+14 m long"},
      {"sweep --cache " + c + " --depth 2% --samples 10 --trajectory " + beyond + " -o " + file("s"), 1,
       "beyond.csv:3: x = 1e+200 m is beyond the coordinate range"},
      {"trace --cache " + c + " --hips " + beyond + " -o " + o, 1, "beyond.csv:3: x = 1e+200 m"},
      {"sweep-merge " + file("nodir") + " -o " + file("m"), 1, "sweep.json: cannot open"},
      // checked before anything is written or run
      {"generate torus-knot --trajectory-out " + (dir / "no" / "t.csv").string() + " -o " + file("unwritten.obj"), 1,
       "t.csv: cannot open for writing"},
  };
  std::set<std::string> commands;
  for (const Case& k : cases) {
    const CliStreams r = run(k.args);
    EXPECT_EQ(r.status, k.status) << k.args << "\n" << r.err;
    EXPECT_NE(r.err.find(k.message), std::string::npos) << k.args << "\n" << r.err;
    EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << "one line: " << k.args << "\n" << r.err;
    EXPECT_EQ(r.out, "") << "nothing on stdout: " << k.args;
    commands.insert(k.args.substr(0, k.args.find(' ')));
  }
  EXPECT_EQ(cases.size(), 76u);
  EXPECT_FALSE(std::filesystem::exists(file("unwritten.obj"))) << "the OBJ of a generate whose helix cannot be written";
  EXPECT_EQ(commands.size(), 10u);  // "", frobnicate, and the 8 subcommands
  for (const char* help : {"--help", "cache build --help", "trace --help", "loop --help", "sweep --help"})
    EXPECT_EQ(run(help).status, 0) << help;
}

// A face with more sides than a patch can have is a hole in the patch surface: every command
// that opens the mesh says so on stderr, once (before, only `cache build` counted it). The caps
// are wavy: a flat one is fanned into triangles by the fold repair and gets patches.
TEST_F(CliContract, FacesBeyondThePatchSidesAreNoted) {
  std::ostringstream o, bottom, top;  // a prism of 65-gons (a stream: GCC 12 warned of "v " + std::string&& here)
  o.precision(17);
  for (int z = 0; z < 2; ++z)
    for (int k = 0; k < 65; ++k)
      o << "v " << std::cos(2 * M_PI * k / 65) << ' ' << std::sin(2 * M_PI * k / 65) << ' '
        << z + 0.1 * std::sin(6 * M_PI * k / 65) << '\n';
  bottom << 'f';
  top << 'f';
  for (int k = 0; k < 65; ++k) {
    bottom << ' ' << 65 - k;
    top << ' ' << 66 + k;
    o << "f " << k + 1 << ' ' << (k + 1) % 65 + 1 << ' ' << (k + 1) % 65 + 66 << ' ' << k + 66 << '\n';
  }
  o << bottom.str() << '\n' << top.str() << '\n';
  const std::string prism = file("prism65.obj", o.str());
  const std::string hips = file("ph.csv", "x,y,z\n0.1,0.1,0.95\n0.1,0.1,0.5\n");
  int noted = 0;
  for (const std::string& cmd : {"trace --mesh " + prism + " --hips " + hips + " -o " + file("pt.csv"),
                                 "export " + prism + " --level 2 -o " + file("pe.obj"),
                                 "sweep --mesh " + prism + " --depth 1% --samples 50 --no-plots -o " + file("ps")}) {
    const CliStreams r = run(cmd);
    EXPECT_EQ(r.status, 0) << cmd << "\n" << r.err;
    EXPECT_NE(r.err.find("prism65.obj: note: 2 faces with more than 64 sides (up to 65) get no patch"),
              std::string::npos)
        << cmd << "\n"
        << r.err;
    noted += r.err.find("get no patch") != std::string::npos;
  }
  EXPECT_EQ(noted, 3);
}

// Faces that repeat another's vertices (here a double-sided sheet: each triangle twice, opposite
// orders) are noted on stderr by every command that opens the mesh: such a surface encloses
// nothing and its inside tests are unreliable (a trace found 1 kN of phantom contact 2 m away).
TEST_F(CliContract, DuplicateFacesAreNoted) {
  const std::string sheet =
      file("sheet.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 1 1 0\nf 1 2 3\nf 1 3 2\nf 2 4 3\nf 2 3 4\n");
  const std::string hips = file("sh.csv", "x,y,z\n-2,0.1,0.05\n");
  int noted = 0;
  for (const std::string& cmd : {"trace --mesh " + sheet + " --hips " + hips + " -o " + file("st.csv"),
                                 "export " + sheet + " --level 2 -o " + file("se.obj")}) {
    const CliStreams r = run(cmd);
    EXPECT_EQ(r.status, 0) << cmd << "\n" << r.err;
    EXPECT_NE(r.err.find("sheet.obj: note: 2 faces repeat another face's vertices (face 1 first)"), std::string::npos)
        << cmd << "\n"
        << r.err;
    noted += r.err.find("repeat another face's vertices") != std::string::npos;
  }
  EXPECT_EQ(noted, 2);
}

// An output path that is a device is written in place: /dev/null stays a character device.
// Before, outputs written beside the path and renamed into place replaced it with a regular file
// when run as root (`cache build -o /dev/null`), and failed to rename otherwise.
TEST_F(CliContract, OutputsToADeviceAreWrittenInPlace) {
  const std::string hips = file("dn.csv", sphereHips()), pts = file("dnp.csv", "face,xi,eta\n0,0,0\n");
  int written = 0;
  for (const std::string& cmd :
       {"cache build " + sphere + " -o /dev/null", "trace --mesh " + sphere + " --hips " + hips + " -o /dev/null",
        "eval " + sphere + " --points " + pts + " -o /dev/null"}) {
    const CliStreams r = run(cmd);
    EXPECT_EQ(r.status, 0) << cmd << "\n" << r.err;
    EXPECT_TRUE(std::filesystem::is_character_file("/dev/null")) << cmd;
    written += r.status == 0;
  }
  EXPECT_EQ(written, 3);
}

// A report or JSON summary on stdout that cannot be written (/dev/full: no space) is a failed
// write: exit 1 and one line, as `-o -` already reported it; each exited 0 before.
TEST_F(CliContract, AFailedWriteToStdoutIsAnError) {
  if (!std::filesystem::exists("/dev/full")) GTEST_SKIP() << "no /dev/full";
  const std::string c = cache(), pts = file("pts.csv", "face,xi,eta\n0,0,0\n");
  const std::string hips = file("hips.csv", sphereHips());
  const std::vector<std::string> commands = {
      "cache build " + mesh + " -o " + file("c.sfcache"),
      "cache info " + c,
      "cache info --json " + c,
      "eval " + c + " --points " + pts + " -o " + file("e.csv") + " --json",
      "trace --cache " + c + " --hips " + hips + " -o " + file("t.csv") + " --json",
      "sweep --cache " + c + " --samples 10 --depth 2% --methods patch --no-plots -o " + file("sw"),
      "eval " + c + " --points " + pts + " -o -"};
  int failed = 0;
  for (const std::string& args : commands) {
    const std::string err = file("stderr.txt");
    const int raw = std::system((std::string(SF_CLI_PATH) + " " + args + " > /dev/full 2> " + err).c_str());
    const int status = WIFEXITED(raw) ? WEXITSTATUS(raw) : -1;
    const std::string text = fileBytes(err);
    EXPECT_EQ(status, 1) << args << "\n" << text;
    // one error line, the last (a sweep's notes and progress lines come before it)
    const size_t cut = text.size() >= 2 ? text.rfind('\n', text.size() - 2) : std::string::npos;
    const std::string last = cut == std::string::npos ? text : text.substr(cut + 1);
    EXPECT_NE(last.find("<stdout>: write failed"), std::string::npos) << args << "\n" << text;
    EXPECT_EQ(text.find("write failed"), text.rfind("write failed")) << "one error line: " << args << "\n" << text;
    failed += status == 1;
  }
  EXPECT_EQ(failed, 7);
}

// A mesh or reference of zero area is named in the error (it said "sampling: the patches have
// zero area" and "reference mesh has zero area").
TEST_F(CliContract, ZeroAreaMeshesAreNamed) {
  const std::string zero = file("zero.obj", "v 0 0 0\nv 0 0 0\nv 0 0 0\nf 1 2 3\n");
  const std::string sw = " --samples 10 --depth 1% --no-plots --methods patch -o ";
  const CliStreams a = run("sweep --mesh " + zero + sw + file("a"));
  EXPECT_EQ(a.status, 1) << a.err;
  EXPECT_NE(a.err.find(zero + ": sampling: the patches have zero area"), std::string::npos) << a.err;
  const CliStreams b =
      run("sweep --cache " + cache() + sw + file("b") + " --reference " + zero + " --sample-on reference");
  EXPECT_EQ(b.status, 1) << b.err;
  EXPECT_NE(b.err.find(zero + ": the reference mesh has zero area"), std::string::npos) << b.err;
  EXPECT_EQ(std::count(b.err.begin(), b.err.end(), '\n'), 1) << b.err;
}

TEST_F(CliContract, ResultsOnStdoutDiagnosticsOnStderr) {
  const std::string pts = file("pts3.csv", "face,xi,eta\n0,0,0\n17,0.25,-0.4\n179,0.2,-0.3\n");
  CliStreams r = run("cache info " + cache());
  EXPECT_EQ(r.status, 0);
  EXPECT_NE(r.out.find("188 vertices, 180 faces"), std::string::npos) << r.out;
  EXPECT_EQ(r.err, "");
  // eval: the summary on stdout; with -o - the CSV on stdout and the summary on stderr
  const std::string csv = file("e.csv");
  r = run("eval " + cache() + " --points " + pts + " -o " + csv);
  EXPECT_EQ(r.status, 0);
  EXPECT_EQ(r.out, "eval: 3 points -> " + csv + "\n");
  EXPECT_EQ(r.err, "");
  r = run("eval " + cache() + " --points " + pts + " -o -");
  EXPECT_EQ(r.status, 0);
  EXPECT_EQ(r.out, fileBytes(csv));
  EXPECT_EQ(r.err, "eval: 3 points -> <stdout>\n");
  // trace alike
  const std::string hips = file("hips.csv", sphereHips()), tcsv = file("t.csv");
  r = run("trace --mesh " + sphere + " --hips " + hips + " -o " + tcsv);
  EXPECT_EQ(r.status, 0);
  EXPECT_EQ(r.out.rfind("trace: 41 steps", 0), 0u) << r.out;
  EXPECT_EQ(r.err, "");
  r = run("trace --mesh " + sphere + " --hips " + hips + " -o -");
  EXPECT_EQ(r.status, 0);
  EXPECT_EQ(r.out, fileBytes(tcsv));
  EXPECT_EQ(r.err.rfind("trace: 41 steps", 0), 0u) << r.err;
  // loop: the report on stdout; with --json the set-up lines on stderr
  r = run("loop --mesh " + sphere + " --device null --duration 0.05");
  EXPECT_EQ(r.status, 0) << r.err;
  EXPECT_NE(r.out.find("step compute: p50"), std::string::npos) << r.out;
  EXPECT_EQ(r.err, "");
  r = run("loop --mesh " + sphere + " --device null --duration 0.05 --json");
  EXPECT_EQ(r.status, 0) << r.err;
  EXPECT_TRUE(json::accept(r.out)) << r.out;
  EXPECT_NE(r.err.find("device: null"), std::string::npos) << r.err;
  // sweep: notes on stderr, the results table on stdout
  r = run("sweep --mesh " + sphere + " --depth 1% --samples 200 --methods direct --no-plots -o " + file("sw"));
  EXPECT_EQ(r.status, 0) << r.err;
  EXPECT_NE(r.err.find("sweep: built all 512 patches"), std::string::npos) << r.err;
  EXPECT_NE(r.out.find("sweep: direct"), std::string::npos) << r.out;
  EXPECT_EQ(r.out.find("built all"), std::string::npos) << r.out;
}

TEST_F(CliContract, CacheInfoFaultsMeasuresFoldedAndOverlappingSurface) {
  CliStreams r = run("cache info " + cache() + " --faults --json");
  ASSERT_EQ(r.status, 0) << r.err;
  const json j = json::parse(r.out);
  const json& f = j["surface_faults"];
  ASSERT_TRUE(f.is_object()) << r.out;
  EXPECT_EQ(f["closed"], true);
  EXPECT_EQ(f["level"], 11);  // the global query's uniform tessellation of the spot cage
  EXPECT_EQ(f["triangles"], 732 * 11 * 11);  // n L^2 per n-gon
  const double fault = f["fault_area_m2"], total = f["area_m2"];
  EXPECT_NEAR(double(f["folded"]["area_m2"]) + double(f["overlapping"]["area_m2"]) + double(f["thin"]["area_m2"]),
              fault, 1e-12 * total);
  EXPECT_NEAR(double(f["fault_fraction"]), fault / total, 1e-15);
  // the cage's folded patches overlap their neighbours: 1.4% of its area, on and around its 14 fold
  // faces; the folds of 88 and 178 (the ears' tips) are narrower than this tessellation's
  // triangles (at level 32 they too have fault area)
  EXPECT_GT(fault, 0.01 * total);
  EXPECT_LT(fault, 0.03 * total);
  const std::vector<int> faulty = f["fault_faces"], folds = j["patches"]["fold_faces"];
  EXPECT_EQ(folds.size(), 14u);
  int foldsFaulty = 0;
  for (int face : folds) foldsFaulty += std::find(faulty.begin(), faulty.end(), face) != faulty.end();
  EXPECT_EQ(foldsFaulty, 12);
  // split by the cage's 4 intersecting pairs (around its bow-ties): both parts, adding up, every
  // fault face in exactly one
  const double input = f["input_fault_area_m2"], construction = f["construction_fault_area_m2"];
  EXPECT_GT(input, 0);
  EXPECT_GT(construction, 0);
  EXPECT_NEAR(input + construction, fault, 1e-12 * total);
  std::vector<int> split = f["input_fault_faces"], rest = f["construction_fault_faces"];
  split.insert(split.end(), rest.begin(), rest.end());
  std::sort(split.begin(), split.end());
  std::vector<int> all = faulty;
  std::sort(all.begin(), all.end());
  EXPECT_EQ(split, all);

  r = run("cache info " + cache() + " --faults");
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_NE(r.out.find("surface faults (uniform tessellation level 11, 88572 triangles"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("fault faces (largest area first):"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("the input's (within reach of intersecting polygons): "), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("the construction's: "), std::string::npos) << r.out;

  // at a level of the user's: the same measure on that level's tessellation (n L^2 triangles per
  // n-gon: 732 L^2 on the spot cage), the same split
  r = run("cache info " + cache() + " --faults --faults-level 16 --json");
  ASSERT_EQ(r.status, 0) << r.err;
  const json level16 = json::parse(r.out);
  const json& g = level16["surface_faults"];
  EXPECT_EQ(g["level"], 16);
  EXPECT_EQ(g["triangles"], 732 * 16 * 16);
  EXPECT_NEAR(double(g["input_fault_area_m2"]) + double(g["construction_fault_area_m2"]), double(g["fault_area_m2"]),
              1e-12 * total);
  EXPECT_GT(double(g["fault_area_m2"]), 0.01 * total);
  EXPECT_NE(double(g["fault_area_m2"]), fault);
  for (const std::string bad : {" --faults --faults-level 65", " --faults --faults-level -1", " --faults-level 16"}) {
    r = run("cache info " + cache() + bad);
    EXPECT_EQ(r.status, 2) << bad << ": " << r.err;
    EXPECT_NE(r.err.find("--faults-level"), std::string::npos) << r.err;
  }

  // an open mesh has no inside: nothing measured, said so
  const std::string open = (dir / "L-plane.sfcache").string();
  r = run("cache build " + std::string(SF_SHARED_MESHES) + "/polygon_laplacian/L-plane.obj -o " + open);
  ASSERT_EQ(r.status, 0) << r.err;
  r = run("cache info " + open + " --faults --json");
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_EQ(json::parse(r.out)["surface_faults"], json::parse(R"({"closed": false})"));
  r = run("cache info " + open + " --faults");
  EXPECT_NE(r.out.find("surface faults: not measured (the patch surface is not closed"), std::string::npos) << r.out;
}

// Polygons: the spot cage's two bow-ties and four intersecting pairs in `cache build` and `cache
// info` (text, JSON); two cubes
// through each other: 6 intersecting pairs, reported (the cache is built), and with --faults the
// fault area on the cubes is the input's.
TEST_F(CliContract, CacheReportsIntersectingAndSelfCrossingPolygons) {
  CliStreams r = run("cache info " + cache());
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_NE(r.out.find("polygons: 4 intersecting pairs, 2 self-crossing\n  intersecting polygons: 4 pairs (first: "
                       "70-71, 70-72, 160-161, 160-162) on 6 faces, "),
            std::string::npos)
      << r.out;
  EXPECT_NE(r.out.find("\n  self-crossing polygons: 2 (first: 60, 150)\n"), std::string::npos) << r.out;
  r = run("cache info " + cache() + " --json");
  ASSERT_EQ(r.status, 0) << r.err;
  json p = json::parse(r.out)["polygons"];
  EXPECT_EQ(p["self_crossing_faces"], json::parse("[60, 150]"));
  // the cage's polygons next to its bow-ties pass through each other (checked exactly in rationals too)
  EXPECT_EQ(p["intersecting_pairs"], json::parse("[[70, 71], [70, 72], [160, 161], [160, 162]]"));
  EXPECT_EQ(p["intersecting_faces"], json::parse("[70, 71, 72, 160, 161, 162]"));
  EXPECT_GT(double(p["intersecting_area_m2"]), 0);
  EXPECT_LT(double(p["intersecting_area_m2"]), 0.1 * double(p["area_m2"]));
  r = run("cache build " + std::string(SF_DATA_DIR) + "/spot_control_mesh.obj -o " + file("spot2.sfcache"));
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_NE(r.out.find("  self-crossing polygons: 2 (first: 60, 150)\n"), std::string::npos) << r.out;

  // [0, 2]^3 and (1, 1, 1) + [0, 2]^3, faces -x, +x, -y, +y, -z, +z of each
  const std::string obj =
      "v 0 0 0\nv 2 0 0\nv 0 2 0\nv 2 2 0\n"
      "v 0 0 2\nv 2 0 2\nv 0 2 2\nv 2 2 2\n"
      "v 1 1 1\nv 3 1 1\nv 1 3 1\nv 3 3 1\n"
      "v 1 1 3\nv 3 1 3\nv 1 3 3\nv 3 3 3\n"
      "f 1 5 7 3\nf 2 4 8 6\nf 1 2 6 5\nf 3 7 8 4\n"
      "f 1 3 4 2\nf 5 6 8 7\nf 9 13 15 11\nf 10 12 16 14\n"
      "f 9 10 14 13\nf 11 15 16 12\nf 9 11 12 10\nf 13 14 16 15\n";
  const std::string cubes = file("cubes.obj", obj), cubesCache = file("cubes.sfcache");
  r = run("cache build " + cubes + " -o " + cubesCache);
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_NE(r.out.find("  intersecting polygons: 6 pairs (first: 1-8, 1-10, 3-6, 3-10, 5-6, 5-8) on 6 faces, 24 m^2 "
                       "(50% of the area)\n"),
            std::string::npos)
      << r.out;
  r = run("cache info " + cubesCache + " --json --faults");
  ASSERT_EQ(r.status, 0) << r.err;
  const json j = json::parse(r.out);
  p = j["polygons"];
  EXPECT_EQ(p["intersecting_pairs"], json::parse("[[1, 8], [1, 10], [3, 6], [3, 10], [5, 6], [5, 8]]"));
  EXPECT_EQ(p["intersecting_faces"], json::parse("[1, 3, 5, 6, 8, 10]"));
  EXPECT_EQ(p["intersecting_pair_areas_m2"][0], json::parse("[4.0, 4.0]"));
  EXPECT_EQ(p["intersecting_area_m2"], 24.0);
  EXPECT_EQ(p["area_m2"], 48.0);
  const json& f = j["surface_faults"];
  ASSERT_EQ(f["closed"], true);
  // every face of either cube shares a vertex with a crossing one: all of the fault area is the input's
  EXPECT_GT(double(f["fault_area_m2"]), 0);
  EXPECT_NEAR(double(f["input_fault_area_m2"]), double(f["fault_area_m2"]), 1e-12 * double(f["area_m2"]));
  EXPECT_EQ(f["construction_fault_area_m2"], 0.0);
  EXPECT_EQ(f["input_fault_faces"], f["fault_faces"]);
  r = run("cache info " + cubesCache);
  EXPECT_NE(r.out.find("polygons: 6 intersecting pairs, 0 self-crossing\n"), std::string::npos) << r.out;
}

TEST_F(CliContract, CageOptionBuildsAndKeepsTheLimitCache) {
  const std::string cage = file("cage.sfcache");
  CliStreams r = run("cache build " + mesh + " --cage catmull-clark -o " + cage);
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_NE(r.out.find("cage: catmull-clark: 188 vertices moved to their limit positions (0 on a boundary"),
            std::string::npos)
      << r.out;
  EXPECT_NE(r.out.find("Catmull-Clark limit normals of the cage"), std::string::npos) << r.out;
  r = run("cache info " + cage);
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_NE(r.out.find("orient outward, cage catmull-clark"), std::string::npos) << r.out;
  r = run("cache info " + cache());
  EXPECT_NE(r.out.find("orient outward, cage none"), std::string::npos) << r.out;
  r = run("cache info " + cage + " --json");
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_EQ(json::parse(r.out)["options"]["cage"], "catmull-clark");
  // the cage is an option of the surface: a cache keeps it; a mesh gets it now
  const std::string points = file("cage_points.csv", "face,xi,eta\n0,1,0\n");
  r = run("eval " + cage + " --points " + points + " --cage none -o " + file("cage_eval.csv"));
  EXPECT_EQ(r.status, 1);
  EXPECT_NE(r.err.find("built with --cage catmull-clark, but --cage none was given"), std::string::npos) << r.err;
  r = run("eval " + cage + " --points " + points + " -o " + file("cage_eval.csv"));
  ASSERT_EQ(r.status, 0) << r.err;
  const std::string fromCache = fileBytes(dir / "cage_eval.csv");
  r = run("eval " + mesh + " --cage catmull-clark --points " + points + " -o " + file("cage_eval_mesh.csv"));
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_EQ(fileBytes(dir / "cage_eval_mesh.csv"), fromCache);
  // what a cage cannot be is named
  r = run("cache build " + mesh + " --cage catmull-clark --normals area -o " + file("x.sfcache"));
  EXPECT_EQ(r.status, 2);
  EXPECT_NE(r.err.find("--normals area cannot be combined with it"), std::string::npos) << r.err;
  const std::string fin = file("fin.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 -1 0\nv 0 0 1\nf 1 2 3\nf 2 1 4\nf 1 2 5\n");
  r = run("cache build " + fin + " --cage catmull-clark -o " + file("fin.sfcache"));
  EXPECT_EQ(r.status, 1);
  EXPECT_NE(r.err.find("fin.obj: --cage catmull-clark: non-manifold edge 0-1"), std::string::npos) << r.err;
  r = run("cache build " + mesh + " --cage loop -o " + file("x.sfcache"));
  EXPECT_EQ(r.status, 2);
}

// cache build --certify on every backend: the certificate runs on the host's cores after
// construction, so an OpenCL-built cache and a oneTBB-built one (the same records) are the same
// bytes; cache info reports it (text and JSON), and a cache without it says how to get one.
TEST_F(CliContract, CertifyGivesTheSameCacheOnEveryBackend) {
  const std::string cube = std::string(SF_SHARED_MESHES) + "/lagrange/cube.obj";
  const std::string tbb = file("cube_tbb.sfcache"), cl = file("cube_cl.sfcache"), plain = file("cube.sfcache");
  CliStreams r = run("cache build " + cube + " --certify -o " + tbb);
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_NE(r.out.find("certificate: 6 of 6 patches certified fold-free"), std::string::npos) << r.out;
  r = run("cache info " + tbb + " --json");
  ASSERT_EQ(r.status, 0) << r.err;
  const json j = json::parse(r.out);
  EXPECT_EQ(j["format"], 3);  // the fold repair (on by default) keeps each face's source
  EXPECT_EQ(j["certificate"]["certified"], 6);
  EXPECT_EQ(j["certificate"]["uncertified_faces"], json::array());
  ASSERT_EQ(run("cache build " + cube + " -o " + plain).status, 0);
  r = run("cache info " + plain);
  EXPECT_NE(r.out.find("cache: " + plain + ", format 3,"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("certificate: not computed (cache build --certify)"), std::string::npos) << r.out;
  r = run("cache build " + cube + " --backend opencl --cl-device 0 --certify -o " + cl);
  if (!SF_HAS_OPENCL || (r.status != 0 && r.err.find("no OpenCL device") != std::string::npos))
    GTEST_SKIP() << "no OpenCL here: " << r.err;
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_EQ(fileBytes(cl), fileBytes(tbb));
}

TEST_F(CliContract, JsonOutputsParseWithTheDocumentedKeys) {
  auto keys = [](const json& j) {
    std::vector<std::string> k;
    for (const auto& [key, value] : j.items()) k.push_back(key);
    return k;
  };
  using V = std::vector<std::string>;
  CliStreams r = run("cache info " + cache() + " --json");
  ASSERT_EQ(r.status, 0) << r.err;
  json j = json::parse(r.out);
  EXPECT_EQ(keys(j), (V{"boundary_slots", "bytes", "cache", "certificate", "creases", "edge_slots", "face_sizes", "faces",
                        "fold_repair", "format", "memory", "mesh_hash", "non_manifold_slots", "options", "options_hash", "patches",
                        "polygons", "surface_faults", "vertices"}));
  EXPECT_EQ(keys(j["polygons"]), (V{"area_m2", "intersecting_area_m2", "intersecting_faces",
                                    "intersecting_pair_areas_m2", "intersecting_pairs", "self_crossing_faces"}));
  EXPECT_TRUE(j["surface_faults"].is_null());  // measured only with --faults
  EXPECT_TRUE(j["memory"].is_null());          // and only with --memory
  EXPECT_EQ(j["faces"], 180);
  EXPECT_EQ(j["vertices"], 188);
  EXPECT_EQ(j["face_sizes"], json::parse(R"({"3": 4, "4": 160, "5": 16})"));
  EXPECT_EQ(j["bytes"], fs::file_size(cache()));
  EXPECT_EQ(keys(j["options"]),
            (V{"cage", "crease_angle", "creases", "cross_tangent", "fold_repair", "normals", "orient", "precision"}));
  EXPECT_EQ(j["fold_repair"]["mode"], "on");  // the default, with nothing to cut on the cage
  EXPECT_EQ(j["fold_repair"]["cut"], json::array());
  EXPECT_EQ(keys(j["creases"]), (V{"corners", "crease_vertices", "darts", "edges"}));
  EXPECT_TRUE(j["creases"]["edges"].empty());  // the spot cage has no marks
  EXPECT_EQ(j["patches"]["built"], 180);
  EXPECT_EQ(j["patches"]["folds"], j["patches"]["fold_faces"].size());  // the spot cage's 14 folded patches
  EXPECT_EQ(j["patches"]["folds"], 14);

  const std::string pts = file("pts2.csv", "face,xi,eta\n0,0,0\n3,0.1,0.1\n");
  r = run("eval " + cache() + " --points " + pts + " -o " + file("e2.csv") + " --json");
  ASSERT_EQ(r.status, 0) << r.err;
  j = json::parse(r.out);
  EXPECT_EQ(keys(j), (V{"flagged", "input", "output", "points", "precision"}));
  EXPECT_EQ(j["points"], 2);

  const std::string hips = file("hips.csv", sphereHips()), out = file("tj.csv");
  r = run("trace --mesh " + sphere + " --hips " + hips + " -o " + out + " --json");
  ASSERT_EQ(r.status, 0) << r.err;
  j = json::parse(r.out);
  EXPECT_EQ(keys(j), (V{"compute_us_max", "compute_us_mean", "contacts", "faces", "final_step", "in_contact",
                        "max_force_difference_n", "max_force_difference_step", "method", "output", "patches_built",
                        "preset", "refine", "steps"}));
  EXPECT_EQ(j["final_step"], "evaluated");
  // against the CSV it wrote: steps = rows, in_contact = rows with contact 1
  std::istringstream rows(fileBytes(out));
  std::string line;
  std::getline(rows, line);
  int n = 0, contact = 0;
  while (std::getline(rows, line)) {
    ++n;
    contact += cells(line).at(3) == "1";  // x,y,z,contact,...
  }
  EXPECT_EQ(n, 41);
  EXPECT_EQ(j["steps"], n);
  EXPECT_EQ(j["in_contact"], contact);
  EXPECT_GT(contact, 10);

  r = run("loop --mesh " + sphere + " --device scripted --speed 0.5 --duration 0.2 --json");
  ASSERT_EQ(r.status, 0) << r.err;
  j = json::parse(r.out);
  EXPECT_EQ(keys(j), (V{"contact_onsets",
                        "contact_steps",
                        "device",
                        "duration_s",
                        "elapsed_s",
                        "exit_status",
                        "faces",
                        "max_consecutive_misses",
                        "missed_deadlines",
                        "objects",
                        "patches_built",
                        "rate_hz",
                        "records",
                        "safety",
                        "skipped_ticks",
                        "step_compute_us",
                        "steps",
                        "stopped",
                        "ticks",
                        "wake_up_lateness_us"}));
  EXPECT_EQ(keys(j["step_compute_us"]), (V{"max", "p50", "p99", "p99_9"}));
  EXPECT_EQ(j["ticks"], 200);
  EXPECT_EQ(j["steps"].get<int>() + j["skipped_ticks"].get<int>(), 200);
  EXPECT_EQ(j["exit_status"], 0);
  EXPECT_TRUE(j["safety"]["fault"].is_null());
  EXPECT_EQ(j["objects"].size(), 1u);
  EXPECT_GT(j["contact_steps"].get<int>(), 0);
}

TEST_F(CliContract, DashReadsStdinAndWritesStdout) {
  const std::string pts = "face,xi,eta\n0,0,0\n17,0.25,-0.4\n";
  const std::string viaFile = file("ef.csv");
  ASSERT_EQ(run("eval " + cache() + " --points " + file("p.csv", pts) + " -o " + viaFile).status, 0);
  CliStreams r = run("eval " + cache() + " --points - -o -", pts);
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_EQ(r.out, fileBytes(viaFile));
  const std::string hips = sphereHips(), tFile = file("tf.csv");
  ASSERT_EQ(run("trace --mesh " + sphere + " --hips " + file("h.csv", hips) + " -o " + tFile).status, 0);
  r = run("trace --mesh " + sphere + " --hips - -o -", hips);
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_EQ(r.out, fileBytes(tFile));
  // an error in standard input is named <stdin>
  r = run("trace --mesh " + sphere + " --hips - -o -", "x,y,z\n1,2\n");
  EXPECT_EQ(r.status, 1);
  EXPECT_NE(r.err.find("<stdin>:2: expected 3 columns"), std::string::npos) << r.err;
  EXPECT_EQ(r.out, "");
  // sweep --hips -: the same per-HIP results as from the file
  const std::string common = "sweep --mesh " + sphere + " --methods patch,direct --no-plots ";
  ASSERT_EQ(run(common + "--hips " + file("h.csv") + " -o " + file("swf")).status, 0);
  r = run(common + "--hips - -o " + file("sws"), hips);
  ASSERT_EQ(r.status, 0) << r.err;
  for (const char* f : {"results_patch.bin", "results_direct.bin", "hips.bin"})
    EXPECT_EQ(fileBytes(dir / "swf" / f), fileBytes(dir / "sws" / f)) << f;
  // generate --trajectory-out -: the helix on stdout, the report on stderr
  ASSERT_EQ(
      run("generate torus-knot --trajectory-points 50 --trajectory-out " + file("hx.csv") + " -o " + file("k1.obj"))
          .status,
      0);
  r = run("generate torus-knot --trajectory-points 50 --trajectory-out - -o " + file("k2.obj"));
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_EQ(r.out, fileBytes(dir / "hx.csv"));
  EXPECT_NE(r.err.find("generate: torus-knot"), std::string::npos) << r.err;
}

TEST_F(CliContract, OneCsvReaderAcceptsNumpyHeaders) {
  // numpy.savetxt(f, a, delimiter=",", header="x,y,z") writes "# x,y,z" and %.18e values
  auto numpy = [](const std::string& header, const std::string& plain) {
    std::istringstream in(plain);
    std::string line, out = "# " + header + "\n";
    std::getline(in, line);  // the plain header
    while (std::getline(in, line)) {
      std::istringstream cells(line);
      std::string cell, row;
      char b[40];
      while (std::getline(cells, cell, ',')) {
        std::snprintf(b, sizeof b, "%.18e", std::stod(cell));
        if (!row.empty()) row += ',';
        row += b;
      }
      out += row + "\n";
    }
    return out;
  };
  const std::string hips = sphereHips();
  int accepted = 0;
  // trace --hips, sweep --hips, eval --points, loop --device replay: the same numbers either way
  const std::string t1 = file("t1.csv"), t2 = file("t2.csv");
  ASSERT_EQ(run("trace --mesh " + sphere + " --hips " + file("plain.csv", hips) + " -o " + t1).status, 0);
  CliStreams r = run("trace --mesh " + sphere + " --hips " + file("np.csv", numpy("x,y,z", hips)) + " -o " + t2);
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_EQ(fileBytes(t1), fileBytes(t2));
  accepted += r.status == 0;
  r = run("sweep --mesh " + sphere + " --methods direct --no-plots --hips " + file("np.csv") + " -o " + file("swn"));
  EXPECT_EQ(r.status, 0) << r.err;
  accepted += r.status == 0;
  const std::string pts = "face,xi,eta\n0,0,0\n17,0.25,-0.4\n";
  const std::string e1 = file("e1.csv"), e2 = file("e2n.csv");
  ASSERT_EQ(run("eval " + cache() + " --points " + file("pp.csv", pts) + " -o " + e1).status, 0);
  r = run("eval " + cache() + " --points " + file("pn.csv", "# made by gen.py\n" + numpy("face,xi,eta", pts)) + " -o " +
          e2);
  EXPECT_EQ(r.status, 0) << r.err;
  EXPECT_EQ(fileBytes(e1), fileBytes(e2));
  accepted += r.status == 0;
  r = run("loop --mesh " + sphere +
          " --duration 0.02 --device replay:" + file("rp.csv", numpy("t,x,y,z", "t,x,y,z\n0,0,0,1.1\n1,0,0,0.9\n")));
  EXPECT_EQ(r.status, 0) << r.err;
  accepted += r.status == 0;
  EXPECT_EQ(accepted, 4);
  // CR-only line ends (old Mac OS) are line ends: the same numbers
  std::string cr = hips;
  std::replace(cr.begin(), cr.end(), '\n', '\r');
  r = run("trace --mesh " + sphere + " --hips " + file("cr.csv", cr) + " -o " + t2);
  EXPECT_EQ(r.status, 0) << r.err;
  EXPECT_EQ(fileBytes(t1), fileBytes(t2));
  // a '#' line that is not the header stays a comment: the data line is then not a header
  r = run("trace --mesh " + sphere + " --hips " + file("wrong.csv", "# a,b,c\n1,2,3\n") + " -o " + t2);
  EXPECT_EQ(r.status, 1);
  EXPECT_NE(r.err.find("wrong.csv:2: expected header 'x,y,z', got '1,2,3'"), std::string::npos) << r.err;
}

// Loggers and spreadsheets write the same columns other ways: named in another case, order or
// quoting, among other columns, split by semicolons, tabs or blanks. Every such file gives the
// plain file's trace, every HIP equal; a header without a wanted column names it.
TEST_F(CliContract, OneCsvReaderTakesColumnsByName) {
  const std::string hips = sphereHips();
  std::vector<std::vector<std::string>> rows;  // the x, y, z cells of every HIP
  {
    std::istringstream in(hips);
    std::string line;
    std::getline(in, line);
    while (std::getline(in, line)) rows.push_back(cells(line));
  }
  ASSERT_EQ(rows.size(), 41u);
  struct Variant {
    const char* name;
    const char* header;  ///< with '|' between the fields, each the delimiter below
    std::string delim;
    std::vector<int> order;  ///< per field: x, y, z (0-2), or -1: an extra column (the row index)
  };
  const std::vector<Variant> variants = {
      {"upper", "X|Y|Z", ",", {0, 1, 2}},
      {"time first", "t|x|y|z", ",", {-1, 0, 1, 2}},
      {"reordered, extra last", "z|x|y|fx", ",", {2, 0, 1, -1}},
      {"quoted", "\"x\"|\"y\"|\"z\"", ",", {0, 1, 2}},
      {"semicolons, a comma in a name", "time, s|x|y|z", ";", {-1, 0, 1, 2}},
      {"tabs", "x|y|z", "\t", {0, 1, 2}},
      {"blanks", "x|y|z", "   ", {0, 1, 2}},
      {"blanks around commas", " x | y | z ", " , ", {0, 1, 2}},
  };
  const std::string plain = file("plain_t.csv");
  ASSERT_EQ(run("trace --mesh " + sphere + " --hips " + file("plain.csv", hips) + " -o " + plain).status, 0);
  int same = 0;
  for (const Variant& v : variants) {
    std::string text = v.header;
    for (size_t at; (at = text.find('|')) != std::string::npos;) text.replace(at, 1, v.delim);
    text += "\n";
    for (size_t r = 0; r < rows.size(); ++r) {
      for (size_t k = 0; k < v.order.size(); ++k)
        text += (k ? v.delim : "") + (v.order[k] < 0 ? std::to_string(r) : rows[r][v.order[k]]);
      text += "\n";
    }
    const std::string out = file("v_t.csv");
    const CliStreams r = run("trace --mesh " + sphere + " --hips " + file("v.csv", text) + " -o " + out);
    EXPECT_EQ(r.status, 0) << v.name << ": " << r.err;
    EXPECT_EQ(fileBytes(out), fileBytes(plain)) << v.name;
    same += r.status == 0 && fileBytes(out) == fileBytes(plain);
  }
  EXPECT_EQ(same, static_cast<int>(variants.size()));
  // eval --points with its columns reordered: the same values
  const std::string e1 = file("eo1.csv"), e2 = file("eo2.csv");
  ASSERT_EQ(
      run("eval " + cache() + " --points " + file("po.csv", "face,xi,eta\n0,0,0\n17,0.25,-0.4\n") + " -o " + e1).status,
      0);
  CliStreams r =
      run("eval " + cache() + " --points " + file("pr.csv", "Eta;Face;XI\n0;0;0\n-0.4;17;0.25\n") + " -o " + e2);
  EXPECT_EQ(r.status, 0) << r.err;
  EXPECT_EQ(fileBytes(e1), fileBytes(e2));
  // what is refused, naming the file, the line and the column
  const struct {
    const char* text;
    const char* message;
  } bad[] = {
      {"t,x,y\n0,1,2\n",
       "bad.csv:1: expected header 'x,y,z' (the columns in any order, others ignored), got "
       "'t,x,y': the header has no column 'z'"},
      {"x,y,z,X\n1,2,3,4\n",
       "bad.csv:1: expected header 'x,y,z' (the columns in any order, others ignored), got "
       "'x,y,z,X': the header names column 'x' twice"},
      {"t,x,y,z\n0,1,2,3\n1,2,3\n", "bad.csv:3: expected 4 columns t,x,y,z, got 3"},
      {"t;x;y;z\n0;1;2;abc\n", "bad.csv:2: z is not a finite number: 'abc'"},
  };
  for (const auto& b : bad) {
    r = run("trace --mesh " + sphere + " --hips " + file("bad.csv", b.text) + " -o " + file("bad_t.csv"));
    EXPECT_EQ(r.status, 1) << b.text;
    EXPECT_NE(r.err.find(b.message), std::string::npos) << r.err;
  }
}

TEST_F(CliContract, OpenClDeviceIsClDevice) {
  for (const char* cmd : {"cache build", "eval", "export", "trace", "sweep"}) {
    const CliStreams h = run(std::string(cmd) + " --help");
    EXPECT_NE(h.out.find("--cl-device"), std::string::npos) << cmd;
    EXPECT_EQ(h.out.find("--device"), std::string::npos) << cmd << ": the deprecated alias is hidden";
  }
  const CliStreams loop = run("loop --help");
  EXPECT_NE(loop.out.find("--device"), std::string::npos);
  EXPECT_EQ(loop.out.find("--cl-device"), std::string::npos);
  // the OpenCL evaluation on device 0 equals the CPU's text; --device still works, with a warning
  const std::string pts = file("pcl.csv", "face,xi,eta\n0,0,0\n17,0.25,-0.4\n");
  const std::string cpu = file("cpu.csv"), cl = file("cl.csv"), old = file("old.csv");
  ASSERT_EQ(run("eval " + cache() + " --points " + pts + " -o " + cpu).status, 0);
  const CliStreams r = run("eval " + cache() + " --backend opencl --cl-device 0 --points " + pts + " -o " + cl);
  if (!SF_HAS_OPENCL) {  // CPU-only build: bad input, one line naming the reason; nothing to compare
    EXPECT_EQ(r.status, 1);
    EXPECT_NE(r.err.find("built without OpenCL"), std::string::npos) << r.err;
    GTEST_SKIP() << "built without OpenCL: " << r.err;
  }
  if (r.status != 0 && r.err.find("no OpenCL device") != std::string::npos)
    GTEST_SKIP() << "no OpenCL device here: " << r.err;
  ASSERT_EQ(r.status, 0) << r.err;
  const std::vector<double> a = numbers(fileBytes(cpu)), b = numbers(fileBytes(cl));
  ASSERT_EQ(a.size(), 18u);  // 2 rows of face,xi,eta,x,y,z,nx,ny,nz
  ASSERT_EQ(b.size(), a.size());
  for (size_t i = 0; i < a.size(); ++i) EXPECT_NEAR(a[i], b[i], 1e-9) << i;
  const CliStreams d = run("eval " + cache() + " --backend opencl --device 0 --points " + pts + " -o " + old);
  EXPECT_EQ(d.status, 0) << d.err;
  EXPECT_NE(d.err.find("--device is deprecated for the OpenCL device; use --cl-device"), std::string::npos) << d.err;
  EXPECT_EQ(fileBytes(old), fileBytes(cl));
  const CliStreams none =
      run("eval " + cache() + " --backend opencl --cl-device nosuchdevice --points " + pts + " -o " + file("x.csv"));
  EXPECT_EQ(none.status, 1);
  // one line, listing the devices
  EXPECT_NE(none.err.find("OpenCL device 'nosuchdevice' not found (devices: 0: "), std::string::npos) << none.err;
  EXPECT_EQ(std::count(none.err.begin(), none.err.end(), '\n'), 1) << none.err;
}

}  // namespace
