// Shipped silicone decks as the tests of mechanisms run them: in the material (and for the
// cylinder, the mesh) they had before they became Dragon Skin 10 at nu 0.4995. These tests
// check a mechanism (a cavity's constraint, the column method, the controller and its
// real-time modes, restart, output, the reduced models) against a reference of their own,
// which holds on either, at a half to a third of the nearly incompressible body's cost. The
// decks as shipped are tested in solvers/mpi_test_cavities.cpp
// (Cavities.VolumeControlReachesItsVolumeAndWaterWeighs) and solvers/mpi_test_control_decks.cpp
// (ControlDecks.FingersReachDifferentTargets, PendulumExtendsContractsAndBends).
#pragma once

#include <string>
#include <vector>

namespace hs_test {

// The paper's cylinder (input/cylinder_*.yaml) on its coarse P1 mesh, E 200 kPa, nu 0.45
// (1,164 dofs against the decks' 6,957 on P2).
inline const std::vector<std::string> kCoarseCylinder = {"mesh.order=1", "materials[0].E=2.0e5",
                                                         "materials[0].nu=0.45"};

// The fingers (input/finger_pneumatic.yaml, finger_hydraulic.yaml) in E 200 kPa, nu 0.45 (the
// displacement element), with the 30 kPa bound below that material's limit point near 34 kPa
// and the targets of its ranges.
inline const std::vector<std::string> kCompressibleFinger = {
    "materials[0].E=2.0e5", "materials[0].nu=0.45", "control.actuators[0].max_pressure=30000",
    "control.targets=[{tip: [0.09, 0, -0.012]}, {tip: [0.09, 0, -0.003]}, {tip: [0.09, 0, 0.010]}, "
    "{tip: [0.09, 0, -0.0175]}, {tip: [0.09, 0, -0.008]}, {tip: [0.09, 0, -0.030]}]"};

// The deck's overrides: the pinned ones, then the test's own, which win.
inline std::vector<std::string> pinned(const std::vector<std::string>& pins,
                                       const std::vector<std::string>& overrides) {
  std::vector<std::string> all = pins;
  all.insert(all.end(), overrides.begin(), overrides.end());
  return all;
}

// The same as arguments of a shell's command line, each quoted, with a space after each.
inline std::string as_arguments(const std::vector<std::string>& pins) {
  std::string args;
  for (const std::string& o : pins) args += "--set '" + o + "' ";
  return args;
}

inline std::vector<std::string> coarse_cylinder(const std::vector<std::string>& overrides = {}) {
  return pinned(kCoarseCylinder, overrides);
}
inline std::string coarse_cylinder_args() { return as_arguments(kCoarseCylinder); }

inline std::vector<std::string> compressible_finger(
    const std::vector<std::string>& overrides = {}) {
  return pinned(kCompressibleFinger, overrides);
}
inline std::string compressible_finger_args() { return as_arguments(kCompressibleFinger); }

}  // namespace hs_test
