// The paper's cylinder (input/cylinder_*.yaml) as the tests of mechanisms run it: its coarse
// P1 mesh in the compressible silicone the decks had before they became Dragon Skin 10 on P2
// (E 200 kPa, nu 0.45; 1,164 dofs against the decks' 6,957). These tests check a mechanism
// (a cavity's constraint, the column method, the controller, restart, output) against a
// reference of their own, which holds on either; the decks as shipped are tested in
// solvers/mpi_test_cavities.cpp (Cavities.VolumeControlReachesItsVolumeAndWaterWeighs).
#pragma once

#include <string>
#include <vector>

namespace hs_test {

inline const std::vector<std::string> kCoarseCylinder = {"mesh.order=1", "materials[0].E=2.0e5",
                                                         "materials[0].nu=0.45"};

// The deck's overrides: the coarse cylinder's, then the test's own, which win.
inline std::vector<std::string> coarse_cylinder(const std::vector<std::string>& overrides = {}) {
  std::vector<std::string> all = kCoarseCylinder;
  all.insert(all.end(), overrides.begin(), overrides.end());
  return all;
}

// The same as command-line arguments, with a space after each.
inline std::string coarse_cylinder_args() {
  std::string args;
  for (const std::string& o : kCoarseCylinder) args += "--set " + o + " ";
  return args;
}

}  // namespace hs_test
