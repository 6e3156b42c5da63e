// SPDX-License-Identifier: Apache-2.0
// Scene files (JSON): objects with their mesh or cache, method, options and pose, read into a
// Scene; every error names the file and the JSON path.
#include <smoothforce/runtime/scene.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <nlohmann/json.hpp>
#include <sstream>
#include <utility>
#include <vector>

#include <smoothforce/base/coordinate_range.h>
#include <smoothforce/force/force_option_text.h>
#include <smoothforce/force/force_presets.h>
#include <smoothforce/force/force_tracking.h>
#include <smoothforce/patch/cache_file.h>
#include <smoothforce/patch/mesh_pipeline.h>
#include <smoothforce/patch/patch_option_text.h>

namespace sf::rt {

namespace {

using nlohmann::json;

/// Error helper: "FILE: /json/path: message".
struct Ctx {
  std::string file;
  [[noreturn]] void fail(const std::string& where, const std::string& what) const {
    throw InputError(file + ": " + (where.empty() ? "/" : where) + ": " + what);
  }
  double number(const json& j, const std::string& where, const char* expect) const {
    if (!j.is_number()) fail(where, std::string("expected ") + expect + ", got " + j.dump());
    const double v = j.get<double>();
    if (!std::isfinite(v)) fail(where, std::string("expected ") + expect + ", got " + j.dump());
    return v;
  }
  Eigen::Vector3d vec3(const json& j, const std::string& where) const {
    if (!j.is_array() || j.size() != 3) fail(where, "expected an array of 3 numbers, got " + j.dump());
    Eigen::Vector3d v;
    for (int k = 0; k < 3; ++k) v[k] = number(j[k], where + "/" + std::to_string(k), "a finite number");
    return v;
  }
  void onlyKeys(const json& j, const std::string& where, const std::vector<std::string>& keys) const {
    for (auto it = j.begin(); it != j.end(); ++it) {
      bool ok = false;
      for (const std::string& k : keys) ok = ok || it.key() == k;
      if (!ok) {
        std::string list;
        for (const std::string& k : keys) list += (list.empty() ? "" : ", ") + k;
        fail(where + "/" + it.key(), "unknown key (expected one of: " + list + ")");
      }
    }
  }
};

Eigen::Quaterniond parseRotation(const Ctx& c, const json& j, const std::string& where) {
  if (!j.is_object())
    c.fail(where, "expected {\"axis\": [x, y, z], \"angle\": radians} or {\"quaternion\": [w, x, y, z]}");
  c.onlyKeys(j, where, {"axis", "angle", "quaternion"});
  if (j.contains("quaternion")) {
    if (j.contains("axis") || j.contains("angle")) c.fail(where, "give either axis/angle or quaternion, not both");
    const std::string w = where + "/quaternion";
    const json& q = j["quaternion"];
    if (!q.is_array() || q.size() != 4) c.fail(w, "expected [w, x, y, z], got " + q.dump());
    double v[4];
    for (int k = 0; k < 4; ++k) v[k] = c.number(q[k], w + "/" + std::to_string(k), "a finite number");
    Eigen::Quaterniond r(v[0], v[1], v[2], v[3]);
    if (!(r.coeffs().stableNorm() > 1e-12)) c.fail(w, "the quaternion is zero");
    if (!(r.coeffs().stableNorm() < 1e150)) c.fail(w, "the quaternion's norm is beyond 1e150 (it would not normalise)");
    return r.normalized();
  }
  if (!j.contains("axis") || !j.contains("angle"))
    c.fail(where, "axis-angle needs both \"axis\" and \"angle\" (radians)");
  const Eigen::Vector3d axis = c.vec3(j["axis"], where + "/axis");
  if (!(axis.norm() > 1e-12)) c.fail(where + "/axis", "the axis is zero");
  const double angle = c.number(j["angle"], where + "/angle", "an angle in radians");
  return Eigen::Quaterniond(Eigen::AngleAxisd(angle, axis.normalized()));
}

Pose parsePose(const Ctx& c, const json& j, const std::string& where) {
  if (!j.is_object()) c.fail(where, "expected an object with translation, rotation, scale");
  c.onlyKeys(j, where, {"translation", "rotation", "scale"});
  Pose p;
  if (j.contains("translation")) p.translation = c.vec3(j["translation"], where + "/translation");
  if (!inCoordinateRange(p.translation)) c.fail(where + "/translation", "beyond the coordinate range +-1e15 m");
  if (j.contains("rotation")) p.rotation = parseRotation(c, j["rotation"], where + "/rotation");
  if (j.contains("scale")) {
    p.scale = c.number(j["scale"], where + "/scale", "a scale in [1e-09, 1e+09]");
    if (!(p.scale >= kMinSceneScale && p.scale <= kMaxSceneScale))
      c.fail(where + "/scale", "expected a scale in [1e-09, 1e+09], got " + j["scale"].dump());
  }
  return p;
}

std::string stringField(const Ctx& c, const json& j, const std::string& where) {
  if (!j.is_string() || j.get<std::string>().empty()) c.fail(where, "expected a non-empty string, got " + j.dump());
  if (j.get<std::string>().find('\0') != std::string::npos)  // a path would end there
    c.fail(where, "expected a string without NUL characters");
  return j.get<std::string>();
}

bool isControl(char ch) { return static_cast<unsigned char>(ch) < 0x20 || ch == 0x7f; }

/// A control character of s, or -1.
int controlCharacter(const std::string& s) {
  for (const char ch : s)
    if (isControl(ch)) return static_cast<unsigned char>(ch);
  return -1;
}

/// An object's name: the given one (no control characters: it is printed in the report), or
/// the file's stem with any control character replaced by '?'.
std::string objectName(const Ctx& c, const json& o, const std::string& w, const std::string& file) {
  if (!o.contains("name")) {
    std::string stem = std::filesystem::path(file).stem().string();
    for (char& ch : stem)
      if (isControl(ch)) ch = '?';
    return stem;
  }
  const std::string name = stringField(c, o["name"], w + "/name");
  if (const int ch = controlCharacter(name); ch >= 0) {
    char buf[96];
    std::snprintf(buf, sizeof buf, "expected a name without control characters, got U+%04X in it", ch);
    c.fail(w + "/name", buf);
  }
  return name;
}

/// The patch options of a `mesh` object (after its preset): the keys of patch_option_text.h
/// (precision, normals, cross_tangent, orient, cage, creases, fold_repair: strings; crease_angle: degrees),
/// read by the parser every front end shares. A cache keeps its own.
void parsePatchKeys(const Ctx& c, const json& o, const std::string& w, bool mesh, PatchOptions& opt) {
  for (const PatchOptionSpec& spec : kPatchOptionSpecs) {
    const std::string key = spec.key;
    if (!o.contains(key)) continue;
    const std::string where = w + "/" + key;
    if (!mesh) c.fail(where, "applies to mesh objects only (a cache keeps the options it was built with)");
    try {
      if (key == "crease_angle") {
        if (!o[key].is_number()) c.fail(where, "expected a number (degrees)");
        setCreaseAngle(opt, o[key].get<double>());
      } else {
        setPatchOption(opt, key, stringField(c, o[key], where));
      }
    } catch (const InputError& e) {
      if (std::string(e.what()).rfind(c.file + ": ", 0) == 0) throw;  // c.fail's own
      c.fail(where, e.what());
    }
  }
}

/// The force options of an object: the keys of force_option_text.h in their order (method and
/// preset first, explicit options after the preset), strings or numbers as each takes, read by the
/// parser every front end shares.
void parseForceKeys(const Ctx& c, const json& o, const std::string& w, ForceSettings& force) {
  for (const OptionSpec& spec : kForceOptionSpecs) {
    const std::string key = spec.key;
    if (!o.contains(key)) continue;
    const std::string where = w + "/" + key;
    try {
      if (o[key].is_number())
        setForceOption(force, key, o[key].get<double>());
      else
        setForceOption(force, key, stringField(c, o[key], where));
    } catch (const InputError& e) {
      if (std::string(e.what()).rfind(c.file + ": ", 0) == 0) throw;  // c.fail's own
      c.fail(where, e.what());
    }
  }
}

/// Every key an object may have: its source, name and pose, the force and the patch options.
std::vector<std::string> objectKeys() {
  std::vector<std::string> keys = {"name", "mesh", "cache", "pose", "comment"};
  for (const OptionSpec& s : kForceOptionSpecs) keys.push_back(s.key);
  for (const OptionSpec& s : kPatchOptionSpecs) keys.push_back(s.key);
  return keys;
}

/// The key of an object's cache in loadScene: the file (its canonical path where it exists),
/// its kind, and for a mesh the options its patches are built with.
std::string cacheKey(const std::filesystem::path& file, bool mesh, const PatchOptions& o) {
  std::error_code ec;
  const std::filesystem::path canonical = std::filesystem::weakly_canonical(file, ec);
  std::string key = (ec ? file : canonical).string();
  key += '\0';
  if (!mesh) return key + "cache";
  const PatchOptionText t = patchOptionText(o);
  char angle[32];
  std::snprintf(angle, sizeof angle, "%.17g", t.creaseAngle);
  key += "mesh " + t.precision + ' ' + t.crossTangent + ' ' + t.normals + ' ' + t.orient + ' ' + t.cage + ' ' +
         t.creases + ' ' + angle + ' ' + t.foldRepair;
  return key;
}
}  // namespace

Scene loadScene(const std::string& path, const SceneDefaults& defaults, const RendererFactory& factory) {
  namespace fs = std::filesystem;
  const Ctx c{path};
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError(path + ": cannot open scene file");
  std::stringstream ss;
  ss << in.rdbuf();
  json root;
  try {
    root = json::parse(ss.str());
  } catch (const json::exception& e) {  // a syntax error, or a number too large for a double
    throw InputError(path + ": invalid JSON: " + e.what());
  }
  if (!root.is_object()) c.fail("", "expected an object with \"objects\"");
  c.onlyKeys(root, "", {"objects", "device", "comment"});
  if (!root.contains("objects")) c.fail("/objects", "missing (expected an array of objects)");
  const json& objs = root["objects"];
  if (!objs.is_array() || objs.empty()) c.fail("/objects", "expected a non-empty array of objects");
  const fs::path base = fs::path(path).parent_path();
  // objects that name one file with the same patch options share its cache (read once)
  std::map<std::string, std::shared_ptr<const PatchCache>> loadedCaches;
  std::vector<std::pair<std::string, bool>> names;  // each object's name, and whether the file gave it
  Scene scene;
  if (root.contains("device")) {
    const json& d = root["device"];
    if (!d.is_object()) c.fail("/device", "expected an object with \"transform\"");
    c.onlyKeys(d, "/device", {"transform", "comment"});
    if (d.contains("transform"))
      scene.setDeviceTransform(DeviceTransform(parsePose(c, d["transform"], "/device/transform")));
  }
  for (size_t i = 0; i < objs.size(); ++i) {
    const std::string w = "/objects/" + std::to_string(i);
    const json& o = objs[i];
    if (!o.is_object()) c.fail(w, "expected an object with \"mesh\" or \"cache\"");
    c.onlyKeys(o, w, objectKeys());
    const bool hasMesh = o.contains("mesh"), hasCache = o.contains("cache");
    if (hasMesh == hasCache)
      c.fail(w, hasMesh ? "give either \"mesh\" or \"cache\", not both" : "missing \"mesh\" or \"cache\"");
    const std::string key = hasMesh ? "mesh" : "cache";
    const std::string rel = stringField(c, o[key], w + "/" + key);
    const fs::path file = fs::path(rel).is_absolute() ? fs::path(rel) : base / rel;
    SceneObject obj;
    obj.source = file.string();
    obj.name = objectName(c, o, w, rel);
    for (size_t k = 0; k < names.size(); ++k)  // a given name names one object
      if (names[k].first == obj.name && (o.contains("name") || names[k].second))
        c.fail(w + "/name", "\"" + obj.name + "\" is also the name of /objects/" + std::to_string(k) +
                                (o.contains("name") ? "" : " (this object's default name: its file's stem)"));
    names.emplace_back(obj.name, o.contains("name"));
    if (o.contains("pose")) obj.pose = parsePose(c, o["pose"], w + "/pose");
    ForceSettings force{defaults.method, defaults.force, ""};
    PatchOptions patchOptions = defaults.patchOptions;
    parseForceKeys(c, o, w, force);
    if (!force.preset.empty()) patchOptions.precision = findForcePreset(force.preset).precision;
    obj.method = force.method;
    obj.force = force.options;
    parsePatchKeys(c, o, w, hasMesh, patchOptions);
    try {  // here, not in the renderer's factory, whose errors name the file
      validateForceOptions(obj.force);
    } catch (const InputError& e) {
      c.fail(o.contains("preset") ? w + "/preset" : w, e.what());
    }
    try {
      std::shared_ptr<const PatchCache>& shared = loadedCaches[cacheKey(file, hasMesh, patchOptions)];
      if (shared) {
        obj.cache = shared;
        obj.fromMesh = hasMesh;
      } else if (hasMesh) {
        const auto t0 = std::chrono::steady_clock::now();
        const LoadedMesh loaded = loadMesh(obj.source, patchOptions);
        obj.cache = shared = std::make_shared<const PatchCache>(preparePatchSkeleton(loaded, patchOptions));
        obj.buildSeconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
        obj.fromMesh = true;
      } else {
        obj.cache = shared = std::make_shared<const PatchCache>(readPatchCache(obj.source));
      }
      obj.force = servoForceOptions(obj.force);
      obj.renderer = factory(obj.cache, obj.method, obj.force);
    } catch (const InputError& e) {
      c.fail(w + "/" + key, e.what());
    }
    if (!obj.renderer) c.fail(w, "no renderer for this object");
    scene.add(std::move(obj));
  }
  return scene;
}

}  // namespace sf::rt
