// Balancing a shift matrix towards given row totals (the Eulerian builder's
// mass correction), and the small CSR helpers it needs.
#include "database/csr.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>

namespace rcfd {
namespace {

/// Iterative proportional scaling of a column-stochastic T towards row
/// totals t of T m, in the form T = diag(r) T0 diag(c): a step scales rows
/// and renormalises columns.  Rows are grouped into the components of the
/// bipartite row-column graph (rows sharing a source column); T keeps each
/// component's total, so its target is rescaled to that total (what is left
/// is the unreachable part, visible in the raw residual).  A step is either a
/// Sinkhorn sweep (row factor t_j / y_j) or a Newton step on the row
/// log-factors: with the concave dual h(phi) = t.phi - sum_i m_i log(sum_j
/// T0_ji e^phi_j), whose gradient is t - y and whose negative Hessian is the
/// graph Laplacian H = diag(y) - sum_i m_i T(:, i) T(:, i)^T, the step solves
/// H delta = t - y by Jacobi-preconditioned conjugate gradients and is
/// halved until the residual drops.
class ProportionalScaling {
public:
  ProportionalScaling(CsrMatrix &T, const std::vector<double> &m, const std::vector<double> &target)
      : T(T), m(m), t(target), active(T.n, 0) {
    const int n = T.n;
    mTotal = 0.0;
    for (double x : m) mTotal += x;
    // Components by union-find over the rows of each occupied column.
    std::vector<int> parent(n), firstRow(n, -1);
    std::iota(parent.begin(), parent.end(), 0);
    auto find = [&](int a) {
      while (parent[a] != a) a = parent[a] = parent[parent[a]];
      return a;
    };
    for (int j = 0; j < n; ++j)
      for (int64_t e = T.rowPtr[j]; e < T.rowPtr[j + 1]; ++e) {
        const int i = T.col[e];
        if (!(m[i] > 0.0)) continue;
        active[j] = 1;
        if (firstRow[i] < 0) firstRow[i] = j;
        else parent[find(j)] = find(firstRow[i]);
      }
    multiply(T, m, y);
    std::vector<double> reach(n, 0.0), want(n, 0.0);
    for (int j = 0; j < n; ++j)
      if (active[j]) reach[find(j)] += y[j], want[find(j)] += t[j];
    for (int j = 0; j < n; ++j)
      if (active[j] && want[find(j)] > 0.0) t[j] *= reach[find(j)] / want[find(j)];
  }

  /// ||T m - t||_1 / ||m||_1 over the rows that can receive solid; updates y.
  double residual() {
    multiply(T, m, y);
    double d = 0.0;
    for (int j = 0; j < T.n; ++j)
      if (active[j]) d += std::fabs(y[j] - t[j]);
    return mTotal > 0.0 ? d / mTotal : 0.0;
  }

  void sweep() {
    std::vector<double> logFactor(T.n, 0.0);
    for (int j = 0; j < T.n; ++j)
      if (active[j] && y[j] > 0.0 && t[j] > 0.0) logFactor[j] = std::log(t[j] / y[j]);
    T.val = scaled(logFactor, 1.0);
  }

