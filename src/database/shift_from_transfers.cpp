#include "rcfd/frames.hpp"

#include <algorithm>
#include <numeric>
#include <stdexcept>

namespace rcfd {

CsrMatrix shiftFromTransfers(int n, std::vector<int32_t> dest, std::vector<int32_t> src,
                             std::vector<double> weight) {
  if (dest.size() != src.size() || dest.size() != weight.size())
    throw std::invalid_argument("shiftFromTransfers: dest, src and weight differ in length");
  // Column totals first, so that every entry is divided by exactly the same
  // number and each column sums to one to round-off.
  std::vector<double> colTotal(n, 0.0);
  for (size_t e = 0; e < src.size(); ++e) {
    if (src[e] < 0 || src[e] >= n || dest[e] < 0 || dest[e] >= n)
      throw std::out_of_range("shiftFromTransfers: cell index outside the mesh");
    if (!(weight[e] >= 0.0)) throw std::invalid_argument("shiftFromTransfers: negative weight");
    colTotal[src[e]] += weight[e];
  }
  for (int i = 0; i < n; ++i)
    if (colTotal[i] <= 0.0) { // untouched cell: identity column
      dest.push_back(i);
      src.push_back(i);
      weight.push_back(1.0);
      colTotal[i] = 1.0;
    }
  std::vector<size_t> order(dest.size());
  std::iota(order.begin(), order.end(), size_t{0});
  std::sort(order.begin(), order.end(), [&](size_t a, size_t b) {
    return dest[a] != dest[b] ? dest[a] < dest[b] : src[a] < src[b];
  });
  CsrMatrix T;
  T.n = n;
  T.rowPtr.assign(n + 1, 0);
  for (size_t p = 0; p < order.size();) {
    const int32_t r = dest[order[p]], c = src[order[p]];
    double w = 0.0;
    for (; p < order.size() && dest[order[p]] == r && src[order[p]] == c; ++p) w += weight[order[p]];
    if (w <= 0.0) continue;
    T.col.push_back(c);
    T.val.push_back(w / colTotal[c]);
    ++T.rowPtr[r + 1];
  }
  for (int r = 0; r < n; ++r) T.rowPtr[r + 1] += T.rowPtr[r];
  return T;
}

} // namespace rcfd
