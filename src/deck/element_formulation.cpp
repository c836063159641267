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

// nu = 0.5: the nodal-pressure element with its volume multipliers, the one element that
// carries them.
FormulationChoice choose_incompressible(ElementFormulation asked, int order,
                                        bool law_has_volumetric_term) {
  FormulationChoice c;
  c.formulation = ElementFormulation::nodal_pressure;
  c.reason = std::string(asked == ElementFormulation::automatic ? "auto: " : "asked, ") +
             "nu = 0.5 (incompressible) on P" + std::to_string(order) +
             ": nodal pressure with volume multipliers";
  if (order != 1) {
    c.error_key = "nu";
    c.error =
        "0.5 (exact incompressibility) is built on P1 meshes only, by the nodal-pressure "
        "element's volume multipliers; on mesh.order: 2, nu 0.4999 runs the F-bar element "
        "(within 0.1 % of the incompressible sphere, docs/stiff_cases.md)";
  } else if (!law_has_volumetric_term) {
    c.error_key = "nu";
    c.error =
        "0.5 (exact incompressibility) needs a law with a volumetric term (neo_hookean, "
        "mooney_rivlin, yeoh, gent, linear_elastic): its multipliers keep the nodal-pressure "
        "element's volumes";
  } else if (asked != ElementFormulation::automatic &&
             asked != ElementFormulation::nodal_pressure) {
    c.error = std::string(
                  "nu = 0.5 (exact incompressibility) runs on the nodal-pressure "
                  "element only (formulation: auto or nodal_pressure); the ") +
              (asked == ElementFormulation::fbar ? "F-bar" : "displacement") +
              " element has no volume multipliers";
  }
  return c;
}

}  // namespace

FormulationChoice choose_formulation(ElementFormulation asked, double nu, int order,
                                     bool law_has_volumetric_term) {
  const bool nearly_incompressible = nu >= kNearlyIncompressibleNu;
  const std::string at = "nu = " + format_number(nu) + (nearly_incompressible ? " >= " : " < ") +
                         format_number(kNearlyIncompressibleNu) + " on P" + std::to_string(order);
  FormulationChoice c;
  const bool automatic = asked == ElementFormulation::automatic;
  if (nu == 0.5) return choose_incompressible(asked, order, law_has_volumetric_term);
  c.reason = (automatic ? "auto: " : "asked, ") + at;
  if (asked == ElementFormulation::fbar) {
    if (order == 1)
      c.error =
          "fbar needs mesh.order: 2 (on a P1 element J is constant and F-bar is the "
          "displacement element); nodal_pressure is the locking-free element of P1 meshes";
    c.formulation = ElementFormulation::fbar;
    return c;
  }
  if (asked == ElementFormulation::nodal_pressure) {
    if (order != 1)
      c.error = "nodal_pressure needs mesh.order: 1 (fbar is the locking-free element of P2)";
    else if (!law_has_volumetric_term)
      c.error =
          "nodal_pressure needs a law with a volumetric term k/2 (ln J)^2 or k/2 (tr eps)^2 "
          "(neo_hookean, mooney_rivlin, yeoh, gent, linear_elastic)";
    c.formulation = ElementFormulation::nodal_pressure;
    return c;
  }
  if (automatic && nearly_incompressible && order == 2) {
    c.formulation = ElementFormulation::fbar;
    return c;
  }
  if (automatic && nearly_incompressible && law_has_volumetric_term) {
    c.formulation = ElementFormulation::nodal_pressure;
    return c;
  }
  if (nearly_incompressible && order == 1)
    c.warning = "P1 displacement elements lock at nu = " + format_number(nu) +
                ": a thick sphere inflated by pressure comes out about " + p1_locking_error(nu) +
                " too stiff at this nu (docs/stiff_cases.md); " +
                (law_has_volumetric_term
                     ? "formulation: nodal_pressure (the default) runs the locking-free element"
                     : "this law has no volumetric term for the locking-free nodal_pressure "
                       "element; mesh.order: 2 runs the F-bar element");
  return c;
}

}  // namespace hs