  /// False when no step length lowers the residual.
  bool newtonStep() {
    const int n = T.n;
    std::vector<double> g(n, 0.0), diag(n, 1.0);
    for (int j = 0; j < n; ++j)
      if (active[j]) g[j] = t[j] - y[j];
    // Jacobi preconditioner: H_jj = y_j - sum_i m_i T_ji^2.
    for (int j = 0; j < n; ++j) {
      if (!active[j]) continue;
      double s = (1.0 + kShift) * y[j];
      for (int64_t e = T.rowPtr[j]; e < T.rowPtr[j + 1]; ++e) s -= m[T.col[e]] * T.val[e] * T.val[e];
      diag[j] = s > 1e-12 * y[j] ? s : y[j];
    }
    const std::vector<double> delta = solve(g, diag);
    double slope = 0.0; // g . delta > 0: delta ascends h
    for (int j = 0; j < n; ++j) slope += g[j] * delta[j];
    const double before = residual();
    for (double alpha = 1.0; alpha > 1e-4; alpha *= 0.5) {
      const double gain = dualGain(delta, alpha, g);
      const std::vector<double> saved = T.val;
      T.val = scaled(delta, alpha);
      const double after = residual();
      // Armijo on the dual; near round-off the gain is noise, then the
      // residual decides.
      if (gain >= 1e-4 * alpha * slope || after < before) return true;
      T.val = saved;
    }
    residual(); // y back to the kept T
    return false;
  }

private:
  /// Entries of T with row j scaled by exp(alpha * logFactor_j), columns
  /// renormalised.
  std::vector<double> scaled(const std::vector<double> &logFactor, double alpha) const {
    std::vector<double> v = T.val, sum(T.n, 0.0);
    for (int j = 0; j < T.n; ++j) {
      if (logFactor[j] == 0.0) continue;
      const double f = std::exp(std::clamp(alpha * logFactor[j], -kMaxLogStep, kMaxLogStep));
      for (int64_t e = T.rowPtr[j]; e < T.rowPtr[j + 1]; ++e) v[e] *= f;
    }
    for (std::size_t e = 0; e < v.size(); ++e) sum[T.col[e]] += v[e];
    for (std::size_t e = 0; e < v.size(); ++e) v[e] /= sum[T.col[e]];
    return v;
  }

  /// h(phi + alpha delta) - h(phi) for the current T, computed as
  /// alpha g.delta - sum_i m_i [log(1 + u_i) - alpha (T^T delta)_i] with
  /// u_i = sum_j T_ji expm1(alpha delta_j), so that the second-order gain
  /// is not lost to cancellation.
  double dualGain(const std::vector<double> &delta, double alpha, const std::vector<double> &g) const {
    std::vector<double> u(T.n, 0.0), v(T.n, 0.0);
    for (int j = 0; j < T.n; ++j) {
      if (delta[j] == 0.0) continue;
      const double x = std::clamp(alpha * delta[j], -kMaxLogStep, kMaxLogStep);
      const double em = std::expm1(x);
      for (int64_t e = T.rowPtr[j]; e < T.rowPtr[j + 1]; ++e)
        u[T.col[e]] += T.val[e] * em, v[T.col[e]] += T.val[e] * x;
    }
    double gain = 0.0;
    for (int j = 0; j < T.n; ++j) gain += alpha * g[j] * delta[j];
    for (int i = 0; i < T.n; ++i) {
      if (!(m[i] > 0.0)) continue;
      if (!(u[i] > -1.0)) return -std::numeric_limits<double>::infinity(); // a column vanished
      gain -= m[i] * (std::log1p(u[i]) - v[i]);
    }
    return std::isfinite(gain) ? gain : -std::numeric_limits<double>::infinity();
  }

  /// H x for the current T (rows that cannot receive solid stay zero).
  void applyH(const std::vector<double> &x, std::vector<double> &out) const {
    std::vector<double> s(T.n, 0.0);
    for (int j = 0; j < T.n; ++j)
      for (int64_t e = T.rowPtr[j]; e < T.rowPtr[j + 1]; ++e) s[T.col[e]] += T.val[e] * x[j];
    out.assign(T.n, 0.0);
    for (int j = 0; j < T.n; ++j) {
      if (!active[j]) continue;
      double h = (1.0 + kShift) * y[j] * x[j];
      for (int64_t e = T.rowPtr[j]; e < T.rowPtr[j + 1]; ++e)
        h -= T.val[e] * m[T.col[e]] * s[T.col[e]];
      out[j] = h;
    }
  }

