// Synthetic bed generator: exact shifts (column-stochastic, T_k alpha_k =
// alpha_k+1), bounded alpha_s, conserved solid, an empty freeboard, rising
// voids, determinism, and clear errors for bad options; the operating point
// (two-phase scaling: more excess gas, more bubble volume) and stationarity
// over the recorded span (halves, frame use of a random path) and the standard
// errors of the halves on series of known autocorrelation.
#include "check.hpp"
#include "observable/bed_dynamics.hpp"
#include "base/random.hpp"
#include "analysis/span_statistics.hpp"
#include "builders/synthetic/synthetic_bed.hpp"
#include "builders/synthetic/two_phase_scaling.hpp"
#include "path/frame_path.hpp"
#include "path/recurrence.hpp"
#include "rcfd/path.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <vector>

using rcfd::CsrMatrix;
using rcfd::FrameRecord;
using rcfd::SyntheticBedOptions;

namespace {

/// 10 x 4 x 30 cells of 5 mm, a 6 cm bed, small bubbles.
SyntheticBedOptions smallBed() {
  SyntheticBedOptions o;
  o.box.nx = 10;
  o.box.ny = 4;
  o.box.nz = 30;
  o.box.length = {0.05, 0.02, 0.15};
  o.numFrames = 20;
  o.bedHeight = 0.06;
  o.initialDiameter = 0.01;
  o.maxDiameter = 0.02;
  o.growthLength = 0.03;
  o.nucleationRate = 20000.0;
  o.warmUpTime = 0.3;
  o.nucleationStrips = 4; // strips about 1.25 cm wide, a bubble's size here
  o.nucleation = SyntheticBedOptions::Nucleation::steady;
  return o;
}

std::vector<FrameRecord> generate(const SyntheticBedOptions &o, rcfd::SyntheticBedReport *report) {
  std::vector<FrameRecord> frames;
  const auto r = rcfd::generateSyntheticBed(o, [&](const FrameRecord &f) { frames.push_back(f); });
  if (report) *report = r;
  return frames;
}

void checkShift(const CsrMatrix &T, int n) {
  RCFD_CHECK(T.n == n);
  RCFD_CHECK(static_cast<int>(T.rowPtr.size()) == n + 1);
  std::vector<double> colSum(n, 0.0);
  bool entriesOk = true, sortedOk = true;
  for (int r = 0; r < n; ++r)
    for (int64_t e = T.rowPtr[r]; e < T.rowPtr[r + 1]; ++e) {
      colSum[T.col[e]] += T.val[e];
      entriesOk = entriesOk && T.val[e] > 0.0 && T.val[e] <= 1.0;
      if (e > T.rowPtr[r]) sortedOk = sortedOk && T.col[e - 1] < T.col[e];
    }
  RCFD_CHECK(entriesOk);
  RCFD_CHECK(sortedOk);
  double worst = 0.0;
  for (double s : colSum) worst = std::fmax(worst, std::fabs(s - 1.0));
  RCFD_CHECK(worst <= 1e-14);
}

std::vector<double> apply(const CsrMatrix &T, const std::vector<double> &x) {
  std::vector<double> y(T.n, 0.0);
  for (int r = 0; r < T.n; ++r)
    for (int64_t e = T.rowPtr[r]; e < T.rowPtr[r + 1]; ++e) y[r] += T.val[e] * x[T.col[e]];
  return y;
}

/// A cell with alpha_s < 0.2 that has dense solid somewhere above it in its
/// column: a void inside the bed rather than the freeboard.
bool hasVoidBelowSurface(const std::vector<double> &alpha, const rcfd::BoxSpec &b, double dense) {
  for (int j = 0; j < b.ny; ++j)
    for (int i = 0; i < b.nx; ++i) {
      bool solidAbove = false;
      for (int k = b.nz - 1; k >= 0; --k) {
        const double a = alpha[b.cellIndex(i, j, k)];
        if (solidAbove && a < 0.2) return true;
        solidAbove = solidAbove || a >= dense;
      }
    }
  return false;
}

void testFrames(const SyntheticBedOptions &o) {
  const rcfd::BoxSpec &b = o.box;
  const int n = b.numCells();
  const double cellVolume = b.spacing()[0] * b.spacing()[1] * b.spacing()[2];
  rcfd::SyntheticBedReport report;
  const std::vector<FrameRecord> frames = generate(o, &report);
  RCFD_CHECK(static_cast<int>(frames.size()) == o.numFrames);
  RCFD_CHECK(report.parcels > 0);
  RCFD_CHECK_CLOSE(report.solidVolume, report.parcels * report.parcelVolume, 1e-14);
  RCFD_CHECK(report.maxAlpha <= o.packing + 1e-15);
  RCFD_CHECK(report.bubblesNucleated > 0);
  RCFD_CHECK(std::isfinite(report.wrapMismatchL1) && report.wrapMismatchL1 >= 0.0);
  RCFD_CHECK(report.meanBedHeight > 0.5 * o.bedHeight && report.meanBedHeight < b.length[2]);

  bool anyVoid = false, anyMove = false;
  double worstIdentity = 0.0;
  for (size_t k = 0; k < frames.size(); ++k) {
    const FrameRecord &f = frames[k];
    RCFD_CHECK(static_cast<int>(f.alphaS.size()) == n);
    checkShift(f.shift, n);

    bool inRange = true;
    double solid = 0.0;
    for (double a : f.alphaS) {
      inRange = inRange && a >= 0.0 && a < 0.65; // also false for NaN
      solid += a * cellVolume;
    }
    RCFD_CHECK(inRange);
    RCFD_CHECK_CLOSE(solid / report.solidVolume, 1.0, 1e-12);

    // Freeboard: the top five layers stay empty.
    bool freeboardEmpty = true;
    for (int kz = b.nz - 5; kz < b.nz; ++kz)
      for (int j = 0; j < b.ny; ++j)
        for (int i = 0; i < b.nx; ++i) freeboardEmpty = freeboardEmpty && f.alphaS[b.cellIndex(i, j, kz)] == 0.0;
    RCFD_CHECK(freeboardEmpty);

    anyVoid = anyVoid || hasVoidBelowSurface(f.alphaS, b, 0.9 * o.packing);
    for (int r = 0; r < n && !anyMove; ++r)
      for (int64_t e = f.shift.rowPtr[r]; e < f.shift.rowPtr[r + 1]; ++e)
        anyMove = anyMove || (f.shift.col[e] != r && f.alphaS[f.shift.col[e]] > 0.0);

    if (k + 1 < frames.size()) {
      const std::vector<double> moved = apply(f.shift, f.alphaS);
      for (int c = 0; c < n; ++c)
        worstIdentity = std::fmax(worstIdentity, std::fabs(moved[c] - frames[k + 1].alphaS[c]));
    }
  }
  RCFD_CHECK(worstIdentity <= 1e-12);
  RCFD_CHECK(anyVoid);
  RCFD_CHECK(anyMove);
}

bool sameFrames(const std::vector<FrameRecord> &a, const std::vector<FrameRecord> &b) {
  if (a.size() != b.size()) return false;
  for (size_t k = 0; k < a.size(); ++k)
    if (a[k].alphaS != b[k].alphaS || a[k].shift.rowPtr != b[k].shift.rowPtr ||
        a[k].shift.col != b[k].shift.col || a[k].shift.val != b[k].shift.val)
      return false;
  return true;
}

void testDeterminism() {
  SyntheticBedOptions o = smallBed();
  o.numFrames = 8;
  const auto first = generate(o, nullptr), second = generate(o, nullptr);
  RCFD_CHECK(sameFrames(first, second));
  o.seed = 2;
  RCFD_CHECK(!sameFrames(first, generate(o, nullptr)));
}

void testTwoPhaseScaling() {
  const rcfd::TwoPhaseScaling same = rcfd::twoPhaseScaling(1.0);
  RCFD_CHECK(same.diameterFactor == 1.0 && same.nucleationFactor == 1.0 && same.holdUpFactor == 1.0);
  SyntheticBedOptions o = smallBed();
  rcfd::applyTwoPhaseScaling(same, &o);
  RCFD_CHECK(o.initialDiameter == smallBed().initialDiameter && o.nucleationRate == smallBed().nucleationRate);
  const double r = 1.764;
  const rcfd::TwoPhaseScaling s = rcfd::twoPhaseScaling(r);
  RCFD_CHECK_CLOSE(s.diameterFactor, std::pow(r, 0.4), 1e-14);   // Darton: D ~ (U - U_mf)^0.4
  RCFD_CHECK_CLOSE(s.nucleationFactor, std::pow(r, -0.2), 1e-14); // bubble flow ~ U - U_mf
  RCFD_CHECK_CLOSE(s.holdUpFactor, std::pow(r, 0.8), 1e-14);
  rcfd::applyTwoPhaseScaling(s, &o);
  const double flow = o.nucleationRate * std::pow(o.initialDiameter, 3.0);
  const double flow0 = smallBed().nucleationRate * std::pow(smallBed().initialDiameter, 3.0);
  RCFD_CHECK_CLOSE(flow / flow0, r, 1e-13);
  for (double bad : {0.0, -1.0, std::nan(""), HUGE_VAL}) {
    bool refused = false;
    try {
      rcfd::twoPhaseScaling(bad);
    } catch (const std::invalid_argument &) {
      refused = true;
    }
    RCFD_CHECK(refused);
  }
}

/// The small bed at excess-gas ratio r (two-phase scaling), long enough for means.
SyntheticBedOptions smallBedAt(double r, int frames) {
  SyntheticBedOptions o = smallBed();
  o.numFrames = frames;
  o.warmUpTime = 1.0;
  rcfd::applyTwoPhaseScaling(rcfd::twoPhaseScaling(r), &o);
  return o;
}

// More excess gas, more bubble volume: the bed expands more and its centre of
// gravity moves more.  Two-phase theory predicts the hold-up as (U - U_mf)^0.8;
// the kinematic bed's expansion follows with an exponent of 0.6 (measured);
// accepted: 0.4 to 1.2.  The frames stay exact at both points.
void testExcessGas() {
  rcfd::SyntheticBedReport low, high;
  const SyntheticBedOptions lo = smallBedAt(0.3, 200), hi = smallBedAt(3.0, 200);
  generate(lo, &low);
  generate(hi, &high);
  const double expansionLow = low.meanBedHeight / lo.bedHeight - 1.0;
  const double expansionHigh = high.meanBedHeight / hi.bedHeight - 1.0;
  RCFD_CHECK(expansionLow > 0.0 && expansionHigh > expansionLow);
  const double exponent = std::log(expansionHigh / expansionLow) / std::log(3.0 / 0.3);
  RCFD_CHECK(exponent > 0.4 && exponent < 1.2);
  RCFD_CHECK(rcfd::bedDynamics(high.centreOfGravity) > 2.0 * rcfd::bedDynamics(low.centreOfGravity));
  SyntheticBedOptions exact = smallBedAt(3.0, 20);
  exact.warmUpTime = 0.3;
  testFrames(exact);
}

double meanOf(const std::vector<double> &v, size_t first, size_t last) {
  double sum = 0.0;
  for (size_t k = first; k < last; ++k) sum += v[k];
  return sum / static_cast<double>(last - first);
}

/// Largest over smallest number of steps a 12,000-step random path (today's
/// rule, 4 candidates as in runs) spends in each quarter of the frames.
double frameUseRatio(const std::vector<FrameRecord> &frames, std::uint64_t seed) {
  std::vector<const double *> alpha;
  for (const FrameRecord &f : frames) alpha.push_back(f.alphaS.data());
  const std::vector<double> volume(frames[0].alphaS.size(), 1.0);
  const std::vector<double> R =
      rcfd::recurrenceMatrix(rcfd::RecurrenceNorm::SqrDiff, alpha, volume.data(), volume.size());
  rcfd::PathParams params;
  params.seed = seed;
  params.candidates = 4;
  const int K = static_cast<int>(frames.size());
  auto path = rcfd::makeFramePath("random", K, R, params);
  std::vector<int> use(4, 0);
  for (int step = 0; step <= 12000; ++step) ++use[4 * path->next() / K];
  return static_cast<double>(*std::max_element(use.begin(), use.end())) /
         std::max(1, *std::min_element(use.begin(), use.end()));
}

// Stationary after the warm-up (issue 15's targets on a small bed): the mean
// bed height of the two halves of the span within 2 %, and a random path's
// frame use within a factor 2 of uniform.  (Delta z_CoG of the halves is not
// asserted: over a span of a few bubble transit times it is a noisy estimate,
// docs/synthetic.md.)
void testStationarity() {
  for (std::uint64_t seed : {1u, 2u}) {
    SyntheticBedOptions o = smallBedAt(1.0, 400);
    o.seed = seed;
    rcfd::SyntheticBedReport report;
    const std::vector<FrameRecord> frames = generate(o, &report);
    const std::vector<double> &h = report.surfaceHeight;
    RCFD_CHECK_CLOSE(meanOf(h, 0, 200) / meanOf(h, 200, 400), 1.0, 0.02);
    RCFD_CHECK(frameUseRatio(frames, 1) <= 2.0);
  }
}

// Without frames the bed moves the same: the series-only run gives the report's
// series bit for bit.
void testSeriesOnly() {
  SyntheticBedOptions o = smallBed();
  o.numFrames = 30;
  rcfd::SyntheticBedReport withFrames;
  generate(o, &withFrames);
  const rcfd::SyntheticBedReport seriesOnly = rcfd::generateSyntheticBedSeries(o);
  RCFD_CHECK(seriesOnly.surfaceHeight == withFrames.surfaceHeight);
  RCFD_CHECK(seriesOnly.centreOfGravity == withFrames.centreOfGravity);
  RCFD_CHECK(seriesOnly.wrapMismatchL1 == withFrames.wrapMismatchL1);
}

/// x_k = mean + a_k, a_k = phi a_k-1 + e_k with e_k uniform in [-1, 1) (variance 1/3),
/// started in its stationary spread: var(a) = (1/3) / (1 - phi^2), integrated
/// autocorrelation time tau = 1 + 2 sum phi^k = (1 + phi) / (1 - phi).
std::vector<double> autoregressive(size_t n, double phi, double mean, std::uint64_t seed) {
  rcfd::Xoshiro256 random(seed);
  std::vector<double> x(n);
  double a = 0.0;
  for (int k = 0; k < 2000; ++k) a = phi * a + (2.0 * random.uniform() - 1.0);
  for (double &v : x) {
    a = phi * a + (2.0 * random.uniform() - 1.0);
    v = mean + a;
  }
  return x;
}

// The standard errors rcfd synth prints next to the halves (batch means over the
// span), on AR(1) series of known integrated time tau = (1 + 0.9) / 0.1 = 19 frames.
void testHalvesStandardError() {
  // tau itself from 10^6 frames in 250 batches of 4000 frames (>> tau, so unbiased to
  // 2 phi / (m (1 - phi)^2) = 0.05 frames): the batch variance has 249 degrees of
  // freedom, a relative standard deviation of sqrt(2 / 249) = 9 %; 30 % is over 3 of them.
  const std::vector<double> x = autoregressive(1000000, 0.9, 0.0, 7);
  RCFD_CHECK_CLOSE(rcfd::integratedTimeByBatches(x, 250), 19.0, 0.3); // relative to 19

  // Spans of 300 frames, as rcfd synth's default (6 batches of 50 frames): over 4000
  // independent spans the halves of the mean differ by an rms of sqrt(var(m2 - m1)) / mean
  // = 6.3 % (AR(1) exactly: var of a 150-frame mean 17.8 var(a) / 150 less the halves'
  // covariance), known to 1/sqrt(2 x 4000) = 1.1 %.  Batches of 50 frames see
  // tau(50) = 19 - 2 phi / (50 (1 - phi)^2) = 15.4 of the 18.4 that a 300-frame mean
  // has, so the printed error is expected sqrt(15.4 / 18.4 x 17.8 / 17.3) = 0.93 of the rms:
  // the band [0.8, 1.1] holds that with room for the 1.1 % and the estimator's own
  // scatter; ignoring the correlation (tau = 1) would give 0.24, batches not divided out
  // sqrt(6) = 2.4.
  const std::vector<double> y = autoregressive(4000 * 300, 0.9, 10.0, 11);
  double observed = 0.0, printed = 0.0, observedDeviation = 0.0, printedDeviation = 0.0;
  int within = 0;
  for (size_t s = 0; s < 4000; ++s) {
    const std::vector<double> span(y.begin() + s * 300, y.begin() + (s + 1) * 300);
    const rcfd::HalvesDifference d = rcfd::halvesOfMean(span);
    observed += d.relative * d.relative;
    printed += d.standardError * d.standardError;
    within += std::fabs(d.relative) <= 2.0 * d.standardError;
    const rcfd::HalvesDifference dev = rcfd::halvesOfMeanDeviation(span);
    observedDeviation += dev.relative * dev.relative;
    printedDeviation += dev.standardError * dev.standardError;
  }
  RCFD_CHECK_CLOSE(std::sqrt(observed / 4000), 0.063, 0.005);
  const double ratio = std::sqrt(printed / observed);
  RCFD_CHECK(ratio > 0.8 && ratio < 1.1);
  // |difference| <= 2 printed standard errors in at least the 90 % of spans that
  // Student's t with 5 degrees of freedom gives (P(|t_5| <= 2) = 0.898); more in fact
  // (97 %), because the batch means contain the halves' difference itself; ignoring
  // the correlation would give about 40 %.
  RCFD_CHECK(within >= 0.9 * 4000);
  // Delta z_CoG of the halves (mean |z - mean| of each half): the same estimator on
  // |z - mean of the span|, whose correlation is shorter (rho^2-like for a Gaussian-like a).
  const double ratioDeviation = std::sqrt(printedDeviation / observedDeviation);
  RCFD_CHECK(ratioDeviation > 0.8 && ratioDeviation < 1.2);

  // The halves themselves: means and mean absolute deviations of [0, n/2) and [n/2, n).
  const rcfd::HalvesDifference m = rcfd::halvesOfMean({1.0, 3.0, 2.0, 6.0});
  RCFD_CHECK(m.first == 2.0 && m.second == 4.0 && m.relative == 1.0 && std::isnan(m.standardError));
  const rcfd::HalvesDifference dev = rcfd::halvesOfMeanDeviation({1.0, 3.0, 2.0, 6.0});
  RCFD_CHECK(dev.first == 1.0 && dev.second == 2.0 && dev.relative == 1.0);
  RCFD_CHECK(std::isnan(rcfd::varianceOfMeanByBatches({1.0, 2.0, 3.0}, 2)));
}

template <class Change> bool rejects(Change change) {
  SyntheticBedOptions o = smallBed();
  change(o);
  try {
    rcfd::generateSyntheticBed(o, [](const FrameRecord &) {});
  } catch (const std::invalid_argument &) {
    return true;
  }
  return false;
}

void testBadOptions() {
  RCFD_CHECK(rejects([](SyntheticBedOptions &o) { o.bedHeight = 0.2; }));      // above the box
  RCFD_CHECK(rejects([](SyntheticBedOptions &o) { o.bedHeight = 0.12; }));     // no freeboard left
  RCFD_CHECK(rejects([](SyntheticBedOptions &o) { o.dtRec = 0.0; }));
  RCFD_CHECK(rejects([](SyntheticBedOptions &o) { o.numFrames = 0; }));
  RCFD_CHECK(rejects([](SyntheticBedOptions &o) { o.packing = 0.7; }));
  RCFD_CHECK(rejects([](SyntheticBedOptions &o) { o.maxDiameter = 0.005; }));  // below initial
  RCFD_CHECK(rejects([](SyntheticBedOptions &o) { o.wakeFraction = 0.6; }));
  RCFD_CHECK(rejects([](SyntheticBedOptions &o) { o.nucleationStrips = 0; }));
  // More than 10 m/s of gas in new bubbles (the option fuzz's 1e9 per s and m^2 never ended).
  RCFD_CHECK(rejects([](SyntheticBedOptions &o) {
    o.nucleationRate = 1.001 * 10.0 / (std::acos(-1.0) / 6.0 * std::pow(o.initialDiameter, 3));
  }));
  bool emptySink = false;
  try {
    rcfd::generateSyntheticBed(smallBed(), rcfd::FrameSink());
  } catch (const std::invalid_argument &) {
    emptySink = true;
  }
  RCFD_CHECK(emptySink);
}

} // namespace

int main() {
  testFrames(smallBed());
  testFrames([] {
    SyntheticBedOptions o = smallBed();
    o.nucleation = SyntheticBedOptions::Nucleation::poisson;
    return o;
  }());
  testTwoPhaseScaling();
  testExcessGas();
  testStationarity();
  testSeriesOnly();
  testHalvesStandardError();
  testDeterminism();
  testBadOptions();
  return RCFD_TEST_RESULT();
}
