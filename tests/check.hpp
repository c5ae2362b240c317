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
      rcfd::test::fail(__FILE__, __LINE__,                                                         \
                       std::string(#a " = ") + std::to_string(rcfd_a_) + ", " #b " = " +           \
                           std::to_string(rcfd_b_) + ", tol " + std::to_string(tol));              \
  } while (0)

/// Exit status for main(): 0 when every check passed.
#define RCFD_TEST_RESULT() (rcfd::test::failures() == 0 ? 0 : 1)
