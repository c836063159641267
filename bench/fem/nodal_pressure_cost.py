#!/usr/bin/python3
"""The price of silicone's nu on P1 meshes: the same scene run with the displacement element at
nu 0.45 and with the nodal-pressure element at nu 0.4999, its tangent solved by MUMPS either
assembled (pc_type cholesky: the patch coupling joins a node to its neighbours' neighbours) or
through its mixed system (pc_type hs_mixed, the default). Runs interleaved (one of each, then
again), medians over --repeats; prints a Markdown table (docs/stiff_cases.md).

    /usr/bin/python3 bench/fem/nodal_pressure_cost.py [--hydrosoft build/bin/hydrosoft]
        [--repeats 3] [--scene sphere|finger] [--h 0.1]
"""
import argparse
import json
import os
import statistics
import subprocess
import tempfile

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))

SPHERE = """mesh:
  file: {root}/meshes/lame_sphere.geo
  order: 1
  parameters: {{a: 1.0, b: 2.0, h: {h}}}
materials:
  - {{group: body, model: neo_hookean, E: 2.9998e5, nu: {nu}, density: 0}}
boundary:
  - {{group: symmetry_x, components: [x]}}
  - {{group: symmetry_y, components: [y]}}
  - {{group: symmetry_z, components: [z]}}
  - {{group: inner, exact: true}}
time: {{type: static, steps: 4}}
solver: {{preset: mumps}}
exact:
  type: neo_hookean_sphere
  parameters: {{A: 1.0, B: 2.0, stretch: 1.2}}
output: {{folder: out, every: 100}}
"""

CASES = [  # label, nu, extra command-line options
    ("displacement, nu 0.45", 0.45, []),
    ("nodal pressure, nu 0.4999, assembled (cholesky)", 0.4999, ["-hs_newton_pc_type", "cholesky",
     "-hs_newton_pc_factor_mat_solver_type", "mumps", "-hs_bordered_pc_type", "cholesky",
     "-hs_bordered_pc_factor_mat_solver_type", "mumps", "-hs_control_pc_type", "cholesky",
     "-hs_control_pc_factor_mat_solver_type", "mumps"]),
    ("nodal pressure, nu 0.4999, mixed (hs_mixed)", 0.4999, []),
]


def run(hydrosoft, deck_text, options, folder):
    """options: --set first, then PETSc options (the command line's order)."""
    deck = os.path.join(folder, "deck.yaml")
    with open(deck, "w") as f:
        f.write(deck_text)
    env = dict(os.environ, OPENBLAS_NUM_THREADS="1")
    subprocess.run([hydrosoft, deck] + options + ["-options_left", "0"], cwd=folder, env=env,
                   check=True, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    with open(os.path.join(folder, "out", "summary.json")) as f:
        return json.load(f)


def finger_deck(nu):
    with open(os.path.join(ROOT, "input", "finger_hydraulic.yaml")) as f:
        text = f.read().replace("../meshes/", ROOT + "/meshes/")
    assert "nu: 0.45," in text
    return text.replace("nu: 0.45,", f"nu: {nu},"), ["--set", "output.folder=out"]


def main():
    p = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    p.add_argument("--hydrosoft", default=os.path.join(ROOT, "build", "bin", "hydrosoft"))
    p.add_argument("--repeats", type=int, default=3)
    p.add_argument("--scene", choices=["sphere", "finger"], default="sphere")
    p.add_argument("--h", type=float, default=0.1)
    a = p.parse_args()
    results = {label: [] for label, _, _ in CASES}
    for _ in range(a.repeats):
        for label, nu, options in CASES:
            with tempfile.TemporaryDirectory() as folder:
                if a.scene == "sphere":
                    deck, extra = SPHERE.format(root=ROOT, h=a.h, nu=nu), []
                else:
                    deck, extra = finger_deck(nu)
                results[label].append(run(a.hydrosoft, deck, extra + options, folder))
    print("| element, solve | dofs | Newton its / cutbacks | assembly | solve | whole run |")
    print("|---|---|---|---|---|---|")
    for label, runs in results.items():
        med = lambda key: statistics.median(r["time_s"][key] for r in runs)
        s = runs[0]
        print(f"| {label} | {s['dofs']:,} | {s['newton_iterations']} / {s['cutbacks']} | "
              f"{med('assembly'):.2f} s | {med('solve'):.2f} s | {med('total'):.2f} s |")


if __name__ == "__main__":
    main()
