#!/usr/bin/python3
"""Mesh-refinement study of a deck with an exact solution: runs hydrosoft at several mesh
sizes for P1 and P2, writes a CSV of error, size and run time, fits the L2 rates and plots
error against run time and against the mesh size. A deck without an exact solution is
refused before any run: postprocess/refinement_study.py studies those.

    /usr/bin/python3 postprocess/convergence_study.py                       # Lame sphere
    /usr/bin/python3 postprocess/convergence_study.py --np 2 --out out/convergence

The mesh size of a level is h_eff = (volume / elements)^(1/3) -- what the mesher made, not
what was asked for -- so the rates do not depend on how faithfully gmsh follows h.
"""
import argparse
import csv
import json
import math
import os
import re
import subprocess
import sys

DEFAULT_LEVELS = {1: [0.4, 0.2, 0.1, 0.05], 2: [0.5, 0.35, 0.25, 0.18, 0.125]}


NO_EXACT = ("{deck} has no exact solution ({why}), so there is no error to "
            "measure; for a refinement study of its quantities (observed order, Richardson "
            "extrapolation) run: /usr/bin/python3 postprocess/refinement_study.py {deck}")


def require_exact_solution(deck):
    """Refuses, before any run, a deck without a top-level exact: section."""
    try:
        with open(deck) as f:
            text = f.read()
    except OSError as e:
        sys.exit(f"convergence_study: cannot read the deck {deck}: {e.strerror}")
    if not re.search(r"^exact\s*:", text, re.MULTILINE):
        sys.exit("convergence_study: " + NO_EXACT.format(deck=deck, why="no exact: section"))


def run_level(args, order, h):
    folder = os.path.join(args.out, f"p{order}_h{h:g}")
    cmd = ["mpirun", "--oversubscribe", "-np", str(args.np)]
    if os.geteuid() == 0:
        cmd.append("--allow-run-as-root")
    cmd += [args.binary, args.deck, "--set", f"mesh.order={order}",
            "--set", f"mesh.parameters.h={h}", "--set", f"output.folder={folder}"]
    env = dict(os.environ, OPENBLAS_NUM_THREADS="1")
    result = subprocess.run(cmd, capture_output=True, text=True, env=env)
    if result.returncode != 0:
        sys.exit(f"convergence_study: level p{order} h={h} failed:\n{result.stderr}")
    with open(os.path.join(folder, "summary.json")) as f:
        summary = json.load(f)
    if "error" not in summary:  # an exact: section whose type is none
        sys.exit("convergence_study: " + NO_EXACT.format(deck=args.deck, why="its exact.type is none"))
    return summary


def fitted_rate(hs, errors, finest=3):
    """Least-squares slope of log(error) against log(h) over the finest levels."""
    x = [math.log(h) for h in hs[-finest:]]
    y = [math.log(e) for e in errors[-finest:]]
    mx, my = sum(x) / len(x), sum(y) / len(y)
    return sum((a - mx) * (b - my) for a, b in zip(x, y)) / sum((a - mx) ** 2 for a in x)


def main():
    p = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("--deck", default="input/lame_sphere.yaml")
    p.add_argument("--binary", default="build/bin/hydrosoft")
    p.add_argument("--np", type=int, default=1)
    p.add_argument("--out", default="out/convergence")
    p.add_argument("--volume", type=float, default=math.pi / 6 * (2.0**3 - 1.0),
                   help="reference volume of the domain, for h_eff (default: eighth Lame sphere)")
    p.add_argument("--p1", type=float, nargs="+", default=DEFAULT_LEVELS[1])
    p.add_argument("--p2", type=float, nargs="+", default=DEFAULT_LEVELS[2])
    args = p.parse_args()
    require_exact_solution(args.deck)
    os.makedirs(args.out, exist_ok=True)

    rows = []
    for order, levels in ((1, args.p1), (2, args.p2)):
        for h in levels:
            s = run_level(args, order, h)
            h_eff = (args.volume / s["elements"]) ** (1.0 / 3.0)
            rows.append(dict(order=order, h=h, h_eff=h_eff, elements=s["elements"], dofs=s["dofs"],
                             ranks=s["ranks"], l2_relative=s["error"]["l2_relative"],
                             time_total_s=s["time_s"]["total"], time_solve_s=s["time_s"]["solve"],
                             time_assembly_s=s["time_s"]["assembly"]))
            print(f"P{order} h={h:<6g} dofs={s['dofs']:>8} L2={rows[-1]['l2_relative']:.4e} "
                  f"t={rows[-1]['time_total_s']:.2f}s", flush=True)

    csv_path = os.path.join(args.out, "convergence.csv")
    with open(csv_path, "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=list(rows[0].keys()))
        w.writeheader()
        w.writerows(rows)

    rates = {}
    for order in (1, 2):
        r = [row for row in rows if row["order"] == order]
        rates[order] = fitted_rate([x["h_eff"] for x in r], [x["l2_relative"] for x in r])
        print(f"P{order}: fitted L2 rate over the finest three levels = {rates[order]:.2f}")
    with open(os.path.join(args.out, "rates.json"), "w") as f:
        json.dump({f"P{k}": v for k, v in rates.items()}, f, indent=2)

    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    fig, (ax1, ax2) = plt.subplots(1, 2, figsize=(11, 4.5))
    for order, marker in ((1, "o"), (2, "s")):
        r = [row for row in rows if row["order"] == order]
        label = f"P{order} (rate {rates[order]:.2f})"
        ax1.loglog([x["h_eff"] for x in r], [x["l2_relative"] for x in r], marker + "-", label=label)
        ax2.loglog([x["time_total_s"] for x in r], [x["l2_relative"] for x in r], marker + "-",
                   label=f"P{order}")
    ax1.set_xlabel("h_eff = (V / elements)^(1/3)")
    ax1.set_ylabel("relative L2 displacement error")
    ax1.grid(True, which="both", alpha=0.3)
    ax1.legend()
    ax2.set_xlabel(f"run time, s ({rows[0]['ranks']} rank(s), whole run)")
    ax2.set_ylabel("relative L2 displacement error")
    ax2.grid(True, which="both", alpha=0.3)
    ax2.legend()
    fig.suptitle(os.path.basename(args.deck))
    fig.tight_layout()
    png = os.path.join(args.out, "convergence.png")
    fig.savefig(png, dpi=120)
    print(f"wrote {csv_path} and {png}")


if __name__ == "__main__":
    main()
