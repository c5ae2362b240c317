// Minimal assertion helpers for rcfd's CTest executables: each failed check
// prints where and why, and the test exits non-zero at the end.
#pragma once

#include <cmath>
#include <cstdio>
#include <exception>
#include <string>

namespace rcfd::test {

inline int &failures() {
  static int n = 0;
  return n;
}

inline void fail(const char *file, int line, const std::string &what) {
  std::fprintf(stderr, "%s:%d: check failed: %s\n", file, line, what.c_str());
  ++failures();
}

/// Relative-or-absolute closeness: |a - b| <= tol * max(1, |a|, |b|).
inline bool close(double a, double b, double tol) {
  const double scale = std::fmax(1.0, std::fmax(std::fabs(a), std::fabs(b)));
  return std::fabs(a - b) <= tol * scale;
}

/// A value in a message: every digit that tells it from its neighbour (%.17g),
/// or, for a tolerance, three significant digits (%.3g), so that 1e-14 is not 0.000000.
inline std::string digits(double v, const char *format = "%.17g") {
  char text[40];
  std::snprintf(text, sizeof text, format, v);
  return text;
}

/// The message of a failed RCFD_CHECK_CLOSE.
inline std::string closeFailure(const char *aText, double a, const char *bText, double b, double tol) {
  return std::string(aText) + " = " + digits(a) + ", " + bText + " = " + digits(b) + ", tol " +
         digits(tol, "%.3g");
}

/// Whether f() throws an exception whose message contains `text`; prints
/// the message when it does not.
template <typename F> bool throwsWith(F &&f, const std::string &text) {
  try {
    f();
  } catch (const std::exception &e) {
    if (std::string(e.what()).find(text) != std::string::npos) return true;
    std::fprintf(stderr, "unexpected message: %s\n", e.what());
    return false;
  }
  std::fprintf(stderr, "no exception; expected: %s\n", text.c_str());
  return false;
}

} // namespace rcfd::test

#define RCFD_CHECK(cond)                                                                           \
  do {                                                                                             \
    if (!(cond)) rcfd::test::fail(__FILE__, __LINE__, #cond);                                      \
  } while (0)

#define RCFD_CHECK_CLOSE(a, b, tol)                                                                \
  do {                                                                                             \
    const double rcfd_a_ = (a), rcfd_b_ = (b);                                                     \
    if (!rcfd::test::close(rcfd_a_, rcfd_b_, (tol)))                                               \
      rcfd::test::fail(__FILE__, __LINE__, rcfd::test::closeFailure(#a, rcfd_a_, #b, rcfd_b_, (tol))); \
  } while (0)

/// Exit status for main(): 0 when every check passed.
#define RCFD_TEST_RESULT() (rcfd::test::failures() == 0 ? 0 : 1)
