#!/usr/bin/python3
"""Side views of control runs: one row per run, one panel per target set, the deformed
body with its target and the position reached (e.g. the pneumatic and the hydraulic finger
on the same targets, the seed paper's Fig. 5).

    /usr/bin/python3 postprocess/render_targets.py out/finger_pneumatic out/finger_hydraulic \\
        --out docs/figures/finger_targets.png [--view y]

Each folder is a run's output folder: summary.json (its "targets" list: "target",
"reached", "error_m", "actuation", "saturated", "step", the output step after that target
set) and <deck>.h5 (docs/output.md). The body's boundary surface is drawn as seen along
--view (y: the x-z plane, x to the right and z up; x: the y-z plane), the undeformed body
in light grey behind it; the target is a red cross, the reached position a black dot,
filled green when the target is met to 0.1 mm. Prints a Markdown table of the targets.
The PNG is written to a temporary name and renamed.
"""
import argparse
import os
import sys

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from render_states import (RenderError, boundary_faces, dataset, deck_name,  # noqa: E402
                           h5_path, read_summary, split_outer)

REACHED_M = 1e-4


def load(folder):
    spath, summary = read_summary(folder, state_keys=("name",))
    if "targets" not in summary:
        raise RenderError(f"{spath}: no \"targets\" (not a control run)")
    import h5py
    path = h5_path(folder, summary)
    with h5py.File(path, "r") as f:
        X = dataset(f, path, "mesh/coordinates", lambda a: None)
        topo = dataset(f, path, "mesh/topology", lambda a: None).astype(np.int64)
        panels = []
        for t in summary["targets"]:
            k = int(t["step"])
            u = dataset(f, path, f"step_{k}/displacement",
                        lambda a: None if a.shape == X.shape else "N x 3")
            if not np.all(np.isfinite(u)):
                raise RenderError(f"{path}: /step_{k}/displacement has non-finite entries")
            panels.append({"u": u, **t})
    outer, _ = split_outer(X, boundary_faces(X, topo[:, :4]))
    return {"deck": deck_name(folder, summary), "X": X, "faces": outer, "panels": panels}


def render(runs, out, view):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    from matplotlib.collections import PolyCollection
    axes2d = (0, 2) if view == "y" else (1, 2)
    ncol = max(len(r["panels"]) for r in runs)
    fig, axes = plt.subplots(len(runs), ncol, figsize=(2.6 * ncol, 2.4 * len(runs)),
                             squeeze=False)
    mm = 1e3
    for i, r in enumerate(runs):
        X, faces = r["X"], r["faces"]
        for j in range(ncol):
            ax = axes[i][j]
            ax.set_aspect("equal")
            ax.axis("off")
            if j >= len(r["panels"]):
                continue
            p = r["panels"][j]
            x = X + p["u"]
            for pts, colour in ((X, "0.88"), (x, "#5b8fd6")):
                poly = mm * pts[faces][:, :, axes2d]
                ax.add_collection(PolyCollection(poly, facecolors=colour, edgecolors="none"))
            t, q = mm * np.array(p["target"]), mm * np.array(p["reached"])
            ax.plot(t[axes2d[0]], t[axes2d[1]], "x", color="red", ms=8, mew=2)
            met = p["error_m"] <= REACHED_M
            ax.plot(q[axes2d[0]], q[axes2d[1]], "o", ms=5, mec="k",
                    mfc="limegreen" if met else "k")
            allp = mm * np.concatenate([X, x])[:, axes2d]
            lo = np.minimum(allp.min(axis=0), t[list(axes2d)]) - 3
            hi = np.maximum(allp.max(axis=0), t[list(axes2d)]) + 3
            ax.set_xlim(lo[0], hi[0])
            ax.set_ylim(lo[1], hi[1])
            act = ", ".join("%.1f" % (round(a / 1e3, 2) + 0.0) for a in p["actuation"])
            sat = "sat." if any(p["saturated"]) else ""
            where = f"z* {t[2]:.1f}" if view == "y" else f"x*, y* {t[0]:.1f}, {t[1]:.1f}"
            ax.set_title(f"{r['deck']}\n{where} mm: err {mm * p['error_m']:.2f} mm\n"
                         f"p {act} kPa {sat}", fontsize=7)
    fig.tight_layout()
    tmp = out + ".tmp.png"
    fig.savefig(tmp, dpi=110)
    os.replace(tmp, out)


def table(runs):
    print("| deck | target (mm) | reached (mm) | error (mm) | pressures (kPa) | saturated |")
    print("|---|---|---|---|---|---|")
    for r in runs:
        for p in r["panels"]:
            fmt = lambda v: ", ".join("%.2f" % (1e3 * c) for c in v)  # noqa: E731
            print(f"| {r['deck']} | {fmt(p['target'])} | {fmt(p['reached'])} | "
                  f"{1e3 * p['error_m']:.3f} | "
                  f"{', '.join('%.2f' % (round(a / 1e3, 2) + 0.0) for a in p['actuation'])} | "
                  f"{', '.join('yes' if s else 'no' for s in p['saturated'])} |")


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("folders", nargs="+")
    ap.add_argument("--out", required=True)
    ap.add_argument("--view", choices=["x", "y"], default="y")
    a = ap.parse_args()
    try:
        runs = [load(f) for f in a.folders]
    except RenderError as e:
        sys.exit(f"render_targets.py: {e}")
    render(runs, a.out, a.view)
    table(runs)


if __name__ == "__main__":
    main()
