// SPDX-License-Identifier: Apache-2.0
// What every option table of the library shares (patch_option_text.h, force_option_text.h,
// runtime/loop_option_text.h): an option's key and flag, the values it takes as messages spell
// them, and the one message a bad value gets from every front end:
//   "NAME: expected VALUES, got 'VALUE'"
// NAME its key (scene files, the C API's fields, Python's keyword arguments, the sweep's JSON)
// or its command-line flag.
#pragma once

#include <cstddef>
#include <string>

namespace sf {

/// How a front end names an option in its messages: by its key (`cross_tangent`) or by its
/// command-line flag (`--cross-tangent`).
enum class OptionSpelling { Key, Flag };

/// What an option's value is: text (a name or a list), a real number, or an integer. Front ends
/// with types (JSON, C, Python) pass numbers as numbers, the others as decimal text.
enum class OptionType { Text, Number, Integer };

/// One option: its key, its flag, its type, the values it takes (as messages spell them: range
/// and unit), and a one-line help text (the command line's, before its details).
struct OptionSpec {
  const char* key;
  const char* flag;
  OptionType type;
  const char* values;
  const char* help;
};

/// The option's name as `spelling` gives it.
const char* optionName(const OptionSpec& spec, OptionSpelling spelling);

/// Throws InputError "unknown KIND option 'KEY'".
[[noreturn]] void throwUnknownOption(const char* kind, const std::string& key);

/// Throws InputError "NAME: expected VALUES, got 'VALUE'".
[[noreturn]] void throwBadOption(const OptionSpec& spec, OptionSpelling spelling, const std::string& value);

/// The text a number is shown as in messages and written as in option text: printf's %g, or
/// all 17 significant digits where %g would not read back as the same double.
std::string optionNumberText(double value);

/// `text` as a decimal number (the whole of it, finite or not); throws as throwBadOption does
/// when it is not one.
double parseOptionNumber(const OptionSpec& spec, OptionSpelling spelling, const std::string& text);

/// `text` as a decimal integer in [lo, hi] (the whole of it); throws as throwBadOption does.
long long parseOptionInteger(const OptionSpec& spec, OptionSpelling spelling, const std::string& text, long long lo,
                             long long hi);

/// The spec of `key` in `table` (n entries), or nullptr.
const OptionSpec* findOptionSpec(const OptionSpec* table, size_t n, const std::string& key);

/// The spec of `key` in `table`; throws InputError "unknown KIND option 'KEY'" (kind: "force").
template <size_t N>
const OptionSpec& optionSpec(const OptionSpec (&table)[N], const std::string& key, const char* kind) {
  const OptionSpec* s = findOptionSpec(table, N, key);
  if (!s) throwUnknownOption(kind, key);
  return *s;
}

}  // namespace sf
