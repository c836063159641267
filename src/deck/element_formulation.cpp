#include "deck/element_formulation.hpp"

#include "common/deck_reader.hpp"

namespace hs {
namespace {

// The displacement P1 element's error in the inner displacement of the thick sphere (A = 1,
// B = 2, neo-Hookean, p/mu = 0.5, 15k dofs) against the exact solution of the same law:
// docs/stiff_cases.md, "Locking".
std::string p1_locking_error(double nu) {
  if (nu < 0.495) return "8 %";
  if (nu < 0.4995) return "40 %";
  return "86 %";
}

}  // namespace

FormulationChoice choose_formulation(ElementFormulation asked, double nu, int order) {
  const bool nearly_incompressible = nu >= kNearlyIncompressibleNu;
  const std::string at = "nu = " + format_number(nu) + (nearly_incompressible ? " >= " : " < ") +
                         format_number(kNearlyIncompressibleNu) + " on P" + std::to_string(order);
  FormulationChoice c;
  if (asked == ElementFormulation::fbar) {
    if (order == 1)
      c.error =
          "fbar needs mesh.order: 2 (on a P1 element J is constant and F-bar is the "
          "displacement element)";
    c.formulation = ElementFormulation::fbar;
    c.reason = "asked, " + at;
    return c;
  }
  if (asked == ElementFormulation::automatic && nearly_incompressible && order == 2) {
    c.formulation = ElementFormulation::fbar;
    c.reason = "auto: " + at;
    return c;
  }
  c.reason = (asked == ElementFormulation::automatic ? "auto: " : "asked, ") + at;
  if (nearly_incompressible && order == 1)
    c.warning = "P1 displacement elements lock at nu = " + format_number(nu) +
                ": a thick sphere inflated by pressure comes out about " + p1_locking_error(nu) +
                " too stiff at this nu (docs/stiff_cases.md); mesh.order: 2 runs the "
                "locking-free F-bar element";
  return c;
}

}  // namespace hs
