// db_compare EXACT.h5 OTHER.h5
// How close the shift matrices of OTHER come to those of EXACT, frame by
// frame over the frames both have (a test helper for scripts; serial, reads
// the HDF5 files directly).  One line per frame k:
//   k  mass  moved  tv  residual  alpha
// with m = V alpha_exact(k) and, all relative to ||m||_1:
//   mass     ||T_other m - T_exact m||_1: the bulk the two shifts deliver
//   moved    (1/2) sum_i m_i ||T_exact(:, i) - e_i||_1: share of the mass
//            that leaves its cell in the exact shift (the scale of tv)
//   tv       (1/2) sum_i m_i ||T_other(:, i) - T_exact(:, i)||_1: share of
//            the mass that OTHER sends to other cells than EXACT does
//   residual ||T_other m'_k - m'_k+1||_1 / ||m'_k||_1 with OTHER's alpha
//            (mass consistency of OTHER; empty for its last frame)
//   alpha    max_c |alpha_other(k, c) - alpha_exact(k, c)|
// The last two lines: "mean" and "max" of each column over the frames.
#include "base/h5.hpp"
#include "database/stored_frame.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <exception>
#include <string>
#include <vector>

namespace {

struct Frame {
  std::vector<double> alpha;
  std::vector<int64_t> ptr;
  std::vector<int32_t> col;
  std::vector<double> val;
};

Frame readFrame(const rcfd::h5::File &f, int k) { // full CSR in every format version
  const int cells = static_cast<int>(f.extents("/mesh/cell_volumes").at(0));
  rcfd::FrameRecord r = rcfd::readStoredFrame(f, k, cells);
  return {std::move(r.alphaS), std::move(r.shift.rowPtr), std::move(r.shift.col), std::move(r.shift.val)};
}

/// Columns of a CSR-by-rows shift: for each source, (destination, share).
std::vector<std::vector<std::pair<int, double>>> columns(const Frame &fr) {
  const int n = static_cast<int>(fr.alpha.size());
  std::vector<std::vector<std::pair<int, double>>> c(n);
  for (int j = 0; j < n; ++j)
    for (int64_t e = fr.ptr[j]; e < fr.ptr[j + 1]; ++e) c[fr.col[e]].emplace_back(j, fr.val[e]);
  for (auto &v : c) std::sort(v.begin(), v.end());
  return c;
}

std::vector<double> apply(const Frame &fr, const std::vector<double> &m) {
  std::vector<double> y(m.size(), 0.0);
  for (std::size_t j = 0; j + 1 < fr.ptr.size(); ++j)
    for (int64_t e = fr.ptr[j]; e < fr.ptr[j + 1]; ++e) y[j] += fr.val[e] * m[fr.col[e]];
  return y;
}

double l1(const std::vector<double> &a, const std::vector<double> &b) {
  double s = 0.0;
  for (std::size_t i = 0; i < a.size(); ++i) s += std::fabs(a[i] - b[i]);
  return s;
}

/// sum over i of m_i * || a(:, i) - b(:, i) ||_1 (both columns sorted).
double weightedColumnL1(const std::vector<std::vector<std::pair<int, double>>> &a,
                        const std::vector<std::vector<std::pair<int, double>>> &b,
                        const std::vector<double> &m) {
  double s = 0.0;
  for (std::size_t i = 0; i < a.size(); ++i) {
    if (!(m[i] > 0)) continue;
    double d = 0.0;
    std::size_t p = 0, q = 0;
    while (p < a[i].size() || q < b[i].size()) {
      if (q == b[i].size() || (p < a[i].size() && a[i][p].first < b[i][q].first))
        d += std::fabs(a[i][p++].second);
      else if (p == a[i].size() || b[i][q].first < a[i][p].first)
        d += std::fabs(b[i][q++].second);
      else
        d += std::fabs(a[i][p++].second - b[i][q++].second);
    }
    s += m[i] * d;
  }
  return s;
}

} // namespace

int main(int argc, char **argv) {
  if (argc != 3) {
    std::fprintf(stderr, "usage: db_compare EXACT.h5 OTHER.h5\n");
    return 2;
  }
  try {
    const auto fe = rcfd::h5::File::openRead(argv[1], MPI_COMM_NULL);
    const auto fo = rcfd::h5::File::openRead(argv[2], MPI_COMM_NULL);
    const auto ve = fe.read<double>("/mesh/cell_volumes");
    const auto vo = fo.read<double>("/mesh/cell_volumes");
    if (vo.size() != ve.size()) throw std::runtime_error("the meshes differ");
    for (std::size_t c = 0; c < ve.size(); ++c)
      if (std::fabs(vo[c] - ve[c]) > 1e-9 * ve[c]) throw std::runtime_error("the meshes differ");
    const int Ke = static_cast<int>(fe.readAttrInt("/frames", "num_frames"));
    const int Ko = static_cast<int>(fo.readAttrInt("/frames", "num_frames"));
    const int K = std::min(Ke, Ko);
    const int n = static_cast<int>(ve.size());
    std::vector<std::vector<std::pair<int, double>>> ident(n);
    for (int i = 0; i < n; ++i) ident[i] = {{i, 1.0}};
    double worst[5] = {0, 0, 0, 0, 0}, sum[5] = {0, 0, 0, 0, 0};
    int residuals = 0;
    std::printf("# k mass moved tv residual alpha\n");
    Frame next = readFrame(fo, 0);
    for (int k = 0; k < K; ++k) {
      const Frame e = readFrame(fe, k);
      const Frame o = next;
      std::vector<double> m(n), mo(n);
      double total = 0.0, totalO = 0.0, dAlpha = 0.0;
      for (int c = 0; c < n; ++c) {
        m[c] = ve[c] * e.alpha[c];
        mo[c] = ve[c] * o.alpha[c];
        total += m[c];
        totalO += mo[c];
        dAlpha = std::max(dAlpha, std::fabs(o.alpha[c] - e.alpha[c]));
      }
      const auto ce = columns(e), co = columns(o);
      const double mass = l1(::apply(o, m), ::apply(e, m)) / total;
      const double moved = 0.5 * weightedColumnL1(ce, ident, m) / total;
      const double tv = 0.5 * weightedColumnL1(co, ce, m) / total;
      double residual = -1.0;
      if (k + 1 < Ko) {
        next = readFrame(fo, k + 1);
        std::vector<double> mn(n);
        for (int c = 0; c < n; ++c) mn[c] = ve[c] * next.alpha[c];
        residual = l1(::apply(o, mo), mn) / totalO;
      }
      std::printf("%d %.6e %.6e %.6e %.6e %.3e\n", k, mass, moved, tv, residual, dAlpha);
      const double v[5] = {mass, moved, tv, residual, dAlpha};
      for (int c = 0; c < 5; ++c) worst[c] = std::max(worst[c], v[c]), sum[c] += c == 3 ? std::max(v[c], 0.0) : v[c];
      residuals += residual >= 0;
    }
    std::printf("mean %.6e %.6e %.6e %.6e %.3e\n", sum[0] / K, sum[1] / K, sum[2] / K,
                sum[3] / std::max(residuals, 1), sum[4] / K);
    std::printf("max %.6e %.6e %.6e %.6e %.3e\n", worst[0], worst[1], worst[2], worst[3], worst[4]);
  } catch (const std::exception &ex) {
    std::fprintf(stderr, "db_compare: %s\n", ex.what());
    return 1;
  }
  return 0;
}
