// Order-dependent hash of 64-bit words, for the fingerprints of frame paths
// (saved with a path's state so that a restart refuses another configuration).
#pragma once

#include "base/random.hpp"

#include <cstdint>
#include <cstring>
#include <string>

namespace rcfd {

/// Order-dependent hash of 64-bit words.
class Hasher {
public:
  void add(std::uint64_t v) {
    std::uint64_t x = h_ ^ v;
    h_ = splitmix64(x);
  }
  void add(double v) {
    std::uint64_t bits;
    std::memcpy(&bits, &v, sizeof bits);
    add(bits);
  }
  void add(const std::string &s) {
    add(static_cast<std::uint64_t>(s.size()));
    for (unsigned char c : s) add(static_cast<std::uint64_t>(c));
  }
  std::uint64_t value() const { return h_; }

private:
  std::uint64_t h_ = 0x72636664ULL;
};

} // namespace rcfd
