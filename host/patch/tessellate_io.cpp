// SPDX-License-Identifier: Apache-2.0
// writeTriangleMesh (tessellate.h): OBJ with a group per patch, binary or ASCII PLY.
#include <unistd.h>

#include <cstdio>
#include <cstring>
#include <string>
#include <vector>

#include <smoothforce/base/staged_output.h>
#include <smoothforce/base/error.h>
#include <smoothforce/patch/tessellate.h>

namespace sf {

namespace {

template <class T>
void append(std::vector<unsigned char>& out, T value) {
  unsigned char b[sizeof(T)];
  std::memcpy(b, &value, sizeof(T));
  out.insert(out.end(), b, b + sizeof(T));
}

void writeObj(std::FILE* f, const TriangleMesh& m) {
  std::fprintf(f, "# SmoothForce patch tessellation: %zu vertices, %zu triangles, one group per patch\n",
               m.positions.size(), m.triangles.size());
  std::fprintf(f, "o smoothforce_patches\n");
  for (const auto& p : m.positions) std::fprintf(f, "v %.17g %.17g %.17g\n", p.x(), p.y(), p.z());
  for (const auto& n : m.normals) std::fprintf(f, "vn %.9g %.9g %.9g\n", n.x(), n.y(), n.z());
  for (size_t t = 0; t < m.triangles.size(); ++t) {
    if (t == 0 || m.face[t] != m.face[t - 1]) std::fprintf(f, "g patch_%d\n", m.face[t]);
    const auto& tri = m.triangles[t];
    std::fprintf(f, "f %d//%d %d//%d %d//%d\n", tri[0] + 1, tri[0] + 1, tri[1] + 1, tri[1] + 1, tri[2] + 1, tri[2] + 1);
  }
}

void writePly(std::FILE* f, const TriangleMesh& m, bool binary) {
  std::fprintf(f,
               "ply\nformat %s 1.0\ncomment SmoothForce patch tessellation; status = SF_ST_* bits of the "
               "evaluation,\ncomment fold = on a folded patch, bulge = largest patch bulge / face diameter, "
               "patch = polygon id\nelement vertex %zu\nproperty double x\nproperty double y\nproperty double z\n"
               "property float nx\nproperty float ny\nproperty float nz\nproperty uint status\n"
               "property uchar fold\nproperty float bulge\nelement face %zu\n"
               "property list uchar int vertex_indices\nproperty int patch\nend_header\n",
               binary ? "binary_little_endian" : "ascii", m.positions.size(), m.triangles.size());
  if (!binary) {
    for (size_t i = 0; i < m.positions.size(); ++i) {
      const auto& p = m.positions[i];
      const auto& n = m.normals[i];
      std::fprintf(f, "%.17g %.17g %.17g %.9g %.9g %.9g %u %u %.9g\n", p.x(), p.y(), p.z(), n.x(), n.y(), n.z(),
                   m.status[i], unsigned(m.fold[i]), double(m.bulge[i]));
    }
    for (size_t t = 0; t < m.triangles.size(); ++t)
      std::fprintf(f, "3 %d %d %d %d\n", m.triangles[t][0], m.triangles[t][1], m.triangles[t][2], m.face[t]);
    return;
  }
  std::vector<unsigned char> b;
  b.reserve(m.positions.size() * 41 + m.triangles.size() * 17);
  for (size_t i = 0; i < m.positions.size(); ++i) {
    for (int a = 0; a < 3; ++a) append(b, m.positions[i][a]);
    for (int a = 0; a < 3; ++a) append(b, static_cast<float>(m.normals[i][a]));
    append(b, m.status[i]);
    append(b, m.fold[i]);
    append(b, m.bulge[i]);
  }
  for (size_t t = 0; t < m.triangles.size(); ++t) {
    append(b, static_cast<uint8_t>(3));
    for (int a = 0; a < 3; ++a) append(b, m.triangles[t][a]);
    append(b, m.face[t]);
  }
  std::fwrite(b.data(), 1, b.size(), f);
}

}  // namespace

void writeTriangleMesh(const TriangleMesh& m, const std::string& path, const TriangleMeshFormat& format) {
  const auto dot = path.find_last_of('.');
  const std::string ext = dot == std::string::npos ? "" : path.substr(dot);
  if (ext != ".obj" && ext != ".ply") throw InputError(path + ": output must end in .obj or .ply");
  if (m.status.size() != m.positions.size() || m.fold.size() != m.positions.size() ||
      m.bulge.size() != m.positions.size() || m.normals.size() != m.positions.size() ||
      m.face.size() != m.triangles.size())
    throw InputError(path + ": the triangle mesh's per-vertex or per-triangle arrays differ in length");
  // written beside the path and renamed into place: a failed write (a full disk) leaves no
  // partial file under the path
  const std::string tmp = stagingPath(path);
  std::FILE* f = std::fopen(tmp.c_str(), "wb");
  if (!f) throw InputError(path + ": cannot open for writing");
  if (ext == ".obj")
    writeObj(f, m);
  else
    writePly(f, m, format.binary);
  const bool bad = std::ferror(f) != 0;
  if (std::fclose(f) != 0 || bad || std::rename(tmp.c_str(), path.c_str()) != 0) {
    discardStaging(tmp, path);
    throw InputError(path + ": write failed");
  }
}

}  // namespace sf
