// What the study objects of include/rcfd/study.hpp share: a scorer's
// DeltaZScore as the public CurveAgreement, and its one-line view.
#pragma once

#include "analysis/segregation_score.hpp"
#include "rcfd/study.hpp"

namespace rcfd {

CurveAgreement agreementOf(const DeltaZScore &score);
/// "mean ... mm (reference ... mm) over [t0, t1] s: Delta_seg ... %, RMS/peak ...".
PetscErrorCode viewAgreement(PetscViewer viewer, const CurveAgreement &agreement);

} // namespace rcfd
