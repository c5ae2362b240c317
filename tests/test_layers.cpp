// Horizontal layers of a hand-made state: masses per layer, the bottom
// layer's Sauter diameter, the mass-median layer and the halves' size
// distributions against hand-computed numbers, on 1 and 2 ranks.
#include "check.hpp"
#include "box_meshes.hpp"
#include "fraction_sets.hpp"
#include "base/petsc_compat.hpp"
#include "state_access.hpp"

#include "state/layer_masses.hpp"

#include <cmath>

using namespace rcfd;

namespace {

PetscErrorCode run(const std::string &dir) {
  PetscFunctionBeginUser;
  // 2 x 1 x 4 cells of 0.1 m, origin 0: layer l holds cells 2l and 2l+1.
  BoxSpec s;
  s.nx = 2;
  s.ny = 1;
  s.nz = 4;
  s.length = {0.2, 0.1, 0.4};
  const Mesh mesh = rcfd::test::boxMesh(s);
  const std::string path = dir + "/layers.h5";
  test::writeIdentityDatabase(path, mesh, std::vector<double>(8, 0.5), DatabaseMetadata{});
  std::unique_ptr<Database> db;
  PetscCall(Database::load(PETSC_COMM_WORLD, path, DatabaseLoadOptions{}, &db));
  const FractionSet fractions = rcfd::test::fractionSet({1.5e-3, 3.0e-3}, {0.5, 0.5});
  FractionState state;
  PetscCall(state.create(db->layout(), 2));
  // Layer l: each of its two cells holds (l + 1) kg, split small/large as
  // l0: 0/1, l1: 1/2 small (d32 = 2 mm), l2: all small, l3: all small.
  const double share[4] = {0.0, 0.5, 1.0, 1.0};
  std::vector<double> natural(16);
  for (int c = 0; c < 8; ++c) {
    const int l = c / 2;
    natural[2 * c] = (l + 1) * share[l];
    natural[2 * c + 1] = (l + 1) * (1.0 - share[l]);
  }
  test::setNatural(*db, state, natural);
  HorizontalLayers layers;
  PetscCall(layers.setUp(*db));
  RCFD_CHECK(layers.numLayers() == 4);
  RCFD_CHECK_CLOSE(layers.height(0), 0.05, 1e-15);
  RCFD_CHECK_CLOSE(layers.height(3), 0.35, 1e-15);
  RCFD_CHECK_CLOSE(layers.volume(2), 2 * 1e-3, 1e-15);
  std::vector<double> perLayer;
  PetscCall(layers.fractionMasses(state.masses(), 2, &perLayer));
  RCFD_CHECK(perLayer.size() == 8);
  RCFD_CHECK(perLayer[0] == 0.0 && perLayer[1] == 2.0); // bottom: 2 kg large
  RCFD_CHECK(perLayer[2] == 2.0 && perLayer[3] == 2.0);
  RCFD_CHECK(perLayer[6] == 8.0 && perLayer[7] == 0.0);
  RCFD_CHECK_CLOSE(layers::sauterDiameter(perLayer, 0, fractions), 3.0e-3, 1e-15);
  RCFD_CHECK_CLOSE(layers::sauterDiameter(perLayer, 1, fractions), 2.0e-3, 1e-15);
  RCFD_CHECK_CLOSE(layers::sauterDiameter(perLayer, 3, fractions), 1.5e-3, 1e-15);
  // Layer masses 2, 4, 6, 8 of 20: the sum from the bottom reaches 10 in layer 2.
  const int median = layers::medianLayer(perLayer, 2);
  RCFD_CHECK(median == 2);
  std::vector<double> bottom, top;
  layers::halves(perLayer, 2, median, &bottom, &top);
  // Bottom: small 0 + 2 + 6 = 8, large 2 + 2 = 4 of 12.  Top: all small.
  RCFD_CHECK_CLOSE(bottom[0], 8.0 / 12.0, 1e-15);
  RCFD_CHECK_CLOSE(bottom[1], 4.0 / 12.0, 1e-15);
  RCFD_CHECK(top[0] == 1.0 && top[1] == 0.0);
  // alpha_s V per layer: 2 cells x 0.5 x 1e-3 m^3.
  std::vector<double> solid;
  PetscCall(layers.solidVolumes(db->alphaS(0), &solid));
  RCFD_CHECK(solid.size() == 4);
  RCFD_CHECK_CLOSE(solid[1], 1e-3, 1e-15);
  // An empty bed has no median; an empty half has NaN shares.
  RCFD_CHECK(layers::medianLayer(std::vector<double>(8, 0.0), 2) == -1);
  layers::halves(perLayer, 2, 3, &bottom, &top);
  RCFD_CHECK(std::isnan(top[0]) && std::isnan(top[1]));
  PetscFunctionReturn(PETSC_SUCCESS);
}

} // namespace

int main(int argc, char **argv) { return test::rankTestMain(argc, argv, "layers", run); }
