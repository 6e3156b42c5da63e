// SPDX-License-Identifier: Apache-2.0
// Point clouds of one method and depth for viewers (sweep_outputs.h): VTK XML .vtp and PLY.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <string>
#include <vector>

#include <smoothforce/base/error.h>
#include <smoothforce/sweep/sweep_io.h>
#include <smoothforce/sweep/sweep_outputs.h>

namespace sf {

namespace {

/// One appended array of a .vtp: its XML attributes and its raw little-endian bytes.
struct VtpArray {
  std::string type, name;
  int components = 1;
  std::vector<unsigned char> bytes;
};

template <class T>
void append(std::vector<unsigned char>& out, T value) {
  unsigned char b[sizeof(T)];
  std::memcpy(b, &value, sizeof(T));
  out.insert(out.end(), b, b + sizeof(T));
}

const HipResult& record(const HipCloud& c, size_t i) { return c.data->results[c.method][c.index[i]]; }

double magnitude(const HipResult& r) {
  return std::sqrt(double(r.force[0]) * r.force[0] + double(r.force[1]) * r.force[1] + double(r.force[2]) * r.force[2]);
}

/// Writes all of `bytes` or throws naming the file.
void put(std::FILE* f, const void* bytes, size_t n, const std::string& path) {
  if (n != 0 && std::fwrite(bytes, 1, n, f) != n) {
    std::fclose(f);
    throw InputError(path + ": write failed");
  }
}

void closeChecked(std::FILE* f, const std::string& path) {
  const bool bad = std::ferror(f) != 0;
  if (std::fclose(f) != 0 || bad) throw InputError(path + ": write failed");
}

}  // namespace

void writeHipVtp(const std::string& path, const HipCloud& c) {
  static_assert(sizeof(float) == 4 && sizeof(double) == 8, "IEEE-754 binary32/64");
  const size_t n = c.index.size();
  std::vector<VtpArray> point = {{"Float32", "force", 3, {}},         {"Float32", "force_magnitude", 1, {}},
                                 {"Float64", "discontinuity", 1, {}}, {"UInt8", "contact", 1, {}},
                                 {"UInt8", "missed", 1, {}},          {"Int32", "face", 1, {}},
                                 {"UInt32", "status", 1, {}},         {"UInt16", "iterations", 1, {}},
                                 {"Float32", "ref_distance", 1, {}},  {"Float32", "scp", 3, {}},
                                 {"UInt64", "hip_index", 1, {}}};
  VtpArray points{"Float64", "Points", 3, {}}, conn{"Int64", "connectivity", 1, {}}, offs{"Int64", "offsets", 1, {}};
  const size_t bytesPerPoint[] = {12, 4, 8, 1, 1, 4, 4, 2, 4, 12, 8};
  for (size_t a = 0; a < point.size(); ++a) point[a].bytes.reserve(n * bytesPerPoint[a]);
  points.bytes.reserve(24 * n);
  conn.bytes.reserve(8 * n);
  offs.bytes.reserve(8 * n);
  for (size_t i = 0; i < n; ++i) {
    const HipResult& r = record(c, i);
    for (int a = 0; a < 3; ++a) append(point[0].bytes, r.force[a]);
    append(point[1].bytes, static_cast<float>(magnitude(r)));
    append(point[2].bytes, c.discontinuity[i]);
    append(point[3].bytes, static_cast<uint8_t>(r.contact));
    append(point[4].bytes, hipMissed(r));
    append(point[5].bytes, r.face);
    append(point[6].bytes, r.status);
    append(point[7].bytes, r.iterations);
    append(point[8].bytes, r.refDistance);
    for (int a = 0; a < 3; ++a) append(point[9].bytes, r.scp[a]);
    append(point[10].bytes, static_cast<uint64_t>(c.index[i]));
    const Eigen::Vector3d& h = c.data->hips[c.index[i]];
    for (int a = 0; a < 3; ++a) append(points.bytes, h[a]);
    append(conn.bytes, static_cast<int64_t>(i));
    append(offs.bytes, static_cast<int64_t>(i + 1));
  }
  std::string xml = "<?xml version=\"1.0\"?>\n<!-- SmoothForce sweep: " + c.data->config.methods[c.method] +
                    " HIPs, one vertex cell each; units: m, N, rad/m -->\n"
                    "<VTKFile type=\"PolyData\" version=\"1.0\" byte_order=\"LittleEndian\" header_type=\"UInt64\">\n"
                    "  <PolyData>\n    <Piece NumberOfPoints=\"" +
                    std::to_string(n) + "\" NumberOfVerts=\"" + std::to_string(n) +
                    "\" NumberOfLines=\"0\" NumberOfStrips=\"0\" NumberOfPolys=\"0\">\n";
  uint64_t offset = 0;
  auto tag = [&](const VtpArray& a, const char* indent) {
    xml += std::string(indent) + "<DataArray type=\"" + a.type + "\" Name=\"" + a.name + "\"" +
           (a.components > 1 ? " NumberOfComponents=\"" + std::to_string(a.components) + "\"" : std::string()) +
           " format=\"appended\" offset=\"" + std::to_string(offset) + "\"/>\n";
    offset += sizeof(uint64_t) + a.bytes.size();
  };
  xml += "      <PointData Scalars=\"force_magnitude\" Vectors=\"force\">\n";
  for (const VtpArray& a : point) tag(a, "        ");
  xml += "      </PointData>\n      <Points>\n";
  tag(points, "        ");
  xml += "      </Points>\n      <Verts>\n";
  tag(conn, "        ");
  tag(offs, "        ");
  xml += "      </Verts>\n    </Piece>\n  </PolyData>\n  <AppendedData encoding=\"raw\">\n   _";
  std::FILE* f = std::fopen(path.c_str(), "wb");
  if (!f) throw InputError(path + ": cannot open for writing");
  put(f, xml.data(), xml.size(), path);
  std::vector<const VtpArray*> order;
  for (const VtpArray& a : point) order.push_back(&a);
  order.insert(order.end(), {&points, &conn, &offs});
  for (const VtpArray* a : order) {
    const uint64_t size = a->bytes.size();
    put(f, &size, sizeof size, path);
    put(f, a->bytes.data(), a->bytes.size(), path);
  }
  const std::string tail = "\n  </AppendedData>\n</VTKFile>\n";
  put(f, tail.data(), tail.size(), path);
  closeChecked(f, path);
}

void writeHipPly(const std::string& path, const HipCloud& c, double ref) {
  std::FILE* f = std::fopen(path.c_str(), "wb");
  if (!f) throw InputError(path + ": cannot open for writing");
  char head[1024];
  const int len = std::snprintf(
      head, sizeof head,
      "ply\nformat binary_little_endian 1.0\ncomment SmoothForce sweep: HIPs, normal = force direction,\n"
      "comment red = local force-direction discontinuity, log scale: white at the depth's largest\n"
      "comment per-method median, full red at 100 times it; blue = no contact\n"
      "comment quality = local force-direction discontinuity, rad/m (-1: none)\n"
      "element vertex %zu\nproperty float x\nproperty float y\nproperty float z\n"
      "property float nx\nproperty float ny\nproperty float nz\nproperty uchar red\nproperty uchar green\n"
      "property uchar blue\nproperty float quality\nelement face 0\nproperty list uchar int vertex_indices\n"
      "end_header\n",
      c.index.size());
  put(f, head, static_cast<size_t>(len), path);
  for (size_t i = 0; i < c.index.size(); ++i) {
    const HipResult& r = record(c, i);
    const Eigen::Vector3d F(r.force[0], r.force[1], r.force[2]);
    const bool valid = r.contact && F.norm() > 0;
    const Eigen::Vector3d dir = valid ? F.normalized() : Eigen::Vector3d::Zero();
    const Eigen::Vector3d& h = c.data->hips[c.index[i]];
    const double local = c.discontinuity[i];
    float v[6];
    for (int a = 0; a < 3; ++a) {
      v[a] = static_cast<float>(h[a]);
      v[3 + a] = static_cast<float>(dir[a]);
    }
    unsigned char rgb[3] = {0, 0, 255};
    if (valid) {
      const double t = std::isfinite(local) && local > 0 ? std::clamp(std::log10(local / ref) / 2, 0.0, 1.0) : 0.0;
      rgb[0] = 255;
      rgb[1] = rgb[2] = static_cast<unsigned char>(std::lround(255 * (1 - t)));
    }
    const float quality = std::isfinite(local) ? static_cast<float>(local) : -1.0f;
    put(f, v, sizeof v, path);
    put(f, rgb, 3, path);
    put(f, &quality, sizeof quality, path);
  }
  closeChecked(f, path);
}

}  // namespace sf
