// SPDX-License-Identifier: Apache-2.0
#include <smoothforce/base/option_spec.h>

#include <cerrno>
#include <cstdio>
#include <cstdlib>

#include <smoothforce/base/error.h>

namespace sf {

const char* optionName(const OptionSpec& s, OptionSpelling spelling) {
  return spelling == OptionSpelling::Flag ? s.flag : s.key;
}

void throwUnknownOption(const char* kind, const std::string& key) {
  throw InputError(std::string("unknown ") + kind + " option '" + key + "'");
}

void throwBadOption(const OptionSpec& s, OptionSpelling spelling, const std::string& value) {
  throw InputError(std::string(optionName(s, spelling)) + ": expected " + s.values + ", got '" + value + "'");
}

std::string optionNumberText(double v) {
  char b[40];
  std::snprintf(b, sizeof b, "%g", v);
  if (std::strtod(b, nullptr) != v && v == v) std::snprintf(b, sizeof b, "%.17g", v);
  return b;
}

double parseOptionNumber(const OptionSpec& s, OptionSpelling spelling, const std::string& text) {
  char* end = nullptr;
  const double v = std::strtod(text.c_str(), &end);
  if (text.empty() || *end != '\0' || text.find_first_of(" \t\n\r\f\v") != std::string::npos)
    throwBadOption(s, spelling, text);
  return v;
}

long long parseOptionInteger(const OptionSpec& s, OptionSpelling spelling, const std::string& text, long long lo,
                             long long hi) {
  char* end = nullptr;
  errno = 0;
  const long long v = std::strtoll(text.c_str(), &end, 10);
  if (text.empty() || *end != '\0' || errno == ERANGE || v < lo || v > hi ||
      text.find_first_of(" \t\n\r\f\v") != std::string::npos)
    throwBadOption(s, spelling, text);
  return v;
}

const OptionSpec* findOptionSpec(const OptionSpec* table, size_t n, const std::string& key) {
  for (size_t i = 0; i < n; ++i)
    if (key == table[i].key) return &table[i];
  return nullptr;
}

}  // namespace sf
