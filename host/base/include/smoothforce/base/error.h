// SPDX-License-Identifier: Apache-2.0
// Errors of SmoothForce: InputError for bad user input, and CHECK-style macros for
// invariants (programming errors) that print both operands.
#pragma once

#include <sstream>
#include <stdexcept>
#include <string>

namespace sf {

/// Error in user input (a file, an option, an element). what() names the file and line
/// (`path:line: message`) or the element (`face 12: ...`).
class InputError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// An option value that the inputs make impossible, found where the inputs are read (a sweep's
/// depth or approach that puts HIPs beyond the coordinate range, a trajectory step too long or
/// too fine for the trajectory, a scripted depth beyond the scene, options that do not go
/// together): bad input like any InputError; the CLI reports it as a usage error (exit 2).
class OptionError : public InputError {
 public:
  using InputError::InputError;
};

/// A broken invariant inside SmoothForce (a bug, not bad input), thrown by SF_CHECK*.
/// what() = "file:line: CHECK failed: <expression>" plus both operands for the comparisons.
class InternalError : public std::logic_error {
 public:
  using std::logic_error::logic_error;
};

namespace detail {
[[noreturn]] void throwCheckFailed(const char* file, int line, const std::string& what);
template <class A, class B>
[[noreturn]] void throwCheckOpFailed(const char* file, int line, const char* expr, const A& a, const B& b) {
  std::ostringstream s;
  s << expr << " (" << a << " vs. " << b << ")";
  throwCheckFailed(file, line, s.str());
}
}  // namespace detail

}  // namespace sf

/// Throws sf::InternalError naming the file, line and the failed condition. Not for the
/// servo step (it throws); not for user input (use InputError with the file, line or element).
#define SF_CHECK(cond) ((cond) ? (void)0 : ::sf::detail::throwCheckFailed(__FILE__, __LINE__, "CHECK failed: " #cond))

#define SF_CHECK_OP_(a, b, op)                                                                              \
  do {                                                                                                      \
    const auto& sf_check_a_ = (a);                                                                          \
    const auto& sf_check_b_ = (b);                                                                          \
    if (!(sf_check_a_ op sf_check_b_))                                                                      \
      ::sf::detail::throwCheckOpFailed(__FILE__, __LINE__, "CHECK failed: " #a " " #op " " #b, sf_check_a_, \
                                       sf_check_b_);                                                        \
  } while (0)
/// SF_CHECK_EQ(a, b) .. SF_CHECK_GE(a, b): as SF_CHECK(a op b), printing both values.
#define SF_CHECK_EQ(a, b) SF_CHECK_OP_(a, b, ==)
#define SF_CHECK_NE(a, b) SF_CHECK_OP_(a, b, !=)
#define SF_CHECK_LT(a, b) SF_CHECK_OP_(a, b, <)
#define SF_CHECK_LE(a, b) SF_CHECK_OP_(a, b, <=)
#define SF_CHECK_GT(a, b) SF_CHECK_OP_(a, b, >)
#define SF_CHECK_GE(a, b) SF_CHECK_OP_(a, b, >=)