  /// Preconditioned conjugate gradients for (H + kShift diag(y)) x = b, to
  /// 1e-3 of |b| (an inexact Newton step) or kCgIterations.
  std::vector<double> solve(const std::vector<double> &b, const std::vector<double> &diag) const {
    const int n = T.n;
    std::vector<double> x(n, 0.0), r = b, z(n), p(n), q;
    auto dot = [n](const std::vector<double> &a, const std::vector<double> &c) {
      double s = 0.0;
      for (int j = 0; j < n; ++j) s += a[j] * c[j];
      return s;
    };
    for (int j = 0; j < n; ++j) z[j] = r[j] / diag[j];
    p = z;
    double rz = dot(r, z);
    const double stop = 1e-6 * dot(b, b);
    for (int k = 0; k < kCgIterations && dot(r, r) > stop; ++k) {
      applyH(p, q);
      const double pq = dot(p, q);
      if (!(pq > 0.0)) break;
      const double a = rz / pq;
      for (int j = 0; j < n; ++j) x[j] += a * p[j], r[j] -= a * q[j];
      for (int j = 0; j < n; ++j) z[j] = r[j] / diag[j];
      const double rzNext = dot(r, z);
      for (int j = 0; j < n; ++j) p[j] = z[j] + (rzNext / rz) * p[j];
      rz = rzNext;
    }
    return x;
  }

  static constexpr int kCgIterations = 300;
  static constexpr double kMaxLogStep = 100.0; // largest row log-factor of one step
  // H + kShift diag(y) is positive definite: components that are connected
  // only through vanishing entries (numerically singular) do not make the
  // step blow up, and the Newton step is barely changed.
  static constexpr double kShift = 1e-8;
  CsrMatrix &T;
  const std::vector<double> &m;
  std::vector<double> t, y;
  std::vector<char> active;
  double mTotal = 0.0;
};

} // namespace

void multiply(const CsrMatrix &T, const std::vector<double> &x, std::vector<double> &y) {
  y.assign(T.n, 0.0);
  for (int j = 0; j < T.n; ++j) {
    double s = 0.0;
    for (int64_t e = T.rowPtr[j]; e < T.rowPtr[j + 1]; ++e) s += T.val[e] * x[T.col[e]];
    y[j] = s;
  }
}

double relativeMismatch(const CsrMatrix &T, const std::vector<double> &m,
                        const std::vector<double> &target) {
  std::vector<double> y;
  multiply(T, m, y);
  double diff = 0.0, total = 0.0;
  for (int j = 0; j < T.n; ++j) diff += std::fabs(y[j] - target[j]), total += std::fabs(m[j]);
  return total > 0 ? diff / total : 0.0;
}

double scaledMismatch(const CsrMatrix &T, const std::vector<double> &m,
                      const std::vector<double> &target) {
  const double mTotal = std::accumulate(m.begin(), m.end(), 0.0);
  const double tTotal = std::accumulate(target.begin(), target.end(), 0.0);
  if (!(mTotal > 0) || !(tTotal > 0)) return 0.0;
  std::vector<double> y;
  multiply(T, m, y);
  double d = 0.0;
  for (int j = 0; j < T.n; ++j) d += std::fabs(y[j] - target[j] * (mTotal / tTotal));
  return d / mTotal;
}

int scaleToTarget(CsrMatrix &T, const std::vector<double> &m, const std::vector<double> &target,
                  int maxIterations, double tolerance) {
  ProportionalScaling scaling(T, m, target);
  int it = 0, stalls = 0;
  // Plain sweeps settle the local mismatch cheaply; when they stall (a
  // sweep removes less than a tenth of what is left), Newton steps carry
  // the long-range corrections that sweeps would take thousands of
  // iterations for.  Newton steps that remove less than a tenth twice in a
  // row mean the support cannot carry the target: stop.
  double r = scaling.residual();
  bool sweeping = true;
  while (r > tolerance && it < maxIterations && stalls < 2) {
    ++it;
    if (sweeping) {
      scaling.sweep();
      const double next = scaling.residual();
      sweeping = next < 0.9 * r;
      r = next;
    } else {
      if (!scaling.newtonStep()) break;
      const double next = scaling.residual();
      stalls = next < 0.9 * r ? 0 : stalls + 1;
      r = next;
    }
  }
  return it;
}

} // namespace rcfd
