// SPDX-License-Identifier: Apache-2.0
// NumPy .npy writer and the per-HIP results_METHOD.npy of a sweep (sweep_outputs.h).
// Format: https://numpy.org/doc/stable/reference/generated/numpy.lib.format.html (version 1.0).
#include <tbb/parallel_for.h>

#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>

#include <smoothforce/base/error.h>
#include <smoothforce/sweep/sweep_io.h>
#include <smoothforce/sweep/sweep_outputs.h>

namespace sf {

namespace {

size_t typeBytes(const std::string& type) {
  if (type.size() < 3 || (type[0] != '<' && type[0] != '|') || std::strchr("fiub", type[1]) == nullptr)
    throw InputError("npy: unsupported type '" + type + "'");
  return static_cast<size_t>(std::stoul(type.substr(2)));
}

/// Packs the fields of one HIP's record; the order and types are sweepNpyFields'.
class RecordPacker {
 public:
  explicit RecordPacker(std::vector<unsigned char>& out) : out_(out) {}
  template <class T>
  RecordPacker& operator<<(T value) {
    unsigned char b[sizeof(T)];
    std::memcpy(b, &value, sizeof(T));
    out_.insert(out_.end(), b, b + sizeof(T));
    return *this;
  }

 private:
  std::vector<unsigned char>& out_;
};

}  // namespace

void writeNpy(const std::string& path, const std::vector<NpyField>& fields, uint64_t rows, const void* bytes) {
  std::string descr = "[";
  size_t record = 0;
  for (const NpyField& f : fields) {
    descr +=
        "('" + f.name + "', '" + f.type + "'" + (f.count > 1 ? ", (" + std::to_string(f.count) + ",)" : "") + "), ";
    record += typeBytes(f.type) * static_cast<size_t>(f.count);
  }
  descr += "]";
  std::string header = "{'descr': " + descr + ", 'fortran_order': False, 'shape': (" + std::to_string(rows) + ",), }";
  // magic (6) + version (2) + header length (2) + header, padded with spaces to a multiple of 64, ending in '\n'.
  const size_t total = 10 + header.size() + 1;
  header.append((64 - total % 64) % 64, ' ');
  header += '\n';
  if (header.size() > 65535) throw InputError(path + ": npy header too long");
  std::FILE* f = std::fopen(path.c_str(), "wb");
  if (!f) throw InputError(path + ": cannot open for writing");
  const unsigned char magic[8] = {0x93, 'N', 'U', 'M', 'P', 'Y', 1, 0};
  const uint16_t hlen = static_cast<uint16_t>(header.size());
  const unsigned char len[2] = {static_cast<unsigned char>(hlen & 0xff), static_cast<unsigned char>(hlen >> 8)};
  const size_t data = static_cast<size_t>(rows) * record;
  bool ok = std::fwrite(magic, 1, 8, f) == 8 && std::fwrite(len, 1, 2, f) == 2 &&
            std::fwrite(header.data(), 1, header.size(), f) == header.size() &&
            (data == 0 || std::fwrite(bytes, 1, data, f) == data);
  ok = std::fclose(f) == 0 && ok;
  if (!ok) throw InputError(path + ": write failed");
}

std::vector<NpyField> sweepNpyFields() {
  return {{"hip", "<f8", 3},
          {"depth", "<f8", 1},
          {"group", "<u2", 1},
          {"force", "<f4", 3},
          {"force_magnitude", "<f4", 1},
          {"scp", "<f4", 3},
          {"ref_distance", "<f4", 1},
          {"discontinuity", "<f8", 1},
          {"face", "<i4", 1},
          {"status", "<u4", 1},
          {"iterations", "<u2", 1},
          {"contact", "|u1", 1},
          {"missed", "|u1", 1},
          {"done", "|u1", 1}};
}

size_t sweepNpyRecordSize() {
  size_t n = 0;
  for (const NpyField& f : sweepNpyFields()) n += typeBytes(f.type) * static_cast<size_t>(f.count);
  return n;
}

void writeSweepNpy(const SweepData& d, const std::vector<std::vector<double>>& disc, const std::string& dir) {
  const size_t N = d.config.samples, total = d.hips.size();
  // one method's file per task (each packs its own records: 174 MB for 2 x 10^6 HIPs)
  tbb::parallel_for(size_t(0), d.config.methods.size(), [&](size_t m) {
    std::vector<unsigned char> bytes;
    bytes.reserve(total * sweepNpyRecordSize());
    RecordPacker p(bytes);
    for (size_t g = 0; g < total; ++g) {
      const HipResult& r = d.results[m][g];
      const size_t group = N ? g / N : 0;
      const double F = std::sqrt(double(r.force[0]) * r.force[0] + double(r.force[1]) * r.force[1] +
                                 double(r.force[2]) * r.force[2]);
      p << d.hips[g].x() << d.hips[g].y() << d.hips[g].z() << d.config.groupDepths.at(group)
        << static_cast<uint16_t>(group) << r.force[0] << r.force[1] << r.force[2] << static_cast<float>(F) << r.scp[0]
        << r.scp[1] << r.scp[2] << r.refDistance << disc[m][g] << r.face << r.status << r.iterations << r.contact
        << hipMissed(r) << r.done;
    }
    writeNpy(dir + "/results_" + d.config.methods[m] + ".npy", sweepNpyFields(), total, bytes.data());
  });
}

}  // namespace sf
