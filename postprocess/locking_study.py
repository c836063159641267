#!/usr/bin/python3
"""Volumetric locking: the Lame sphere at Poisson ratios from 0 to 0.4999 on one mesh, P1
against P2. The Lame solution holds for any nu < 0.5, so the L2 error shows how far each
element is from it as the material becomes incompressible.

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


def run(binary, deck, order, nu, h, folder):
    cmd = [binary, deck, "--set", f"mesh.order={order}", "--set", f"materials[0].nu={nu}",
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
        for order in (1, 2):
            s = run(args.binary, args.deck, order, nu, args.h, os.path.join(args.out, f"p{order}_nu{nu}"))
            row[f"p{order}_l2"] = s["error"]["l2_relative"]
            row[f"p{order}_dofs"] = s["dofs"]
        rows.append(row)
        print(json.dumps(row), flush=True)
    with open(os.path.join(args.out, "locking.csv"), "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=list(rows[0].keys()))
        w.writeheader()
        w.writerows(rows)
    print(f"\n| nu | P1 L2 error ({rows[0]['p1_dofs']} dofs) | P2 L2 error ({rows[0]['p2_dofs']} dofs) |")
    print("|---|---|---|")
    for r in rows:
        print(f"| {r['nu']} | {r['p1_l2']:.3e} | {r['p2_l2']:.3e} |")


if __name__ == "__main__":
    main()
