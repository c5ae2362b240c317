// Random numbers that are the same on every platform, compiler and MPI rank:
// integer-only generators, so that paths and synthetic beds are reproducible
// bit for bit from their seed.
#pragma once

#include <array>
#include <cstdint>

namespace rcfd {

/// One step of splitmix64: advances `x` and returns a well-mixed word (seeding, hashing).
std::uint64_t splitmix64(std::uint64_t &x);

/// xoshiro256** (Blackman & Vigna), seeded through splitmix64.  Integer-only,
/// so its output is the same on every platform and compiler.
class Xoshiro256 {
public:
  explicit Xoshiro256(std::uint64_t seed = 0);
  std::uint64_t next();
  /// Uniform in [0, 1), 53 random bits.
  double uniform();
  /// Uniform integer in [0, n), without modulo bias; n must be > 0.
  std::uint64_t below(std::uint64_t n);
  std::array<std::uint64_t, 4> state() const { return s_; }
  /// Throws std::invalid_argument for the all-zero state, which xoshiro never leaves.
  void setState(const std::array<std::uint64_t, 4> &s);

private:
  std::array<std::uint64_t, 4> s_;
};

} // namespace rcfd
