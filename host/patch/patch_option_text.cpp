// SPDX-License-Identifier: Apache-2.0
#include <smoothforce/patch/patch_option_text.h>

#include <cmath>
#include <cstdio>

#include <smoothforce/base/error.h>

namespace sf {

const PatchOptionSpec kPatchOptionSpecs[7] = {
    {"precision", "--precision", "float|double"},
    {"normals", "--normals", "auto|file|angle|area"},
    {"cross_tangent", "--cross-tangent", "corrected|paper|blend"},
    {"orient", "--orient", "outward|keep"},
    {"cage", "--cage", "none|catmull-clark"},
    {"creases", "--creases", "a list of tags, groups, normals (each once), or none"},
    {"crease_angle", "--crease-angle", "degrees in [0, 180) (0: off)"},
};

namespace {

const PatchOptionSpec* specOf(const std::string& key) {
  for (const PatchOptionSpec& s : kPatchOptionSpecs)
    if (key == s.key) return &s;
  return nullptr;
}

[[noreturn]] void bad(const PatchOptionSpec& s, OptionSpelling spelling, const std::string& value) {
  throw InputError(std::string(spelling == OptionSpelling::Flag ? s.flag : s.key) + ": expected " + s.values +
                   ", got '" + value + "'");
}

}  // namespace

void setPatchOption(PatchOptions& o, const std::string& key, const std::string& value, OptionSpelling spelling) {
  const PatchOptionSpec* s = specOf(key);
  if (!s) throw InputError("unknown patch option '" + key + "'");
  try {
    if (key == "precision") {
      o.precision = parsePrecision(value);
    } else if (key == "normals") {
      o.normals = parseNormalMode(value);
    } else if (key == "cross_tangent") {
      o.crossTangent = parseCrossTangent(value);
    } else if (key == "orient") {
      if (value != "outward" && value != "keep") bad(*s, spelling, value);
      o.keepOrientation = value == "keep";
    } else if (key == "cage") {
      o.cage = parseCageMode(value);
    } else if (key == "creases") {
      parseCreaseMarks(value, o.creases);
    } else {  // crease_angle
      char* end = nullptr;
      const double degrees = std::strtod(value.c_str(), &end);
      if (value.empty() || *end != '\0') bad(*s, spelling, value);
      setCreaseAngle(o, degrees, spelling);
    }
  } catch (const InputError&) {
    bad(*s, spelling, value);  // one message, whoever parsed it
  }
}

void setCreaseAngle(PatchOptions& o, double degrees, OptionSpelling spelling) {
  CreaseOptions c = o.creases;
  c.angleDeg = degrees;
  try {
    checkCreaseOptions(c);
  } catch (const InputError&) {
    char v[32];
    std::snprintf(v, sizeof v, "%g", degrees);
    bad(kPatchOptionSpecs[6], spelling, v);
  }
  o.creases.angleDeg = degrees;
}

PatchOptions parsePatchOptions(const PatchOptionText& t, OptionSpelling spelling) {
  PatchOptions o;
  setPatchOption(o, "precision", t.precision, spelling);
  setPatchOption(o, "normals", t.normals, spelling);
  setPatchOption(o, "cross_tangent", t.crossTangent, spelling);
  setPatchOption(o, "orient", t.orient, spelling);
  setPatchOption(o, "cage", t.cage, spelling);
  setPatchOption(o, "creases", t.creases, spelling);
  setCreaseAngle(o, t.creaseAngle, spelling);
  return o;
}

PatchOptionText patchOptionText(const PatchOptions& o) {
  PatchOptionText t;
  t.precision = toString(o.precision);
  t.normals = toString(o.normals);
  t.crossTangent = toString(o.crossTangent);
  t.orient = o.keepOrientation ? "keep" : "outward";
  t.cage = toString(o.cage);
  t.creases = creaseMarksText(o.creases);
  t.creaseAngle = o.creases.angleDeg;
  return t;
}

}  // namespace sf
