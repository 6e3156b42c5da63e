// SPDX-License-Identifier: Apache-2.0
// readMesh: reads the file and dispatches to the OBJ, OFF or PLY reader by extension.
#include <smoothforce/mesh/mesh_io.h>

#include <algorithm>
#include <cctype>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string_view>

#include <smoothforce/base/text_encoding.h>

#include "mesh_io_detail.h"

namespace sf {
namespace {

std::string lowerExtension(const std::string& path) {
  std::string ext = std::filesystem::path(path).extension().string();
  for (char& c : ext) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return ext;
}

std::string readBytes(const std::string& path) {
  std::error_code ec;
  if (std::filesystem::is_directory(path, ec)) throw InputError(path + ": is a directory");
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError(path + ": cannot open file");
  std::ostringstream buf;
  buf << in.rdbuf();
  if (in.bad()) throw InputError(path + ": read error");
  return std::move(buf).str();
}

/// Refuses UTF-16 and UTF-32 text (textEncodingProblem): the readers would see bad keywords or
/// no statements.
void checkEncoding(const std::string& path, std::string_view data) {
  if (const std::string why = textEncodingProblem(data); !why.empty())
    throw InputError(path + ": " + why + "; save it as UTF-8 or ASCII");
}

}  // namespace

PolygonMesh readMesh(const std::string& path) {
  const std::string ext = lowerExtension(path);
  if (ext != ".obj" && ext != ".off" && ext != ".ply") {
    throw InputError(path + ": unknown mesh file extension " +
                     (ext.empty() ? std::string("(none)") : detail::quoted(ext)) + " (expected .obj, .off or .ply)");
  }
  const std::string bytes = readBytes(path);
  std::string_view data = bytes;
  checkEncoding(path, data);
  if (data.substr(0, 3) == "\xEF\xBB\xBF") data.remove_prefix(3);  // UTF-8 byte-order mark
  bool blank = true;
  for (char c : data) {
    if (!detail::isSpace(c) && c != '\n') {
      blank = false;
      break;
    }
  }
  if (blank) detail::failAt(path, 1, "file is empty");

  PolygonMesh mesh = ext == ".obj"   ? detail::readObj(path, data)
                     : ext == ".off" ? detail::readOff(path, data)
                                     : detail::readPly(path, data);
  mesh.sourcePath = path;
  return mesh;
}

}  // namespace sf
