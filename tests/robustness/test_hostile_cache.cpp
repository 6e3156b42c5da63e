// SPDX-License-Identifier: Apache-2.0
// Hostile cache files made at run time: a real small cache is written with
// the library, then damaged: a bit flipped in every header bit and in every payload array,
// every header field changed with the header checksum recomputed (so that the checks after
// the checksum are reached), structure broken with both checksums recomputed, truncations,
// newer versions, wrong counts. Each must be rejected by readPatchCache with an
// sf::InputError naming the file. Header layout: host/cache_file.cpp (128 bytes).
#include <gtest/gtest.h>

#include <cstring>
#include <fstream>
#include <limits>

#include <smoothforce/base/hash.h>
#include <smoothforce/patch/cache_file.h>
#include <smoothforce/patch/patch_eval.h>
#include "patch_test_support.h"
#include "test_hostile_support.h"

namespace sf::hostile {
namespace {

using Bytes = std::vector<char>;

struct Field {
  const char* name;
  size_t at, size;
};
// Every header field but the reserved words and the header checksum itself.
constexpr Field kFields[] = {{"version", 8, 4},          {"headerBytes", 12, 4},    {"optionsHash", 24, 8},
                             {"precision", 32, 4},       {"crossTangent", 36, 4},   {"normals", 40, 4},
                             {"keepOrientation", 44, 4}, {"recordFields", 48, 4},   {"maxSides", 52, 4},
                             {"numVertices", 56, 8},     {"numFaces", 64, 8},       {"numSlots", 72, 8},
                             {"payloadBytes", 80, 8},    {"payloadChecksum", 88, 8}};
constexpr size_t kHeader = 128, kMeshHash = 16, kPayloadSum = 88, kHeaderSum = 120;

template <class T>
T get(const Bytes& b, size_t at) {
  T v;
  std::memcpy(&v, &b[at], sizeof v);
  return v;
}
template <class T>
void set(Bytes& b, size_t at, T v) {
  std::memcpy(&b[at], &v, sizeof v);
}
/// Recomputes the header checksum, as a writer of the damaged header would.
void resign(Bytes& b) { set<uint64_t>(b, kHeaderSum, hashBytes(b.data(), kHeaderSum)); }
/// Recomputes the payload checksum, then the header checksum.
void resignAll(Bytes& b) {
  set<uint64_t>(b, kPayloadSum, hashBytes(b.data() + kHeader, b.size() - kHeader));
  resign(b);
}

/// Payload array offsets (bytes from the file start), in PatchCache order.
struct Layout {
  size_t positions, faceOffsets, faceVertices, cornerNormals, slotTwin, faceStatus, faceBulge, edgeData, end;
};
Layout layout(const PatchCache& c) {
  const size_t nv = c.numVertices(), nf = c.numFaces(), ns = c.numSlots();
  const size_t real = c.options.precision == Precision::Double ? 8 : 4;
  Layout l;
  l.positions = kHeader;
  l.faceOffsets = l.positions + nv * 24;
  l.faceVertices = l.faceOffsets + (nf + 1) * 4;
  l.cornerNormals = l.faceVertices + ns * 4;
  l.slotTwin = l.cornerNormals + ns * 24;
  l.faceStatus = l.slotTwin + ns * 4;
  l.faceBulge = l.faceStatus + nf * 4;
  l.edgeData = l.faceBulge + nf * 4;
  l.end = l.edgeData + GP_E_NFIELDS * ns * real;
  return l;
}

class HostileCache : public ::testing::TestWithParam<Precision> {
 protected:
  void SetUp() override {
    cache_ = test::cacheFromShape(ref::refUnitSphereCube(), CrossTangentMode::Corrected, GetParam());
    cache_.meshHash = 0x1234;
    path_ = (dir_.path / "cube.sfcache").string();
    writePatchCache(cache_, path_);
    std::ifstream in(path_, std::ios::binary);
    good_.assign(std::istreambuf_iterator<char>(in), {});
    ASSERT_EQ(good_.size(), layout(cache_).end);
    readPatchCache(path_);  // the undamaged file loads
  }
  /// The good file edited by edit(Bytes&), both checksums recomputed: expects it rejected with `what`.
  template <class Edit>
  void with(Edit edit, const std::string& what) {
    Bytes b = good_;
    edit(b);
    resignAll(b);
    SCOPED_TRACE(what);
    rejected(b, what);
  }
  /// Writes `b` and expects it rejected (message starting with the path, containing `what`).
  std::string rejected(const Bytes& b, const std::string& what = "", const CacheExpectation& ex = {}) {
    std::ofstream(path_, std::ios::binary | std::ios::trunc).write(b.data(), static_cast<std::streamsize>(b.size()));
    return expectRejected(
        path_, [&] { readPatchCache(path_, ex); }, what);
  }
  TempDir dir_{"sf_hostile_cache"};
  PatchCache cache_;
  std::string path_;
  Bytes good_;
};

TEST_P(HostileCache, EveryHeaderBitFlipped) {
  for (size_t bit = 0; bit < kHeader * 8; ++bit) {
    Bytes b = good_;
    b[bit / 8] ^= static_cast<char>(1 << (bit % 8));
    SCOPED_TRACE("header bit " + std::to_string(bit));
    rejected(b, bit < 64 ? "bad magic" : "checksum mismatch");
  }
}

// With a valid header checksum the structural checks after it must catch every field.
TEST_P(HostileCache, EveryHeaderFieldChangedWithValidChecksum) {
  for (const Field& f : kFields)
    for (size_t bit = 0; bit < f.size * 8; ++bit) {
      Bytes b = good_;
      b[f.at + bit / 8] ^= static_cast<char>(1 << (bit % 8));
      resign(b);
      SCOPED_TRACE(std::string(f.name) + " bit " + std::to_string(bit));
      rejected(b);
    }
  // the mesh hash is provenance, not structure: caught when the caller states what it expects
  for (size_t bit = 0; bit < 64; ++bit) {
    Bytes b = good_;
    b[kMeshHash + bit / 8] ^= static_cast<char>(1 << (bit % 8));
    resign(b);
    rejected(b, "different mesh", {cache_.meshHash, std::nullopt});
  }
}

TEST_P(HostileCache, VersionsAndHeaderSize) {
  for (uint32_t v : {kCacheFormatVersion + 1, 0xffffffffu, 0u}) {
    Bytes b = good_;
    set(b, 8, v);
    resign(b);
    rejected(b, v ? "newer SmoothForce" : "unsupported cache header");
  }
  Bytes b = good_;
  set<uint32_t>(b, 12, 64);
  resign(b);
  rejected(b, "unsupported cache header");
}

TEST_P(HostileCache, BitFlippedInEveryPayloadArray) {
  const Layout l = layout(cache_);
  const size_t starts[] = {l.positions, l.faceOffsets, l.faceVertices, l.cornerNormals, l.slotTwin, l.faceStatus,
                           l.faceBulge, l.edgeData,    l.end};
  for (int a = 0; a < 8; ++a)
    for (size_t at : {starts[a], (starts[a] + starts[a + 1]) / 2, starts[a + 1] - 1}) {
      Bytes b = good_;
      b[at] ^= 0x08;
      SCOPED_TRACE("array " + std::to_string(a) + " byte " + std::to_string(at));
      rejected(b, "payload (checksum mismatch)");
    }
}

TEST_P(HostileCache, Truncations) {
  std::vector<size_t> cuts;
  for (size_t n = 0; n <= kHeader + 16; ++n) cuts.push_back(n);
  for (size_t n = kHeader + 16; n < good_.size(); n += 97) cuts.push_back(n);
  cuts.push_back(good_.size() - 1);
  for (size_t n : cuts) {
    SCOPED_TRACE("kept " + std::to_string(n) + " bytes");
    rejected(Bytes(good_.begin(), good_.begin() + static_cast<long>(n)),
             n < 8 ? "not a SmoothForce patch cache" : "truncated");
  }
  Bytes b = good_;
  b.push_back('\0');
  rejected(b, "trailing bytes");
}

// Counts that disagree with the payload, with a valid header checksum (and payload
// checksum where the payload changes too).
TEST_P(HostileCache, WrongCountsWithValidChecksums) {
  const uint64_t nv = get<uint64_t>(good_, 56), nf = get<uint64_t>(good_, 64), ns = get<uint64_t>(good_, 72);
  const uint64_t pb = get<uint64_t>(good_, 80);
  for (uint64_t big : {uint64_t(4000000000), uint64_t(1) << 40, (uint64_t(1) << 40) + 1, ~uint64_t(0)})
    for (size_t at : {56, 64, 72, 80}) {
      Bytes b = good_;
      set(b, at, big);
      resign(b);
      rejected(b, "corrupted cache header");
    }
  Bytes b = good_;  // one more vertex: counts and size agree, the file is short
  set(b, 56, nv + 1);
  set(b, 80, pb + 24);
  resign(b);
  rejected(b, "truncated");
  // one more face, payload grown to match and re-checksummed: the arrays shift
  b = good_;
  set(b, 64, nf + 1);
  set(b, 80, pb + 12);
  b.resize(b.size() + 12, '\0');
  resignAll(b);
  rejected(b);
  // one slot fewer, payload shrunk to match
  const size_t real = GetParam() == Precision::Double ? 8 : 4;
  b = good_;
  set(b, 72, ns - 1);
  set(b, 80, pb - 36 - GP_E_NFIELDS * real);
  b.resize(b.size() - 36 - GP_E_NFIELDS * real);
  resignAll(b);
  rejected(b);
}

// Both checksums valid: the structure checks after them must hold.
TEST_P(HostileCache, BrokenStructureWithValidChecksums) {
  const Layout l = layout(cache_);
  const int nf = cache_.numFaces(), ns = cache_.numSlots(), nv = cache_.numVertices();
  with([&](Bytes& b) { set<int32_t>(b, l.faceOffsets, 1); }, "inconsistent face offsets");
  with([&](Bytes& b) { set<int32_t>(b, l.faceOffsets + 4 * nf, ns - 1); }, "inconsistent face offsets");
  with([&](Bytes& b) { set<int32_t>(b, l.faceOffsets + 4, 2); }, "fewer than 3 corners");
  with([&](Bytes& b) { set<int32_t>(b, l.faceOffsets + 4, -5); }, "fewer than 3 corners");
  with([&](Bytes& b) { set<int32_t>(b, l.faceOffsets + 4, std::numeric_limits<int32_t>::min()); },
       "fewer than 3 corners");
  for (int32_t v : {-1, nv, std::numeric_limits<int32_t>::max(), std::numeric_limits<int32_t>::min()}) {
    with([&](Bytes& b) { set<int32_t>(b, l.faceVertices + 4 * (ns - 1), v); }, "out of range");
  }
  for (int32_t t : {-3, ns, std::numeric_limits<int32_t>::max(), std::numeric_limits<int32_t>::min()}) {
    with([&](Bytes& b) { set<int32_t>(b, l.slotTwin + 4 * 5, t); }, "out-of-range neighbour");
  }
  // records that contradict each other: every slot's neighbour made the slot itself, or made to
  // name another slot back; every face's status word given a bit the construction cannot give
  int contradictions = 0;
  for (int s = 0; s < ns; ++s) {
    const int32_t twin = cache_.slotTwin[s];
    if (twin < 0) continue;
    with([&](Bytes& b) { set<int32_t>(b, l.slotTwin + 4 * s, s); }, "do not name each other across two faces");
    with([&](Bytes& b) { set<int32_t>(b, l.slotTwin + 4 * twin, (s + 1) % ns); },
         "do not name each other across two faces");
    contradictions += 2;
  }
  for (int f = 0; f < nf; ++f) {
    for (const uint32_t bad : {0xFFFFFFFFu, uint32_t(GP_ST_OUTSIDE), uint32_t(GP_ST_TOO_MANY_SIDES), 0x400u})
      with([&](Bytes& b) { set<uint32_t>(b, l.faceStatus + 4 * f, bad); }, "status word the construction cannot give");
    contradictions += 4;
  }
  EXPECT_EQ(contradictions, 2 * ns + 4 * nf);  // the cube: every slot has a neighbour
}

// Records that contradict the mesh they claim to be built from, behind valid checksums: every
// neighbour pair made boundary (-1) or non-manifold (-2) on the closed cube, every vertex moved by
// 1e-3 of its size, every corner normal tilted. Each opened the surface or moved it silently
// before (the patches stayed where they were built; the polygons, god-object and bounds moved).
TEST_P(HostileCache, RecordsThatContradictTheirMesh) {
  const Layout l = layout(cache_);
  const int ns = cache_.numSlots(), nv = cache_.numVertices();
  int forged = 0;
  for (int s = 0; s < ns; ++s) {
    const int32_t twin = cache_.slotTwin[s];
    if (twin < s) continue;  // each pair once (the cube: every slot has one)
    for (const int32_t open : {-1, -2}) {
      with(
          [&](Bytes& b) {
            set<int32_t>(b, l.slotTwin + 4 * s, open);
            set<int32_t>(b, l.slotTwin + 4 * twin, open);
          },
          "the neighbours do not match the faces");
      ++forged;
    }
  }
  for (int v = 0; v < nv; ++v) {
    const double x = cache_.positions[3 * v];
    with([&](Bytes& b) { set<double>(b, l.positions + 24 * v, x + 1e-3); }, "does not start at vertex " + std::to_string(v));
    ++forged;
  }
  for (int c = 0; c < ns; ++c) {
    const double nz = cache_.cornerNormals[3 * c + 2];
    with([&](Bytes& b) { set<double>(b, l.cornerNormals + 24 * c + 16, nz * 0.99); },
         "does not carry corner normal " + std::to_string(c));
    ++forged;
  }
  EXPECT_EQ(forged, ns + nv + ns);  // ns / 2 pairs x 2 kinds, every vertex, every corner
}

// Offsets {0, INT32_MAX, INT32_MIN + 5, ...}: face 1's size (INT32_MIN + 5) - INT32_MAX
// overflows int32 in readPatchCache's "fewer than 3 corners" check (host/cache_file.cpp) -
// undefined behaviour that the sanitizer build (SF_SANITIZE=undefined) reports. The file is
// still rejected (at face 2) in a normal build.
TEST_P(HostileCache, FaceOffsetsThatOverflowTheSizeCheck) {
  const Layout l = layout(cache_);
  Bytes b = good_;
  set<int32_t>(b, l.faceOffsets + 4, std::numeric_limits<int32_t>::max());
  set<int32_t>(b, l.faceOffsets + 8, std::numeric_limits<int32_t>::min() + 5);
  resignAll(b);
  rejected(b, "fewer than 3 corners");
}

// Non-finite numbers behind valid checksums are rejected, not passed on to evaluation.
TEST_P(HostileCache, NonFiniteRecordsWithValidChecksums) {
  const Layout l = layout(cache_);
  for (size_t at : {l.positions, l.cornerNormals, l.edgeData}) {
    Bytes b = good_;
    if (at == l.edgeData && GetParam() == Precision::Float)
      set(b, at, std::numeric_limits<float>::quiet_NaN());
    else
      set(b, at, std::numeric_limits<double>::quiet_NaN());
    resignAll(b);
    rejected(b, "non-finite");
  }
}

INSTANTIATE_TEST_SUITE_P(Hostile, HostileCache, ::testing::Values(Precision::Double, Precision::Float),
                         [](const auto& i) { return std::string(toString(i.param)); });

}  // namespace
}  // namespace sf::hostile
