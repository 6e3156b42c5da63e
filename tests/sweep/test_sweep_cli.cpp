// SPDX-License-Identifier: Apache-2.0
// End-to-end: `smoothforce generate`, `sweep` (sharded and whole) and `sweep-merge`.
#include <gtest/gtest.h>

#include <sys/wait.h>
#include <unistd.h>
#include <cstddef>
#include <cstring>

#include <array>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <regex>

#include <smoothforce/base/status.h>
#include <smoothforce/sweep/sweep.h>
#include "cli_test_support.h"
#include "file_bytes.h"

namespace {

namespace fs = std::filesystem;

using sf::test::CliResult;
CliResult run(const std::string& args) { return sf::test::smoothforce(args); }


class SweepCli : public ::testing::Test {
 protected:
  void SetUp() override {
    const CliResult sweep = run("sweep --help"), gen = run("generate --help");
    ASSERT_TRUE(sweep.status == 0 && sweep.out.find("--depth") != std::string::npos)
        << "`smoothforce sweep` is not registered: " << sweep.out;
    ASSERT_TRUE(gen.status == 0 && gen.out.find("torus-knot") != std::string::npos)
        << "`smoothforce generate` is not registered: " << gen.out;
    dir = fs::temp_directory_path() / ("sf_sweep_cli_" + std::to_string(::getpid()));
    fs::create_directories(dir);
  }
  void TearDown() override {
    if (!dir.empty()) fs::remove_all(dir);
  }
  std::string p(const std::string& name) const { return (dir / name).string(); }
  fs::path dir;
};

TEST_F(SweepCli, GenerateKnotSphereTorus) {
  CliResult r = run("generate torus-knot --size 0.1 --trajectory-out " + p("helix.csv") + " -o " + p("knot.obj"));
  ASSERT_EQ(r.status, 0) << r.out;
  EXPECT_NE(r.out.find("1440 quads"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("--analytic torus-knot:2,3,1,0.4,0.15,"), std::string::npos) << r.out;
  EXPECT_TRUE(fs::exists(p("helix.csv")));
  r = run("generate sphere --radius 0.05 --segments 2 -o " + p("s.obj"));
  ASSERT_EQ(r.status, 0) << r.out;
  EXPECT_NE(r.out.find("24 quads, 26 vertices"), std::string::npos) << r.out;
  r = run("generate torus --R 1 --r 0.3 --segments 8 --sides 6 -o " + p("t.obj"));
  ASSERT_EQ(r.status, 0) << r.out;
  EXPECT_NE(r.out.find("48 quads"), std::string::npos) << r.out;
  r = run("generate torus --R 1 --r 2 -o " + p("bad.obj"));
  EXPECT_NE(r.status, 0);
  EXPECT_NE(r.out.find("0 < r < R"), std::string::npos) << r.out;
}

// With --mesh and HIPs sampled on a reference that covers a small cap of a 1,536-quad sphere,
// only the patches the probes touch are built, and the results equal a prebuilt cache's (byte
// for byte with the polygon start; the same contacts and SCPs with the default surface query).
TEST_F(SweepCli, MeshWithReferenceBuildsOnlyTouchedPatches) {
  ASSERT_EQ(run("generate sphere --segments 16 -o " + p("s.obj")).status, 0);
  std::ofstream(p("cap.obj")) << "v 0.2 0.2 0.98\nv -0.2 0.2 0.98\nv 0 -0.25 0.98\nf 1 2 3\n";
  ASSERT_EQ(run("cache build " + p("s.obj") + " --normals file -o " + p("s.sfcache")).status, 0);
  // with the polygon start, a skeleton and a prebuilt cache run the same global query: byte-identical
  const std::string common =
      " --sample-on reference --reference " + p("cap.obj") +
      " --depth 0.05 --samples 3000 --methods patch,direct --initial-guess polygon --no-plots -o ";
  CliResult lazy = run("sweep --mesh " + p("s.obj") + " --normals file" + common + p("lazy"));
  ASSERT_EQ(lazy.status, 0) << lazy.out;
  std::smatch m;
  ASSERT_TRUE(std::regex_search(lazy.out, m, std::regex(R"(patch +([0-9]+) patch constructions)"))) << lazy.out;
  EXPECT_GT(std::stoi(m[1]), 0);
  EXPECT_LT(std::stoi(m[1]), 200) << "the cap touches a few dozen of the 1,536 faces per worker";
  ASSERT_EQ(run("sweep --cache " + p("s.sfcache") + common + p("full")).status, 0);
  for (const char* f : {"results_direct.bin", "hips.bin"})
    EXPECT_EQ(sf::test::fileBytes(dir / "lazy" / f), sf::test::fileBytes(dir / "full" / f)) << f;
  // the patch records too, but for the sweep's inside test: it needs every patch built, so a
  // lazy sweep says UNDECIDED for the patch method (SF_PROBE_* bits of the status, offset 32)
  std::string lazyPatch = sf::test::fileBytes(dir / "lazy" / "results_patch.bin"),
              fullPatch = sf::test::fileBytes(dir / "full" / "results_patch.bin");
  ASSERT_EQ(lazyPatch.size(), fullPatch.size());
  ASSERT_EQ((lazyPatch.size() - 32) % sizeof(sf::HipResult), 0u);
  size_t records = 0, decided = 0;
  for (size_t off = 32; off < lazyPatch.size(); off += sizeof(sf::HipResult), ++records) {
    uint32_t a, b;
    std::memcpy(&a, lazyPatch.data() + off + offsetof(sf::HipResult, status), 4);
    std::memcpy(&b, fullPatch.data() + off + offsetof(sf::HipResult, status), 4);
    EXPECT_EQ(a & sf::SF_PROBE_MASK, sf::SF_PROBE_UNDECIDED);
    decided += (b & sf::SF_PROBE_UNDECIDED) == 0;
    a &= ~sf::SF_PROBE_MASK;
    b &= ~sf::SF_PROBE_MASK;
    std::memcpy(lazyPatch.data() + off + offsetof(sf::HipResult, status), &a, 4);
    std::memcpy(fullPatch.data() + off + offsetof(sf::HipResult, status), &b, 4);
  }
  EXPECT_EQ(records, 3000u);
  EXPECT_GE(decided, records * 19 / 20);
  EXPECT_EQ(lazyPatch, fullPatch) << "results_patch.bin without the inside test's bits";
  // the default global query (the patch surface; on a skeleton over patch boxes,
  // lazy_surface.h): the same contacts, SCPs within float rounding of the prebuilt cache's
  const std::string surface = " --sample-on reference --reference " + p("cap.obj") +
                              " --depth 0.05 --samples 3000 --methods patch --no-plots -o ";
  CliResult lazySurface = run("sweep --mesh " + p("s.obj") + " --normals file" + surface + p("lazy-s"));
  ASSERT_EQ(lazySurface.status, 0) << lazySurface.out;
  ASSERT_TRUE(std::regex_search(lazySurface.out, m, std::regex(R"(patch +([0-9]+) patch constructions)")))
      << lazySurface.out;
  EXPECT_LT(std::stoi(m[1]), 200) << "the cap touches a few dozen of the 1,536 faces per worker";
  ASSERT_EQ(run("sweep --cache " + p("s.sfcache") + surface + p("full-s")).status, 0);
  lazyPatch = sf::test::fileBytes(dir / "lazy-s" / "results_patch.bin");
  fullPatch = sf::test::fileBytes(dir / "full-s" / "results_patch.bin");
  ASSERT_EQ(lazyPatch.size(), fullPatch.size());
  size_t contacts = 0;
  double worst = 0;
  for (size_t off = 32; off < lazyPatch.size(); off += sizeof(sf::HipResult)) {
    sf::HipResult a, b;
    std::memcpy(&a, lazyPatch.data() + off, sizeof a);
    std::memcpy(&b, fullPatch.data() + off, sizeof b);
    ASSERT_EQ(a.contact, b.contact) << "record " << (off - 32) / sizeof a;
    contacts += a.contact;
    if (a.contact)
      for (int d = 0; d < 3; ++d) worst = std::max(worst, double(std::abs(a.scp[d] - b.scp[d])));
  }
  EXPECT_EQ(contacts, 3000u);
  EXPECT_LE(worst, 1e-6) << "m, on a unit sphere";
  // a trajectory needs the whole patch surface: then every patch is built
  std::ofstream(p("path.csv")) << "x,y,z\n0,0,1\n0.3,0,0.95\n";
  CliResult all = run("sweep --mesh " + p("s.obj") + " --normals file --trajectory " + p("path.csv") + common + p("t"));
  ASSERT_EQ(all.status, 0) << all.out;
  EXPECT_NE(all.out.find("built all 1536 patches"), std::string::npos) << all.out;
  EXPECT_EQ(all.out.find("patch constructions"), std::string::npos) << all.out;
}

// A sweep that builds or loads every patch names its folded and bulging patches on stderr before
// it probes, as `cache build` reports them (the same counts and face lists), and says nothing of
// either where there are none. Meshes, under the design page's construction (--fold-repair off):
// one fold (pmp/L.off's reflex corner), 16 folds (the spot cage), folds and bulges (the scanned
// bunny at res4), neither (a generated sphere); a sweep without the patch method does not.
TEST_F(SweepCli, NamesFoldedAndBulgingPatchesAsCacheBuildDoes) {
  ASSERT_EQ(run("generate sphere --radius 0.05 --segments 4 -o " + p("s.obj")).status, 0);
  const std::regex folds(R"(folds (\d+), bulges > 0.5 (\d+))"), list(R"(  (fold|bulge) faces:([ \d.]*)\n)");
  int meshes = 0, withFolds = 0, withBulges = 0;
  for (const std::string& mesh :
       {std::string(SF_SHARED_MESHES) + "/pmp/L.off", std::string(SF_DATA_DIR) + "/spot_control_mesh.obj",
        std::string(SF_SHARED_MESHES) + "/stanford/bun_zipper_res4.ply", p("s.obj")}) {
    SCOPED_TRACE(mesh);
    const CliResult build = run("cache build " + mesh + " --fold-repair off -o " + p("c.sfcache"));
    ASSERT_EQ(build.status, 0) << build.out;
    std::smatch m;
    ASSERT_TRUE(std::regex_search(build.out, m, folds)) << build.out;
    const int nFold = std::stoi(m[1]), nBulge = std::stoi(m[2]);
    std::string foldIds, bulgeIds;
    for (auto it = std::sregex_iterator(build.out.begin(), build.out.end(), list); it != std::sregex_iterator(); ++it)
      ((*it)[1] == "fold" ? foldIds : bulgeIds) = (*it)[2];
    const CliResult sweep =
        run("sweep --cache " + p("c.sfcache") + " --depth 0.5% --samples 50 --methods patch --no-plots -o " + p("out"));
    ASSERT_EQ(sweep.status, 0) << sweep.out;
    const std::string foldLine = "sweep: " + std::to_string(nFold) + " folded patches",
                      bulgeLine = "sweep: " + std::to_string(nBulge) + " bulging patches";
    if (nFold > 0) {
      EXPECT_NE(sweep.out.find(foldLine), std::string::npos) << sweep.out;
      EXPECT_NE(sweep.out.find("faces:" + foldIds + "\n"), std::string::npos) << sweep.out;
    } else {
      EXPECT_EQ(sweep.out.find("folded patches"), std::string::npos) << sweep.out;
    }
    if (nBulge > 0) {
      EXPECT_NE(sweep.out.find(bulgeLine), std::string::npos) << sweep.out;
      EXPECT_NE(sweep.out.find("faces:" + bulgeIds + "\n"), std::string::npos) << sweep.out;
    } else {
      EXPECT_EQ(sweep.out.find("bulging patches"), std::string::npos) << sweep.out;
    }
    ++meshes, withFolds += nFold > 0, withBulges += nBulge > 0;
  }
  EXPECT_EQ(meshes, 4);
  EXPECT_EQ(withFolds, 3);
  EXPECT_EQ(withBulges, 1);
  // without the patch method in the sweep, its patches' folds are not its concern
  const CliResult direct = run("sweep --mesh " + std::string(SF_SHARED_MESHES) +
                               "/pmp/L.off --depth 0.5% --samples 50 --methods direct --no-plots -o " + p("direct"));
  ASSERT_EQ(direct.status, 0) << direct.out;
  EXPECT_EQ(direct.out.find("folded patches"), std::string::npos) << direct.out;
}

TEST_F(SweepCli, ShardsMergeByteIdentical) {
  ASSERT_EQ(run("generate sphere --radius 0.05 --segments 3 -o " + p("s.obj")).status, 0);
  const std::string common = "sweep --mesh " + p("s.obj") +
                             " --normals file --depth 2%,4% --samples 1500 --methods patch,direct "
                             "--analytic sphere:0.05 --no-plots";
  CliResult r = run(common + " -o " + p("whole"));
  ASSERT_EQ(r.status, 0) << r.out;
  EXPECT_NE(r.out.find("patch    2%"), std::string::npos) << r.out;
  const std::string shards[3] = {p("s0"), p("s1"), p("s2")};
  for (int i = 0; i < 3; ++i) {
    r = run(common + " --shard " + std::to_string(i) + "/3 -o " + shards[i]);
    ASSERT_EQ(r.status, 0) << r.out;
  }
  const std::string dirs = shards[2] + " " + shards[0] + " " + shards[1];  // any order
  r = run("sweep-merge " + dirs + " --no-plots -o " + p("merged"));
  ASSERT_EQ(r.status, 0) << r.out;
  for (const char* f : {"summary.json", "results_patch.bin", "results_direct.bin", "hips.bin", "trajectories.json"})
    EXPECT_EQ(sf::test::fileBytes(dir / "whole" / f), sf::test::fileBytes(dir / "merged" / f)) << f;
  EXPECT_TRUE(fs::exists(dir / "merged" / "index.html"));
  EXPECT_TRUE(fs::exists(dir / "merged" / "patch_2pct.ply"));
  r = run("sweep-merge " + p("s0") + " " + p("s2") + " -o " + p("gap"));
  EXPECT_NE(r.status, 0);
  EXPECT_NE(r.out.find("missing"), std::string::npos) << r.out;
}

// A HIP or trajectory file whose points nearly all lie far from the mesh (millimetres for a
// mesh in metres) is noted on stderr: it gave 0 contacts, or a projected trajectory, silently.
TEST_F(SweepCli, FilesInAnotherUnitAreNoted) {
  ASSERT_EQ(run("generate sphere --radius 0.05 --segments 2 -o " + p("s.obj")).status, 0);
  std::ofstream(p("m.csv")) << "x,y,z\n0,0,0.049\n0.01,0,0.048\n0.02,0,0.045\n";
  std::ofstream(p("mm.csv")) << "x,y,z\n0,0,49\n10,0,48\n20,0,45\n";
  const std::string sweep = "sweep --mesh " + p("s.obj") + " --normals file --methods direct --no-plots ";
  struct Case {
    std::string args, note;  ///< note "": none
  };
  const Case cases[] = {
      {"--hips " + p("mm.csv"), "3 of 3 HIPs of " + p("mm.csv") + " lie farther from the mesh's bounding box"},
      {"--depth 2% --samples 20 --trajectory " + p("mm.csv"), "3 of 3 points of --trajectory " + p("mm.csv")},
      {"--hips " + p("m.csv"), ""},
      {"--depth 2% --samples 20 --trajectory " + p("m.csv"), ""},
  };
  int noted = 0;
  for (const Case& c : cases) {
    const CliResult r = run(sweep + c.args + " -o " + p("o"));
    ASSERT_EQ(r.status, 0) << c.args << "\n" << r.out;
    const size_t at = r.out.find("sweep: note: ");
    if (c.note.empty()) {
      EXPECT_EQ(at, std::string::npos) << c.args << "\n" << r.out;
    } else {
      EXPECT_NE(r.out.find(c.note), std::string::npos) << c.args << "\n" << r.out;
      EXPECT_NE(r.out.find("(mm for m)?"), std::string::npos) << r.out;
      noted += at != std::string::npos;
    }
  }
  EXPECT_EQ(noted, 2);
}

TEST_F(SweepCli, BadInputIsOneLine) {
  ASSERT_EQ(run("generate sphere --segments 2 -o " + p("s.obj")).status, 0);
  for (const std::string& args :
       {std::string("--depth 2% --shard 3/3"), std::string("--depth 2%x"),
        std::string("--depth 2% --methods patch,nope"), std::string("--depth 2% --analytic cube:1"), std::string(""),
        std::string("--depth 2% --backend opencl --surface-index bounds")}) {
    const CliResult r = run("sweep --mesh " + p("s.obj") + " --samples 10 " + args + " -o " + p("o"));
    EXPECT_NE(r.status, 0) << args;
    EXPECT_NE(r.out.find("smoothforce: "), std::string::npos) << args << "\n" << r.out;
  }
}

}  // namespace
