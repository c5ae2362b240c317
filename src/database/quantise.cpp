#include "database/quantise.hpp"
#include "rcfd/database.hpp"

#include <algorithm>
#include <cmath>
#include <numeric>
#include <stdexcept>
#include <string>

namespace rcfd {

void quantiseWeights(CsrMatrix *T, int bits) {
  if (bits < 1 || bits > kMaxWeightBits)
    throw std::invalid_argument("weight bits must be 1 to " + std::to_string(kMaxWeightBits) + ", got " +
                                std::to_string(bits));
  const int n = T->n;
  const double units = std::ldexp(1.0, bits);
  // The entries of each column (a transpose of the entry numbers).
  std::vector<int64_t> first(n + 1, 0);
  for (int32_t c : T->col) ++first[c + 1];
  std::partial_sum(first.begin(), first.end(), first.begin());
  std::vector<int64_t> entry(T->col.size()), next(first.begin(), first.end() - 1);
  for (size_t e = 0; e < T->col.size(); ++e) entry[next[T->col[e]]++] = static_cast<int64_t>(e);

  std::vector<double> numerator(T->val.size(), 0.0);
  std::vector<int64_t> order;
  for (int c = 0; c < n; ++c) {
    const int64_t *begin = entry.data() + first[c], *end = entry.data() + first[c + 1];
    double sum = 0.0;
    for (const int64_t *e = begin; e != end; ++e) sum += T->val[*e];
    if (!(sum > 0.0))
      throw std::invalid_argument("column " + std::to_string(c) + " of the shift holds no weight to quantise");
    double given = 0.0;
    for (const int64_t *e = begin; e != end; ++e) {
      numerator[*e] = std::floor(T->val[*e] / sum * units);
      given += numerator[*e];
    }
    // Units missing (or, after round-off in the shares, one too many).
    order.assign(begin, end);
    auto remainder = [&](int64_t e) { return T->val[e] / sum * units - numerator[e]; };
    std::stable_sort(order.begin(), order.end(), [&](int64_t a, int64_t b) { return remainder(a) > remainder(b); });
    for (size_t i = 0; given < units; i = (i + 1) % order.size()) numerator[order[i]] += 1.0, given += 1.0;
    for (size_t i = order.size(); given > units; i = i == 0 ? order.size() : i)
      if (numerator[order[--i]] >= 1.0) numerator[order[i]] -= 1.0, given -= 1.0;
  }
  // Rows without the entries rounded to nothing.
  CsrMatrix q;
  q.n = n;
  q.rowPtr.assign(1, 0);
  for (int r = 0; r < n; ++r) {
    for (int64_t e = T->rowPtr[r]; e < T->rowPtr[r + 1]; ++e)
      if (numerator[e] > 0.0) {
        q.col.push_back(T->col[e]);
        q.val.push_back(numerator[e] / units);
      }
    q.rowPtr.push_back(static_cast<int64_t>(q.col.size()));
  }
  *T = std::move(q);
}

} // namespace rcfd
