// The synthetic bed at another superficial gas velocity, by simple two-phase
// theory (docs/synthetic.md).  The bed's default bubble parameters stand for
// one operating point, u_sup = 1.1 m/s with the bi-wide inventory
// (d32 = 2.026 mm); another point scales them by the excess gas
// U - U_mf over that of the reference:
//   - the excess gas goes to bubbles (Toomey & Johnstone): the visible bubble
//     flow at the distributor, nucleation rate x (pi/6) D0^3, is proportional
//     to U - U_mf;
//   - bubble size at every height goes as (U - U_mf)^0.4 (Darton et al. 1977,
//     D = 0.54 (U - U_mf)^0.4 (h + 4 sqrt(A0))^0.8 g^-0.2): the initial and the
//     largest diameter of the growth law scale so; its length L does not;
//   - so the nucleation rate goes as (U - U_mf)^(1 - 1.2) = (U - U_mf)^-0.2;
//   - bed expansion is not set: it follows from the bubbles' hold-up, which
//     two-phase theory predicts as eps_b = (U - U_mf) / U_b ~ (U - U_mf)^0.8
//     (U_b ~ sqrt(D)); docs/synthetic.md compares.
#pragma once

#include "builders/synthetic/synthetic_bed.hpp"

namespace rcfd {

/// The superficial gas velocity the default synthetic bed stands for [m/s].
inline constexpr double kSyntheticReferenceVelocity = 1.1;
/// The Sauter diameter of the inventory it stands for [m]: the bi-wide cases'
/// 1.459 / 4.075 mm at mass shares 0.564 / 0.436.
inline constexpr double kSyntheticReferenceSauterDiameter = 2.026e-3;

/// Factors applied to the reference bed's bubble parameters.
struct TwoPhaseScaling {
  double excessRatio = 1.0;      ///< r = (U - U_mf) / (U_ref - U_mf,ref)
  double diameterFactor = 1.0;   ///< r^0.4: initialDiameter, maxDiameter
  double nucleationFactor = 1.0; ///< r^-0.2: nucleationRate
  double holdUpFactor = 1.0;     ///< r^0.8: the bubble hold-up two-phase theory predicts (not imposed)
};

/// The factors for excess-gas ratio r > 0, computed with + - * / only (Newton
/// roots), so they are the same bits with any library; r = 1 gives exactly 1.
/// Throws std::invalid_argument when r is not positive and finite.
TwoPhaseScaling twoPhaseScaling(double excessRatio);

/// Scales the bubble parameters of `options` (those of the reference point)
/// by `scaling`.  Factors of exactly 1 leave the options' bits alone.
void applyTwoPhaseScaling(const TwoPhaseScaling &scaling, SyntheticBedOptions *options);

} // namespace rcfd
