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

// nu = 0.5: the two locking-free elements carry volume multipliers (nodal pressure per patch on
// P1, F-bar per element on P2), on the law's volumetric term; the displacement element none.
FormulationChoice choose_incompressible(ElementFormulation asked, int order,
                                        bool law_has_volumetric_term, bool law_small_strain) {
  FormulationChoice c;
  c.formulation = order == 1 ? ElementFormulation::nodal_pressure : ElementFormulation::fbar;
  c.reason = std::string(asked == ElementFormulation::automatic ? "auto: " : "asked, ") +
             "nu = 0.5 (incompressible) on P" + std::to_string(order) + ": " +
             (order == 1 ? "nodal pressure" : "F-bar") + " with volume multipliers";
  if (!law_has_volumetric_term || (order == 2 && law_small_strain)) {
    c.error_key = "nu";
    c.error = order == 1 ? "0.5 (exact incompressibility) needs a law with a volumetric term "
                           "(neo_hookean, mooney_rivlin, yeoh, gent, linear_elastic): its "
                           "multipliers keep the nodal-pressure element's volumes"
                         : "0.5 (exact incompressibility) on P2 needs a finite-strain law with a "
                           "volumetric term (neo_hookean, mooney_rivlin, yeoh, gent): its "
                           "multipliers keep the F-bar element's volumes; linear_elastic takes "
                           "nu = 0.5 on P1 meshes";
  } else if (asked != ElementFormulation::automatic && asked != c.formulation) {
    c.error = std::string("nu = 0.5 (exact incompressibility) runs on the ") +
              (order == 1 ? "nodal-pressure element on P1 meshes (formulation: auto or "
                            "nodal_pressure)"
                          : "F-bar element on P2 meshes (formulation: auto or fbar)") +
              "; the " + name_of(kElementFormulationNames, asked) +
              " element has no volume multipliers there";
  }
  return c;
}

}  // namespace

FormulationChoice choose_formulation(ElementFormulation asked, double nu, int order,
                                     bool law_has_volumetric_term, bool law_small_strain) {
  const bool nearly_incompressible = nu >= kNearlyIncompressibleNu;
  const std::string at = "nu = " + format_number(nu) + (nearly_incompressible ? " >= " : " < ") +
                         format_number(kNearlyIncompressibleNu) + " on P" + std::to_string(order);
  FormulationChoice c;
  const bool automatic = asked == ElementFormulation::automatic;
  if (nu == 0.5)
    return choose_incompressible(asked, order, law_has_volumetric_term, law_small_strain);
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
