// Bed dynamics and the distance between two databases (paper Sec. 3.3).
#pragma once

#include "rcfd/database.hpp"

#include <vector>

namespace rcfd {

/// Delta z_CoG = mean |z_CoG(t) - mean z_CoG| over a series of the bed's centre of
/// gravity [m].  The paper prints the mean of z_CoG - mean z_CoG without the absolute
/// value, which is zero by construction; the absolute value is what it measures.
/// Throws std::invalid_argument for an empty series or a non-finite value.
double bedDynamics(const std::vector<double> &zCog);

/// Delta DB = |a - b| / b: the relative difference of the bed dynamics a of one
/// database (or reference) and b of the other, the second named being the denominator.
/// The paper's (1 - |a - b|) 100 % mixes metres with a pure number; its Table 6 values
/// read as this relative difference.  Throws std::invalid_argument when b is not positive.
double databaseDistance(double a, double b);

/// Collective: the bed's centre of gravity of every frame of a database from its alpha_s,
/// sum(alpha_s V h) / sum(alpha_s V), h the height along the vertical (against gravity) [m],
/// on every rank.  With bedDynamics() it gives a database's Delta z_CoG.
PetscErrorCode databaseBedCentres(const Database &db, std::vector<double> *zCog);

} // namespace rcfd
