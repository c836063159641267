#!/usr/bin/python3
"""hydrosoft's uniaxial bar against postprocess/fit_material.py's closed forms.

A cube of side H (meshes/block.geo, P1) held by rollers on x = 0, y = 0, z = 0 and stretched
along z to stretch 2 by its top face (boundary value, 4 steps): the deformation is homogeneous,
which P1 elements represent exactly, so there is no discretisation error to speak of; what
remains is the deck's nu = 0.4999 against the closed forms' incompressibility, the volume
change J - 1 ~ sigma / (3 kappa), of order 1e-4 here. The top's reaction force over H^2 is the
nominal stress; it must match the script's nominal_stress at each step's stretch to 1e-3 for
every law the script fits, and its difference must shrink as nu -> 0.5 (0.499 against 0.4999:
the difference is the compressibility, not an error of the formula).

    /usr/bin/python3 tests/postprocess/fit_material_bar_test.py BUILD/bin/hydrosoft
"""
import csv
import os
import subprocess
import sys
import tempfile

import numpy as np

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
sys.path.insert(0, os.path.join(ROOT, "postprocess"))
import fit_material as fm  # noqa: E402

H = 0.01  # m
LAWS = {  # the closed forms' coefficients, and the deck's entry for them (SI)
    "neo_hookean": ({"mu": 4.0e4}, "E: {E}, nu: {nu}"),
    "mooney_rivlin": ({"c1": 1.5e4, "c2": 5.0e3}, "E: {E}, nu: {nu}, c1: 1.5e4, c2: 5.0e3"),
    "yeoh": ({"C1": 2.0e4, "C2": 1.0e3, "C3": 50.0}, "C1: 2.0e4, C2: 1.0e3, C3: 50.0, nu: {nu}"),
    "gent": ({"mu": 4.0e4, "Jm": 10.0}, "E: {E}, nu: {nu}, Jm: 10.0"),
}


def small_strain_mu(law, c):
    return {"neo_hookean": c.get("mu"), "gent": c.get("mu"), "yeoh": 2 * c.get("C1", 0),
            "mooney_rivlin": 2 * (c.get("c1", 0) + c.get("c2", 0))}[law]


def run(hydrosoft, tmp, law, nu):
    c, entry = LAWS[law]
    E = 2 * small_strain_mu(law, c) * (1 + nu)
    folder = os.path.join(tmp, f"{law}_{nu}")
    deck = os.path.join(tmp, f"{law}_{nu}.yaml")
    with open(deck, "w") as f:
        f.write(f"""mesh:
  file: {os.path.join(ROOT, "meshes", "block.geo")}
  order: 1
  parameters: {{H: {H}, h: {H / 2}}}
materials:
  - {{group: body, model: {law}, {entry.format(E=repr(E), nu=nu)}, density: 0}}
boundary:
  - {{group: bottom, components: [z]}}
  - {{group: x0, components: [x]}}
  - {{group: y0, components: [y]}}
  - {{group: top, components: [z], value: [0, 0, {H}]}}
time: {{type: static, steps: 4}}
solver: {{preset: mumps}}
output: {{folder: {folder}}}
""")
    subprocess.run([hydrosoft, deck, "-q"], check=True, stdout=subprocess.DEVNULL,
                   stderr=subprocess.DEVNULL)
    with open(os.path.join(folder, "history.csv")) as f:
        rows = list(csv.DictReader(f))
    stretch = np.array([1 + float(r["load_factor"]) for r in rows])  # u_top = H * load factor
    measured = np.array([float(r["reaction_top_z_N"]) for r in rows]) / H**2
    expected = fm.nominal_stress(law, c, stretch)
    return stretch, float(np.max(np.abs(measured / expected - 1)))


def main():
    hydrosoft = sys.argv[1]
    with tempfile.TemporaryDirectory(prefix="hydrosoft_fit_bar_test_") as tmp:
        for law in LAWS:
            stretch, near = run(hydrosoft, tmp, law, 0.4999)
            _, far = run(hydrosoft, tmp, law, 0.499)
            print(f"{law}: stretch {stretch[0]:g} to {stretch[-1]:g}, largest relative difference "
                  f"{near:.2e} at nu 0.4999, {far:.2e} at nu 0.499")
            assert stretch[-1] == 2.0, stretch
            assert near < 1e-3, (law, near)
            assert near < far / 3, (law, near, far)


if __name__ == "__main__":
    main()
