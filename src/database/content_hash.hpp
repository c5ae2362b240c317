// The content hash that names a database: the writer stores it as the root
// attribute content_hash, the loader makes one for older files that have none
// (docs/database-format.md, "Identity").
#pragma once

#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <string>
#include <vector>

namespace rcfd {

/// FNV-1a, 64 bits, over the bytes of what is added: cheap (one pass over
/// data the writer has in memory anyway) and the same on every machine of
/// the same byte order; it names contents, it does not protect them.
class ContentHash {
public:
  void add(const void *data, std::size_t bytes) {
    const auto *p = static_cast<const unsigned char *>(data);
    for (std::size_t i = 0; i < bytes; ++i) state = (state ^ p[i]) * 1099511628211ULL;
  }
  template <typename T> void add(const std::vector<T> &values) { add(values.data(), values.size() * sizeof(T)); }
  void add(const std::string &text) { add(text.data(), text.size()); }
  std::string hex() const {
    char text[20];
    std::snprintf(text, sizeof text, "%016llx", static_cast<unsigned long long>(state));
    return text;
  }

private:
  std::uint64_t state = 14695981039346656037ULL;
};

} // namespace rcfd
