// SPDX-License-Identifier: Apache-2.0
// The patch options as text: the one reader and writer of them that every front end uses (the
// command line's flags, scene files' keys, the C API's sf_cache_options fields, Python's keyword
// arguments), so that each accepts the same values and rejects a bad one with the same message.
#pragma once

#include <string>

#include <smoothforce/base/option_spec.h>
#include <smoothforce/patch/patch_cache.h>

namespace sf {

/// One patch option: its key, its flag, the values it takes (as messages spell them), its help.
using PatchOptionSpec = OptionSpec;
/// Every patch option that is text or a number: precision, normals, cross_tangent, orient, cage,
/// creases, crease_angle, fold_repair.
extern const PatchOptionSpec kPatchOptionSpecs[8];

/// The patch options as text, with their defaults.
struct PatchOptionText {
  std::string precision = "double";      ///< float|double
  std::string normals = "auto";          ///< auto|file|angle|area (normals.h)
  std::string crossTangent = "corrected";  ///< corrected|paper|blend
  std::string orient =
      "outward";  ///< outward|keep: turn faces against their neighbours, flip inward-facing closed meshes
  std::string cage = "none";             ///< none|catmull-clark (cage_limit.h)
  std::string creases = "tags,groups";   ///< a list of tags, groups, normals, or none (creases.h)
  double creaseAngle = 0;                ///< degrees in [0, 180); 0: off
  std::string foldRepair = "on";         ///< off|on|search, split a synonym of on (polygon_split.h)
};

/// The options of `text`. Throws InputError "NAME: expected VALUES, got 'VALUE'" for the first
/// bad value, NAME its key or flag (spelling), VALUES as kPatchOptionSpecs gives them.
PatchOptions parsePatchOptions(const PatchOptionText& text, OptionSpelling spelling = OptionSpelling::Key);

/// Sets one option of `options` from its key (kPatchOptionSpecs; crease_angle as a decimal
/// number); throws as parsePatchOptions does, and InputError "unknown patch option 'KEY'" for a
/// key that is none of them.
void setPatchOption(PatchOptions& options, const std::string& key, const std::string& value,
                    OptionSpelling spelling = OptionSpelling::Key);

/// Sets the crease angle (degrees); throws as parsePatchOptions does.
void setCreaseAngle(PatchOptions& options, double degrees, OptionSpelling spelling = OptionSpelling::Key);

/// The text of `options` (parsePatchOptions of it gives them back).
PatchOptionText patchOptionText(const PatchOptions& options);

}  // namespace sf
