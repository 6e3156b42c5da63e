// SPDX-License-Identifier: Apache-2.0
#include <smoothforce/patch/patch_option_text.h>

#include <iterator>

#include <smoothforce/base/error.h>

namespace sf {

const PatchOptionSpec kPatchOptionSpecs[8] = {
    {"precision", "--precision", OptionType::Text, "float|double", "precision of the patch records"},
    {"normals", "--normals", OptionType::Text, "auto|file|angle|area", "vertex normals"},
    {"cross_tangent", "--cross-tangent", OptionType::Text, "corrected|paper|blend", "cross-tangent construction"},
    {"orient", "--orient", OptionType::Text, "outward|keep",
     "turn faces against their neighbours into line, flip closed meshes whose faces point inward"},
    {"cage", "--cage", OptionType::Text, "none|catmull-clark", "read the mesh as a subdivision cage"},
    {"creases", "--creases", OptionType::Text, "a list of tags, groups, normals (each once), or none",
     "which marks make crease edges"},
    {"crease_angle", "--crease-angle", OptionType::Number, "degrees in [0, 180) (0: off)",
     "also a crease where adjacent faces turn by more than this angle"},
    {"fold_repair", "--fold-repair", OptionType::Text, "off|on|search",
     "on: cut flat polygons with a reflex or straight corner into convex pieces; search: also turn vertex normals "
     "where that removes surface faults"},
};

namespace {

const PatchOptionSpec* specOf(const std::string& key) {
  return findOptionSpec(kPatchOptionSpecs, std::size(kPatchOptionSpecs), key);
}

[[noreturn]] void bad(const PatchOptionSpec& s, OptionSpelling spelling, const std::string& value) {
  throwBadOption(s, spelling, value);
}

}  // namespace

void setPatchOption(PatchOptions& o, const std::string& key, const std::string& value, OptionSpelling spelling) {
  const PatchOptionSpec* s = specOf(key);
  if (!s) throwUnknownOption("patch", key);
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
    } else if (key == "fold_repair") {
      o.foldRepair = parseFoldRepairMode(value);
    } else {  // crease_angle
      setCreaseAngle(o, parseOptionNumber(*s, spelling, value), spelling);
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
    bad(kPatchOptionSpecs[6], spelling, optionNumberText(degrees));
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
  setPatchOption(o, "fold_repair", t.foldRepair, spelling);
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
  t.foldRepair = toString(o.foldRepair);
  return t;
}

}  // namespace sf
