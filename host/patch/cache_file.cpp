// SPDX-License-Identifier: Apache-2.0
#include <smoothforce/patch/cache_file.h>

#include <unistd.h>

#include <bit>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <type_traits>
#include <vector>

#include <smoothforce/base/coordinate_range.h>
#include <smoothforce/base/hash.h>
#include <smoothforce/base/staged_output.h>
#include <smoothforce/mesh/mesh.h>
#include <smoothforce/mesh/topology.h>
#include <smoothforce/patch/patch_build.h>
#include "gp_config.h"  // GP_* status bits and record layout

namespace sf {

static_assert(std::endian::native == std::endian::little, "cache files are little-endian");

namespace {

constexpr char kMagic[8] = {'S', 'F', 'P', 'A', 'T', 'C', 'H', '\0'};

struct Header {  // 128 bytes on disk
  char magic[8];
  uint32_t version, headerBytes;
  uint64_t meshHash, optionsHash;
  uint32_t precision, crossTangent, normals, keepOrientation;
  uint32_t recordFields, maxSides;
  uint64_t numVertices, numFaces, numSlots;
  uint64_t payloadBytes, payloadChecksum;
  uint64_t creaseAngleBits;  // CreaseOptions::angleDeg as IEEE double bits (0: off)
  uint64_t creaseMarks;      // bit 0: tags off, bit 1: smoothing groups off, bit 2: normals on (0: default)
  uint64_t sections;  // format 3: bit 0 certificates, bit 1 face sources (fold repair on); format 4 adds
                      // bit 2, the computed normals (fold repair search turned some); else 0
  uint64_t headerChecksum;  // XXH64 of the bytes before this field
};
static_assert(sizeof(Header) == 128);

/// Payload size for the given counts and format version (2 adds the certificates; 3 and 4 add
/// what their sections say: certificates, face sources, computed normals); false on overflow.
bool payloadSize(uint64_t nv, uint64_t nf, uint64_t ns, Precision p, uint32_t version, uint64_t sections,
                 uint64_t* out) {
  const uint64_t lim = uint64_t(1) << 40;  // no count of a real mesh comes near this
  if (nv > lim || nf > lim || ns > lim) return false;
  const uint64_t real = p == Precision::Double ? 8 : 4;
  const bool certificates = version == 2 || (version >= 3 && (sections & 1u));
  const bool sources = version >= 3 && (sections & 2u);
  const bool computed = version >= 4 && (sections & 4u);
  *out = nv * 3 * 8 + (nf + 1) * 4 + ns * 4 + ns * 3 * 8 + ns * 4 + nf * 4 + nf * 4 + (certificates ? nf * 4 : 0) +
         (sources ? nf * 4 : 0) + (computed ? ns * 3 * 8 : 0) + uint64_t(GP_E_NFIELDS) * ns * real;
  return true;
}

template <class T>
void put(std::vector<char>& buf, const std::vector<T>& v) {
  if (v.empty()) return;
  const char* p = reinterpret_cast<const char*>(v.data());
  buf.insert(buf.end(), p, p + v.size() * sizeof(T));
}

template <class T>
void take(const char*& p, std::vector<T>& v, uint64_t count) {
  v.resize(count);
  if (count == 0) return;  // v.data() may be null: memcpy must not see it
  std::memcpy(v.data(), p, count * sizeof(T));
  p += count * sizeof(T);
}

/// A double's exact text (%a), so that the options hash tells every angle apart.
std::string hexDouble(double x) {
  char buf[64];
  std::snprintf(buf, sizeof buf, "%a", x);
  return buf;
}

/// The fold repair search's name in the options hash. Its patches use untangled vertex fans;
/// caches named "search" were built from the construction's own fans, and are refused.
constexpr const char* kSearchName = "search;fans=untangled";

/// The fold repair's name as the options hash reads it: `name` where given, else the mode's.
std::string foldRepairText(const PatchOptions& o, const char* name) {
  if (name) return name;
  return o.foldRepair == FoldRepairMode::Search ? kSearchName : toString(o.foldRepair);
}

/// The options as the cache's hash reads them. foldRepairName overrides the fold repair's name:
/// version 0.5 named the repair "split", and its caches keep that name in their hash.
std::string optionsText(const PatchOptions& o, const char* foldRepairName = nullptr) {
  return std::string("precision=") + toString(o.precision) + ";cross-tangent=" + toString(o.crossTangent) +
         ";normals=" + toString(o.normals) + ";orient=" + (o.keepOrientation ? "keep" : "outward") +
         ";fields=" + std::to_string(GP_E_NFIELDS) +
         // named only when not none, so that the hash of every cache built without a cage stays as it was
         (o.cage == CageMode::None ? std::string() : std::string(";cage=") + toString(o.cage)) +
         // the same for the crease options: named only when not the default
         (o.creases.tags && o.creases.groups && !o.creases.normals ? std::string() : ";creases=" + creaseMarksText(o.creases)) +
         (o.creases.angleDeg == 0 ? std::string() : ";crease-angle=" + hexDouble(o.creases.angleDeg)) +
         (o.foldRepair == FoldRepairMode::Off ? std::string()
                                               : std::string(";fold-repair=") + foldRepairText(o, foldRepairName));
}

}  // namespace

bool isPatchCacheFile(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  char m[8] = {};
  in.read(m, 8);
  return in.gcount() == 8 && std::memcmp(m, kMagic, 8) == 0;
}

uint64_t hashPatchOptions(const PatchOptions& options) {
  const std::string s = optionsText(options);
  return hashBytes(s.data(), s.size());
}

uint32_t cacheFormatVersion(const PatchCache& c) {
  if (c.options.foldRepair != FoldRepairMode::Off) return c.computedNormals.empty() ? 3 : 4;
  return !c.faceCertificate.empty() && c.faceCertificate.size() == c.faceStatus.size() ? 2 : 1;
}

void writePatchCache(const PatchCache& c, const std::string& path) {
  std::vector<char> payload;
  payload.reserve(c.bytes());
  put(payload, c.positions);
  put(payload, c.faceOffsets);
  put(payload, c.faceVertices);
  put(payload, c.cornerNormals);
  put(payload, c.slotTwin);
  put(payload, c.faceStatus);
  put(payload, c.faceBulge);
  // format 2 carries the certificates, format 3 the face sources of a split (and the
  // certificates where there are some); a cache without either is written as format 1
  const bool certified = !c.faceCertificate.empty() && c.faceCertificate.size() == c.faceStatus.size();
  const bool sourced = c.options.foldRepair != FoldRepairMode::Off;
  if (sourced && c.faceSource.size() != c.faceStatus.size())
    throw std::invalid_argument("writePatchCache: a fold-repaired cache needs one source face per face");
  const bool turned = !c.computedNormals.empty();
  if (turned && (c.options.foldRepair != FoldRepairMode::Search || c.computedNormals.size() != c.cornerNormals.size()))
    throw std::invalid_argument("writePatchCache: computed normals need fold repair search and one normal per corner");
  if (certified) put(payload, c.faceCertificate);
  if (sourced) put(payload, c.faceSource);
  if (turned) put(payload, c.computedNormals);
  if (c.options.precision == Precision::Double)
    put(payload, c.edgeDataD);
  else
    put(payload, c.edgeDataF);
  Header h{};
  std::memcpy(h.magic, kMagic, 8);
  h.version = cacheFormatVersion(c);
  h.sections = sourced ? (certified ? 1u : 0u) | 2u | (turned ? 4u : 0u) : 0u;
  h.headerBytes = sizeof(Header);
  h.meshHash = c.meshHash;
  h.optionsHash = hashPatchOptions(c.options);
  h.precision = static_cast<uint32_t>(c.options.precision);
  h.crossTangent = static_cast<uint32_t>(c.options.crossTangent);
  h.normals = static_cast<uint32_t>(c.options.normals);
  h.keepOrientation = c.options.keepOrientation ? 1 : 0;
  std::memcpy(&h.creaseAngleBits, &c.options.creases.angleDeg, sizeof(double));
  h.creaseMarks = (c.options.creases.tags ? 0u : 1u) | (c.options.creases.groups ? 0u : 2u) |
                  (c.options.creases.normals ? 4u : 0u);
  h.recordFields = GP_E_NFIELDS;
  h.maxSides = GP_MAX_N;
  h.numVertices = c.numVertices();
  h.numFaces = c.numFaces();
  h.numSlots = c.numSlots();
  h.payloadBytes = payload.size();
  h.payloadChecksum = hashBytes(payload.data(), payload.size());
  h.headerChecksum = hashBytes(&h, offsetof(Header, headerChecksum));

  const std::string tmp = stagingPath(path);
  {
    std::ofstream out(tmp, std::ios::binary | std::ios::trunc);
    if (!out) throw InputError(path + ": cannot write (temporary file " + tmp + ")");
    out.write(reinterpret_cast<const char*>(&h), sizeof h);
    out.write(payload.data(), static_cast<std::streamsize>(payload.size()));
    out.flush();
    if (!out) {
      discardStaging(tmp, path);
      throw InputError(path + ": write failed (disk full?)");
    }
  }
  std::error_code ec;
  if (tmp != path) std::filesystem::rename(tmp, path, ec);
  if (ec) {
    discardStaging(tmp, path);
    throw InputError(path + ": cannot rename temporary file into place: " + ec.message());
  }
}

PatchCache readPatchCache(const std::string& path, const CacheExpectation& expect) {
  auto fail = [&](const std::string& what) -> InputError { return InputError(path + ": " + what); };
  std::ifstream in(path, std::ios::binary | std::ios::ate);
  if (!in) throw fail("cannot open cache file");
  const uint64_t fileSize = static_cast<uint64_t>(in.tellg());
  in.seekg(0);
  Header h{};
  if (fileSize < sizeof(Header)) {
    in.read(reinterpret_cast<char*>(&h), static_cast<std::streamsize>(fileSize));
    if (fileSize >= 8 && std::memcmp(h.magic, kMagic, 8) == 0)
      throw fail("truncated cache file: " + std::to_string(fileSize) + " bytes, shorter than its header");
    throw fail("not a SmoothForce patch cache (too short, no SFPATCH header)");
  }
  in.read(reinterpret_cast<char*>(&h), sizeof h);
  if (std::memcmp(h.magic, kMagic, 8) != 0) throw fail("not a SmoothForce patch cache (bad magic)");
  if (h.headerChecksum != hashBytes(&h, offsetof(Header, headerChecksum)))
    throw fail("corrupted cache header (checksum mismatch)");
  if (h.version > kCacheFormatVersion)
    throw fail("written by a newer SmoothForce (cache format " + std::to_string(h.version) +
               "); this build reads formats up to " + std::to_string(kCacheFormatVersion) + ": rebuild the cache");
  if (h.version == 0 || h.headerBytes != sizeof(Header)) throw fail("unsupported cache header");
  if (h.recordFields != GP_E_NFIELDS || h.maxSides != GP_MAX_N)
    throw fail("cache record layout differs from this build's; rebuild the cache");
  if (h.precision > 1 || h.crossTangent > 2 || h.normals > 3 || h.keepOrientation > 1)
    throw fail("corrupted cache header (option codes out of range)");
  PatchOptions opt;
  opt.precision = static_cast<Precision>(h.precision);
  opt.crossTangent = static_cast<CrossTangentMode>(h.crossTangent);
  opt.normals = static_cast<NormalMode>(h.normals);
  opt.keepOrientation = h.keepOrientation != 0;
  if (h.creaseMarks > 7) throw fail("corrupted cache header (crease option codes out of range)");
  opt.creases.tags = !(h.creaseMarks & 1u);
  opt.creases.groups = !(h.creaseMarks & 2u);
  opt.creases.normals = (h.creaseMarks & 4u) != 0;
  std::memcpy(&opt.creases.angleDeg, &h.creaseAngleBits, sizeof(double));
  // format 4 is format 3 with the computed normals, and only with them
  if ((h.version < 3 && h.sections != 0) || h.sections > 7 || (h.version >= 3 && !(h.sections & 2u)) ||
      (h.version == 4) != bool(h.sections & 4u))
    throw fail("corrupted cache header (section bits out of range)");
  opt.foldRepair = (h.sections & 2u) ? FoldRepairMode::On : FoldRepairMode::Off;
  if (!(opt.creases.angleDeg >= 0 && opt.creases.angleDeg < 180))
    throw fail("corrupted cache header (crease angle out of range)");
  // the cage has no header field: the options hash says which one the cache was built with (and
  // a fold-repaired cache of version 0.5 names its repair "split" there)
  auto hashed = [&](const PatchOptions& o) {
    if (h.optionsHash == hashPatchOptions(o)) return true;
    if (o.foldRepair == FoldRepairMode::Off) return false;
    const std::string legacy = optionsText(o, "split");
    return h.optionsHash == hashBytes(legacy.data(), legacy.size());
  };
  // nor has the fold repair's normal search (its caches set the split's bit too)
  auto hashedSearch = [&](PatchOptions& o) {
    if (hashed(o)) return true;
    if (o.foldRepair == FoldRepairMode::Off) return false;
    o.foldRepair = FoldRepairMode::Search;
    if (hashed(o)) return true;
    if (const std::string before = optionsText(o, "search"); h.optionsHash == hashBytes(before.data(), before.size()))
      throw fail("built by an older SmoothForce whose fold repair search kept the construction's tangled vertex fans: "
                 "rebuild the cache");
    o.foldRepair = FoldRepairMode::On;
    return false;
  };
  if (!hashedSearch(opt)) {
    opt.cage = CageMode::CatmullClark;
    if (!hashedSearch(opt)) throw fail("corrupted cache header (options hash)");
  }
  if ((h.sections & 4u) && opt.foldRepair != FoldRepairMode::Search)
    throw fail("corrupted cache header (computed normals without the fold repair's normal search)");
  uint64_t expected = 0;
  if (!payloadSize(h.numVertices, h.numFaces, h.numSlots, opt.precision, h.version, h.sections, &expected) ||
      expected != h.payloadBytes)
    throw fail("corrupted cache header (counts do not match the payload size)");
  if (fileSize - sizeof(Header) < h.payloadBytes)
    throw fail("truncated cache file: payload has " + std::to_string(fileSize - sizeof(Header)) + " of " +
               std::to_string(h.payloadBytes) + " bytes");
  if (fileSize - sizeof(Header) > h.payloadBytes) throw fail("trailing bytes after the cache payload");
  if (expect.meshHash && *expect.meshHash != h.meshHash)
    throw fail("cache was built from a different mesh (mesh hash " + hexHash(h.meshHash) + ", expected " +
               hexHash(*expect.meshHash) + "): rebuild it");
  if (expect.options && hashPatchOptions(*expect.options) != h.optionsHash)
    throw fail("cache was built with different options (" + optionsText(opt) + ", asked for " +
               optionsText(*expect.options) + "): rebuild it");

  std::vector<char> payload(h.payloadBytes);
  in.read(payload.data(), static_cast<std::streamsize>(payload.size()));
  if (!in) throw fail("read error");
  if (hashBytes(payload.data(), payload.size()) != h.payloadChecksum)
    throw fail("corrupted cache payload (checksum mismatch)");

  PatchCache c;
  c.options = opt;
  c.meshHash = h.meshHash;
  const char* p = payload.data();
  take(p, c.positions, h.numVertices * 3);
  take(p, c.faceOffsets, h.numFaces + 1);
  take(p, c.faceVertices, h.numSlots);
  take(p, c.cornerNormals, h.numSlots * 3);
  take(p, c.slotTwin, h.numSlots);
  take(p, c.faceStatus, h.numFaces);
  take(p, c.faceBulge, h.numFaces);
  if (h.version == 2 || (h.sections & 1u)) take(p, c.faceCertificate, h.numFaces);
  if (h.sections & 2u) take(p, c.faceSource, h.numFaces);
  if (h.sections & 4u) take(p, c.computedNormals, h.numSlots * 3);
  if (opt.precision == Precision::Double)
    take(p, c.edgeDataD, uint64_t(GP_E_NFIELDS) * h.numSlots);
  else
    take(p, c.edgeDataF, uint64_t(GP_E_NFIELDS) * h.numSlots);

  // Values and structure: a valid checksum does not prove the writer was sane.
  auto allFinite = [](const auto& v) {
    for (auto x : v)
      if (!std::isfinite(x)) return false;
    return true;
  };
  if (!allFinite(c.positions)) throw fail("non-finite vertex position");
  for (double x : c.positions)
    if (!(std::fabs(x) <= kMaxCoordinate)) throw fail("a vertex position beyond the coordinate range +-1e15 m");
  if (!allFinite(c.cornerNormals)) throw fail("non-finite corner normal");
  if (!allFinite(c.computedNormals)) throw fail("non-finite computed normal");
  for (size_t s = 0; 3 * s < c.computedNormals.size(); ++s) {  // unit, and turned by at most 90 degrees
    const Eigen::Map<const Eigen::Vector3d> a(&c.computedNormals[3 * s]), b(&c.cornerNormals[3 * s]);
    if (!(std::abs(a.norm() - 1) <= 1e-9) || !(a.dot(b) >= -1e-12))
      throw fail("corner " + std::to_string(s) +
                 ": its computed normal is not a unit vector within 90 degrees of its corner normal");
  }
  if (!allFinite(c.faceBulge) || !allFinite(c.edgeDataD) || !allFinite(c.edgeDataF))
    throw fail("non-finite patch record");
  for (size_t f = 0; f < c.faceCertificate.size(); ++f)  // a cosine bound; none without a patch
    if (!(std::fabs(c.faceCertificate[f]) <= 1.f) || (c.faceCertificate[f] != 0 && (c.faceStatus[f] & GP_ST_NOT_BUILT)))
      throw fail("face " + std::to_string(f) + " has a certificate margin the certificate cannot give (" +
                 std::to_string(c.faceCertificate[f]) + ")");
  // pieces follow their faces as read, in order; a cap merged from several faces as read and cut
  // into fewer pieces leaves fewer faces than sources, so a source may exceed its face's index
  for (size_t f = 0; f < c.faceSource.size(); ++f)
    if (c.faceSource[f] < 0 || (f > 0 && c.faceSource[f] < c.faceSource[f - 1]))
      throw fail("face " + std::to_string(f) + " has a source face the split cannot give (" +
                 std::to_string(c.faceSource[f]) + ")");
  if (c.faceOffsets.front() != 0 || c.faceOffsets.back() != static_cast<int32_t>(h.numSlots))
    throw fail("inconsistent face offsets");
  for (uint64_t f = 0; f < h.numFaces; ++f)
    if (int64_t(c.faceOffsets[f + 1]) - int64_t(c.faceOffsets[f]) < 3)
      throw fail("face " + std::to_string(f) + " has fewer than 3 corners");
  for (uint64_t s = 0; s < h.numSlots; ++s) {
    if (c.faceVertices[s] < 0 || static_cast<uint64_t>(c.faceVertices[s]) >= h.numVertices)
      throw fail("corner " + std::to_string(s) + " refers to vertex " + std::to_string(c.faceVertices[s]) +
                 " out of range");
    if (c.slotTwin[s] < -2 || (c.slotTwin[s] >= 0 && static_cast<uint64_t>(c.slotTwin[s]) >= h.numSlots))
      throw fail("slot " + std::to_string(s) + " has an out-of-range neighbour");
  }
  // what the records say of each other: neighbours in pairs across two faces, statuses that the
  // construction can give (a forged status word of 0xFFFFFFFF silently removed every patch)
  std::vector<int32_t> slotFace(h.numSlots);
  for (uint64_t f = 0; f < h.numFaces; ++f)
    for (int32_t s = c.faceOffsets[f]; s < c.faceOffsets[f + 1]; ++s) slotFace[s] = static_cast<int32_t>(f);
  for (uint64_t s = 0; s < h.numSlots; ++s) {
    const int32_t t = c.slotTwin[s];
    if (t >= 0 && (c.slotTwin[t] != static_cast<int32_t>(s) || slotFace[t] == slotFace[s]))
      throw fail("slot " + std::to_string(s) + " and its neighbour " + std::to_string(t) +
                 " do not name each other across two faces");
  }
  // GP_ST_GUARD .. GP_ST_NONFINITE, and GP_ST_AFFINE (checked against the records below)
  constexpr uint32_t kConstructionBits = (0x3FFu & ~GP_ST_OUTSIDE) | GP_ST_AFFINE;
  for (uint64_t f = 0; f < h.numFaces; ++f) {
    const uint32_t st = c.faceStatus[f];
    const bool tooMany = c.faceOffsets[f + 1] - c.faceOffsets[f] > GP_MAX_N;
    const bool affineOk = !(st & GP_ST_AFFINE) || (opt.foldRepair != FoldRepairMode::Off && !(st & GP_ST_NOT_BUILT));
    if ((st & ~kConstructionBits) || bool(st & GP_ST_TOO_MANY_SIDES) != tooMany || !affineOk)
      throw fail("face " + std::to_string(f) + " has a status word the construction cannot give (" +
                 std::to_string(st) + ")");
  }
  {  // (after the vertex ids are checked: the box is of the referenced vertices)
    Eigen::Vector3d lo, hi;
    referencedBox(c, lo, hi);
    if (const std::string why = floatReachProblem(lo, hi, opt.precision); !why.empty()) throw fail(why);
  }
  // the neighbours are the faces' own (computeSlotTwins): a closed mesh's slots forged to
  // boundary or non-manifold would open the surface silently
  {
    PolygonMesh topo;
    topo.faceOffsets = c.faceOffsets;
    topo.faceVertices = c.faceVertices;
    topo.positions.resize(h.numVertices);
    const std::vector<int32_t> twins = computeSlotTwins(topo);
    for (uint64_t s = 0; s < h.numSlots; ++s)
      if (twins[s] != c.slotTwin[s])
        throw fail("slot " + std::to_string(s) + " names neighbour " + std::to_string(c.slotTwin[s]) +
                   " where the faces' vertices give " + std::to_string(twins[s]) +
                   " (-1 boundary, -2 non-manifold): the neighbours do not match the faces");
  }
  // each built face's records start at its vertices with their corner normals, in the cache's
  // precision (gp_edge.h): positions or normals edited after the patches were built contradict them
  auto checkRecords = [&](const auto& data) {
    using Real = std::decay_t<decltype(data[0])>;
    const uint64_t C = h.numSlots;
    for (uint64_t f = 0; f < h.numFaces; ++f) {
      if (c.faceStatus[f] & GP_ST_NOT_BUILT) continue;
      for (int32_t s = c.faceOffsets[f]; s < c.faceOffsets[f + 1]; ++s) {
        const int32_t v = c.faceVertices[s];
        for (int a = 0; a < 3; ++a) {
          if (data[(GP_E_V0 + a) * C + s] != Real(c.positions[3 * size_t(v) + a]))
            throw fail("face " + std::to_string(f) + ": its patch record " + std::to_string(s - c.faceOffsets[f]) +
                       " does not start at vertex " + std::to_string(v) +
                       " (the positions do not match the patches built from them)");
          if (data[(GP_E_N0 + a) * C + s] != Real(c.cornerNormals[3 * size_t(s) + a]))
            throw fail("face " + std::to_string(f) + ": its patch record " + std::to_string(s - c.faceOffsets[f]) +
                       " does not carry corner normal " + std::to_string(s) +
                       " (the normals do not match the patches built from them)");
        }
      }
      // a triangle marked affine is one (markAffineTriangles): else its map would not lie in the
      // neighbours' tangent planes or could fold
      if (c.faceStatus[f] & GP_ST_AFFINE) {
        Real recs[GP_MAX_N * GP_E_NFIELDS];
        gatherRecords(c, static_cast<int>(f), recs);
        if (!isAffineTriangle(c.faceSize(static_cast<int>(f)), recs))
          throw fail("face " + std::to_string(f) +
                     " is marked as a flat triangle (evaluated as its affine map with its edge curves) but its "
                     "patch records are not one, or that map is not proven regular");
      }
    }
  };
  if (opt.precision == Precision::Double)
    checkRecords(c.edgeDataD);
  else
    checkRecords(c.edgeDataF);
  return c;
}

}  // namespace sf
