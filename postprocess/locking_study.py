#!/usr/bin/python3
"""Volumetric locking: the Lame sphere at Poisson ratios from 0 to 0.4999 on one mesh, the
displacement element on P1 and P2 against the locking-free elements: nodal pressure on P1,
F-bar on P2. The Lame solution holds for
any nu < 0.5, so the L2 error shows how far each element is from it as the material becomes
incompressible.

    /usr/bin/python3 postprocess/locking_study.py [--h 0.25] [--out out/locking]

Writes <out>/locking.csv and prints a Markdown table.
"""
import argparse
import csv
import json
import os
import subprocess
import sys

NUS = [0.0, 0.3, 0.45, 0.49, 0.499, 0.4999]


ELEMENTS = [(1, "displacement"), (1, "nodal_pressure"), (2, "displacement"), (2, "fbar")]


def run(binary, deck, order, formulation, nu, h, folder):
    cmd = [binary, deck, "--set", f"mesh.order={order}", "--set", f"materials[0].nu={nu}",
           "--set", f"materials[0].formulation={formulation}",
           "--set", f"mesh.parameters.h={h}", "--set", f"output.folder={folder}"]
    r = subprocess.run(cmd, capture_output=True, text=True, env=dict(os.environ, OPENBLAS_NUM_THREADS="1"))
    if r.returncode != 0:
        sys.exit(f"locking_study: {' '.join(cmd)} failed:\n{r.stderr[-2000:]}")
    with open(os.path.join(folder, "summary.json")) as f:
        return json.load(f)


def main():
    p = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("--binary", default="build/bin/hydrosoft")
    p.add_argument("--deck", default="input/lame_sphere.yaml")
    p.add_argument("--h", type=float, default=0.25)
    p.add_argument("--out", default="out/locking")
    args = p.parse_args()
    os.makedirs(args.out, exist_ok=True)
    rows = []
    for nu in NUS:
        row = {"nu": nu}
        for order, formulation in ELEMENTS:
            name = f"p{order}_{formulation}"
            s = run(args.binary, args.deck, order, formulation, nu, args.h,
                    os.path.join(args.out, f"{name}_nu{nu}"))
            row[f"{name}_l2"] = s["error"]["l2_relative"]
            row[f"{name}_dofs"] = s["dofs"]
        rows.append(row)
        print(json.dumps(row), flush=True)
    with open(os.path.join(args.out, "locking.csv"), "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=list(rows[0].keys()))
        w.writeheader()
        w.writerows(rows)
    first = rows[0]
    print(f"\n| nu | P1 L2 error ({first['p1_displacement_dofs']} dofs) | P1 nodal pressure "
          f"| P2 L2 error ({first['p2_displacement_dofs']} dofs) | P2 F-bar L2 error |")
    print("|---|---|---|---|---|")
    for r in rows:
        print(f"| {r['nu']} | {r['p1_displacement_l2']:.3e} | {r['p1_nodal_pressure_l2']:.3e} "
              f"| {r['p2_displacement_l2']:.3e} | {r['p2_fbar_l2']:.3e} |")


if __name__ == "__main__":
    main()
