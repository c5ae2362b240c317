// Operating conditions from the options of a case (rcfd run) or of a
// database being made (rcfd synth, rcfd build).
#include "rcfd/database.hpp"
#include "base/petsc_compat.hpp"

#include <cmath>

namespace rcfd {

PetscErrorCode OperatingConditions::fromOptions(MPI_Comm comm, OperatingConditions *c) {
  struct Entry {
    const char *option, *help;
    double *value;
  };
  const Entry entries[] = {
      {"-superficial_velocity", "Superficial gas velocity u_sup [m/s] (nan: not given; a run then uses the database's, else 1.1)",
       &c->superficialVelocity},
      {"-gas_density", "Gas density rho_g [kg/m^3] (nan: not given; a run then uses the database's, else 1.189)",
       &c->gasDensity},
      {"-gas_kinematic_viscosity",
       "Gas kinematic viscosity nu [m^2/s], mu = rho_g nu (nan: not given; a run then uses the database's, else 1e-5)",
       &c->gasKinematicViscosity},
  };
  PetscFunctionBeginUser;
  PetscOptionsBegin(comm, nullptr, "Operating conditions of the bed", "rcfd");
  for (const Entry &e : entries) {
    PetscReal v = *e.value;
    PetscBool set = PETSC_FALSE;
    PetscCall(PetscOptionsReal(e.option, e.help, "", v, &v, &set));
    if (!set) continue;
    PetscCheck(v > 0 && std::isfinite(v), comm, PETSC_ERR_USER_INPUT,
               "%s must be a positive number, got %g", e.option, (double)v);
    *e.value = v;
  }
  PetscOptionsEnd();
  PetscFunctionReturn(PETSC_SUCCESS);
}

} // namespace rcfd
