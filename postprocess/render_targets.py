#!/usr/bin/python3
"""Side views of control runs: one row per run, one panel per target set, the deformed
body with its target and the position reached (e.g. the pneumatic and the hydraulic finger
on the same targets, the seed paper's Fig. 5).

    /usr/bin/python3 postprocess/render_targets.py out/finger_pneumatic out/finger_hydraulic \\
        --out docs/figures/finger_targets.png [--view y]

Each folder is a run's output folder: summary.json (its "targets" list: "target",
"reached", "error_m", "actuation", "saturated", "step", the output step after that target
set; null for a set not written, which gets no panel) and <deck>.h5 (docs/output.md). The body's boundary surface is drawn as seen along
--view (y: the x-z plane, x to the right and z up; x: the y-z plane), the undeformed body
in light grey behind it; the target is a red cross, the reached position a black dot,
filled green when the target is met to 0.1 mm. Every panel has the same scale, with axes in
mm and a legend. Prints a Markdown table of the targets.
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
            if t.get("step") is None:  # not written (output.every)
                continue
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
    from matplotlib.lines import Line2D
    from matplotlib.patches import Patch
    axes2d = (0, 2) if view == "y" else (1, 2)
    names = ("x", "z") if view == "y" else ("y", "z")
    ncol = max(len(r["panels"]) for r in runs)
    mm = 1e3
    # One scale for every panel, so that deflections compare across targets and runs.
    pts = [mm * np.concatenate([r["X"], r["X"] + p["u"], [p["target"]]])[:, axes2d]
           for r in runs for p in r["panels"]]
    lo = np.min([q.min(axis=0) for q in pts], axis=0)
    hi = np.max([q.max(axis=0) for q in pts], axis=0)
    pad = 0.06 * (hi - lo).max()
    aspect = (hi[1] - lo[1] + 2 * pad) / (hi[0] - lo[0] + 2 * pad)
    fig, axes = plt.subplots(len(runs), ncol,
                             figsize=(2.3 * ncol, len(runs) * (2.0 * aspect + 0.9) + 0.4),
                             squeeze=False, sharex=True, sharey=True)
    for i, r in enumerate(runs):
        X, faces = r["X"], r["faces"]
        for j in range(ncol):
            ax = axes[i][j]
            ax.set_aspect("equal")
            ax.set_xlim(lo[0] - pad, hi[0] + pad)
            ax.set_ylim(lo[1] - pad, hi[1] + pad)
            ax.tick_params(labelsize=6, length=2)
            if j == 0:
                ax.set_ylabel(f"{r['deck']}\n{names[1]} (mm)", fontsize=7)
            if i == len(runs) - 1:
                ax.set_xlabel(f"{names[0]} (mm)", fontsize=7)
            if j >= len(r["panels"]):
                ax.axis("off")
                continue
            p = r["panels"][j]
            x = X + p["u"]
            for q, colour in ((X, "0.88"), (x, "#5b8fd6")):
                poly = mm * q[faces][:, :, axes2d]
                ax.add_collection(PolyCollection(poly, facecolors=colour, edgecolors="none"))
            t, q = mm * np.array(p["target"]), mm * np.array(p["reached"])
            ax.plot(t[axes2d[0]], t[axes2d[1]], "x", color="red", ms=7, mew=2)
            met = p["error_m"] <= REACHED_M
            ax.plot(q[axes2d[0]], q[axes2d[1]], "o", ms=4.5, mec="k",
                    mfc="limegreen" if met else "k")
            act = ", ".join("%.1f" % (round(a / 1e3, 2) + 0.0) for a in p["actuation"])
            sat = " (sat.)" if any(p["saturated"]) else ""
            where = f"z* {t[2]:.1f} mm" if view == "y" else f"x*, y* {t[0]:.1f}, {t[1]:.1f} mm"
            ax.set_title(f"{where}: error {mm * p['error_m']:.2f} mm\np {act} kPa{sat}",
                         fontsize=6.5)
    legend = [Patch(color="0.88", label="undeformed"), Patch(color="#5b8fd6", label="deformed"),
              Line2D([], [], ls="none", marker="x", color="red", mew=2, label="target"),
              Line2D([], [], ls="none", marker="o", mec="k", mfc="limegreen",
                     label="reached, within 0.1 mm"),
              Line2D([], [], ls="none", marker="o", mec="k", mfc="k", label="reached, farther")]
    fig.legend(handles=legend, loc="lower center", ncol=5, fontsize=7, frameon=False)
    fig.tight_layout(rect=(0, 0.07, 1, 1))
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
