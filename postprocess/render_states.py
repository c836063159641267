#!/usr/bin/python3
"""Side views of the deformed states of one or more runs (e.g. the hanging cylinder filled
with air and with water, at rest and inflated), in one PNG, and a Markdown table of the
tip angles.

    /usr/bin/python3 postprocess/render_states.py out/cylinder_air out/cylinder_water \\
        --out docs/figures/cylinder_states.png

Each folder is a run's output folder: summary.json (its "states" list: "name",
"tip" (its "inclination_deg") and "step", the output step of the state's last load step) and <deck>.h5
(/mesh/coordinates, /mesh/topology, /step_<k>/displacement; docs/output.md). For every state
of every folder (one row per folder, its states left to right), the deformed boundary surface (the faces of the tetrahedra
that belong to one tetrahedron only; the 4 corner nodes of a P2 tetrahedron) is drawn as
seen from +x: the y-z plane with y up and -z to the right, so a cylinder clamped at z = 0
hangs from the left. Faces of the outer surface are coloured by the displacement magnitude
(one colour scale for all panels), over the reference outline in light grey; the outline of
any inner closed surface (a cavity) is drawn through the wall as a dashed white line. The PNG is written to a temporary
name in the target folder and renamed, so a failed run never leaves half a figure.

Prints | deck | state | tip angle (deg) | added volume (ml) |. The added volume is read
from the state's entry when summary.json has it ("added_volume" in m^3, on the state or
summed over its "cavities"); otherwise the column says n/a.
"""
import argparse
import json
import os
import sys
import tempfile

import numpy as np

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
from matplotlib.collections import LineCollection, PolyCollection  # noqa: E402

try:
    import h5py
except ImportError:  # pragma: no cover
    sys.exit("render_states: needs h5py (Debian: apt-get install python3-h5py)")


class RenderError(Exception):
    pass


# ---------------------------------------------------------------- reading

def read_summary(folder, state_keys=("name", "tip", "step")):
    path = os.path.join(folder, "summary.json")
    if not os.path.isfile(path):
        raise RenderError(f"{path}: file not found (is '{folder}' a finished run's output folder?)")
    try:
        with open(path) as f:
            summary = json.load(f)
    except (OSError, ValueError) as e:
        raise RenderError(f"{path}: cannot read it as JSON ({e})")
    states = summary.get("states")
    if not isinstance(states, list) or not states:
        raise RenderError(f"{path}: no \"states\" list (the deck needs a states section)")
    for i, s in enumerate(states):
        for key in state_keys:
            if not isinstance(s, dict) or key not in s:
                raise RenderError(f"{path}: states[{i}] has no \"{key}\"")
    return path, summary


def deck_name(folder, summary):
    deck = summary.get("deck")
    if isinstance(deck, str) and deck:
        return os.path.splitext(os.path.basename(deck))[0]
    return os.path.basename(os.path.normpath(folder))


def h5_path(folder, summary):
    name = deck_name(folder, summary)
    path = os.path.join(folder, name + ".h5")
    if os.path.isfile(path):
        return path
    found = sorted(f for f in os.listdir(folder) if f.endswith(".h5"))
    if len(found) == 1:
        return os.path.join(folder, found[0])
    raise RenderError(f"{path}: file not found"
                      + (f" (the folder holds {', '.join(found)})" if found else ""))


def dataset(f, path, name, shape_check):
    if name not in f:
        raise RenderError(f"{path}: dataset /{name} is missing")
    d = f[name]
    if not isinstance(d, h5py.Dataset):
        raise RenderError(f"{path}: /{name} is not a dataset")
    a = d[()]
    msg = shape_check(a)
    if msg:
        raise RenderError(f"{path}: /{name} has shape {a.shape}, expected {msg}")
    return a


def added_volume_ml(state):
    """Added volume of a state (ml) when summary.json records it, else None."""
    if "added_volume_ml" in state:
        return float(state["added_volume_ml"])
    if "added_volume" in state and state["added_volume"] is not None:
        return float(state["added_volume"]) * 1e6
    cav = state.get("cavities")
    entries = cav.values() if isinstance(cav, dict) else cav if isinstance(cav, list) else []
    vols = [float(c["added_volume"]) for c in entries
            if isinstance(c, dict) and c.get("added_volume") is not None]
    return sum(vols) * 1e6 if vols else None


def load_run(folder):
    if not os.path.isdir(folder):
        raise RenderError(f"{folder}: output folder not found")
    spath, summary = read_summary(folder)
    path = h5_path(folder, summary)
    try:
        f = h5py.File(path, "r")
    except OSError as e:
        raise RenderError(f"{path}: cannot open as HDF5 ({e})")
    with f:
        X = dataset(f, path, "mesh/coordinates",
                    lambda a: None if a.ndim == 2 and a.shape[1] == 3 and len(a) else "N x 3")
        topo = dataset(f, path, "mesh/topology",
                       lambda a: None if a.ndim == 2 and a.shape[1] in (4, 10) and len(a)
                       else "E x 4 or E x 10")
        topo = topo.astype(np.int64)
        if topo.min() < 0 or topo.max() >= len(X):
            raise RenderError(f"{path}: /mesh/topology refers to node {topo.max()} "
                              f"(or {topo.min()}) but /mesh/coordinates has {len(X)} nodes")
        states = []
        for i, s in enumerate(summary["states"]):
            try:
                k = int(s["step"])
            except (TypeError, ValueError):
                raise RenderError(f"{spath}: states[{i}] (\"{s['name']}\"): step is not an "
                                  f"integer ({s['step']!r})")
            name = f"step_{k}/displacement"
            if f"step_{k}" not in f:
                raise RenderError(f"{path}: group /step_{k} is missing (state \"{s['name']}\" "
                                  f"of {spath} says its last output step is {k})")
            u = dataset(f, path, name,
                        lambda a: None if a.shape == X.shape else f"{X.shape[0]} x 3 like "
                        "/mesh/coordinates")
            if not np.all(np.isfinite(u)):
                raise RenderError(f"{path}: /{name} has non-finite entries")
            t = f[f"step_{k}"].attrs.get("time")
            states.append({"name": str(s["name"]), "angle": float(s["tip"]["inclination_deg"]),
                           "step": k, "time": None if t is None else float(t), "u": u,
                           "added_ml": added_volume_ml(s)})
    outer, inner = split_outer(X, boundary_faces(X, topo[:, :4]))
    return {"folder": folder, "deck": deck_name(folder, summary), "X": X,
            "faces": outer, "inner": inner, "states": states}


# ---------------------------------------------------------------- geometry

def boundary_faces(X, tets):
    """Faces that belong to exactly one tetrahedron, oriented outwards (reference)."""
    local = np.array([[1, 2, 3], [0, 3, 2], [0, 1, 3], [0, 2, 1]])
    opposite = np.array([0, 1, 2, 3])
    faces = tets[:, local].reshape(-1, 3)
    opp = tets[:, opposite].reshape(-1)
    key = np.sort(faces, axis=1)
    _, inverse, counts = np.unique(key, axis=0, return_inverse=True, return_counts=True)
    once = counts[inverse.reshape(-1)] == 1
    faces, opp = faces[once], opp[once]
    a, b, c = X[faces[:, 0]], X[faces[:, 1]], X[faces[:, 2]]
    inward = np.einsum("ij,ij->i", np.cross(b - a, c - a), X[opp] - a) > 0
    faces[inward] = faces[inward][:, [0, 2, 1]]
    return faces


def split_outer(X, faces):
    """The boundary's outer surface (the connected piece that holds the node of largest x)
    and the rest (closed inner surfaces: cavities)."""
    label = np.arange(len(X))
    while True:
        m = label[faces].min(axis=1)
        new = label.copy()
        np.minimum.at(new, faces.reshape(-1), np.repeat(m, 3))
        new = new[new]
        if np.array_equal(new, label):
            break
        label = new
    nodes = np.unique(faces)
    top = nodes[np.argmax(X[nodes, 0])]
    outer = label[faces[:, 0]] == label[top]
    return faces[outer], faces[~outer]


def side_view(x, faces):
    """Faces seen from +x (front-facing, far ones first) and their silhouette edges."""
    a, b, c = x[faces[:, 0]], x[faces[:, 1]], x[faces[:, 2]]
    nx = np.cross(b - a, c - a)[:, 0]
    front = faces[nx > 0]
    depth = x[front][:, :, 0].mean(axis=1)
    front = front[np.argsort(depth)]
    edges = np.sort(front[:, [[0, 1], [1, 2], [2, 0]]].reshape(-1, 2), axis=1)
    uniq, counts = np.unique(edges, axis=0, return_counts=True)
    return front, uniq[counts == 1]


def yz(points):
    """Screen coordinates of a view from +x: (-z, y)."""
    return np.stack([-points[..., 2], points[..., 1]], axis=-1)


# ---------------------------------------------------------------- drawing

def render(runs, out, scale, dpi):
    panels = [(run, s) for run in runs for s in run["states"]]
    vmax = max(float(np.linalg.norm(s["u"], axis=1).max()) for _, s in panels) * 1e3
    vmax = vmax if vmax > 0 else 1.0
    lo = np.full(2, np.inf)
    hi = np.full(2, -np.inf)
    for run, s in panels:
        for pts in (run["X"], run["X"] + scale * s["u"]):
            p = yz(pts)
            lo, hi = np.minimum(lo, p.min(0)), np.maximum(hi, p.max(0))
    pad = 0.05 * (hi - lo).max()
    lo, hi = lo - pad, hi + pad
    width = min(max(3.6 * (hi[0] - lo[0]) / (hi[1] - lo[1]), 2.5), 8.0)
    # One row per run, its states left to right: a figure a page's column can hold.
    ncol = max(len(run["states"]) for run in runs)
    fig, axes = plt.subplots(len(runs), ncol, figsize=(width * ncol + 1.0, 4.0 * len(runs)),
                             squeeze=False, constrained_layout=True)
    cmap = plt.get_cmap("viridis")
    norm = matplotlib.colors.Normalize(0, vmax)
    places = [(i, j) for i, run in enumerate(runs) for j in range(len(run["states"]))]
    for i, j in {(i, j) for i in range(len(runs)) for j in range(ncol)} - set(places):
        axes[i][j].axis("off")
    for (i, j), (run, s) in zip(places, panels):
        ax = axes[i][j]
        X, faces = run["X"], run["faces"]
        rfront, redges = side_view(X, faces)
        ax.add_collection(PolyCollection(yz(X[rfront]) * 1e3, facecolors="0.93",
                                         edgecolors="none", zorder=1))
        ax.add_collection(LineCollection(yz(X[redges]) * 1e3, colors="0.7", linewidths=1.0,
                                         zorder=2))
        x = X + scale * s["u"]
        front, edges = side_view(x, faces)
        umag = np.linalg.norm(s["u"], axis=1) * 1e3
        colours = cmap(norm(umag[front].mean(axis=1)))
        ax.add_collection(PolyCollection(yz(x[front]) * 1e3, facecolors=colours,
                                         edgecolors=colours, linewidths=0.2, zorder=3))
        ax.add_collection(LineCollection(yz(x[edges]) * 1e3, colors="k", linewidths=0.6,
                                         zorder=4))
        if len(run["inner"]):
            _, cedges = side_view(x, run["inner"])
            ax.add_collection(LineCollection(yz(x[cedges]) * 1e3, colors="w", linewidths=0.8,
                                             linestyles=(0, (3, 2)), zorder=4))
        ax.set_xlim(lo[0] * 1e3, hi[0] * 1e3)
        ax.set_ylim(lo[1] * 1e3, hi[1] * 1e3)
        ax.set_aspect("equal")
        ax.set_xlabel("-z (mm)")
        ax.set_ylabel("y (mm)")
        title = f"{run['deck']}: {s['name']}\ntip angle {s['angle']:.1f}°"
        if scale != 1:
            title += f" (displacement x{scale:g})"
        ax.set_title(title, fontsize=10)
        ax.tick_params(labelsize=8)
    fig.colorbar(matplotlib.cm.ScalarMappable(norm=norm, cmap=cmap), ax=list(axes.flat),
                 label="|u| (mm)", shrink=0.9, aspect=30)
    if os.path.isdir(out):
        raise RenderError(f"{out}: is a folder; --out names the PNG file to write")
    folder = os.path.dirname(os.path.abspath(out))
    tmp = None
    try:
        os.makedirs(folder, exist_ok=True)
        fd, tmp = tempfile.mkstemp(prefix="." + os.path.basename(out) + ".", suffix=".png",
                                   dir=folder)
        os.close(fd)
        fig.savefig(tmp, dpi=dpi, format="png", bbox_inches="tight")
        os.chmod(tmp, 0o644)
        os.replace(tmp, out)
        tmp = None
    except OSError as e:
        raise RenderError(f"{out}: cannot write the figure ({e}); nothing was written")
    finally:
        plt.close(fig)
        if tmp is not None and os.path.exists(tmp):
            os.remove(tmp)


def table(runs):
    lines = ["| deck | state | tip angle (deg) | added volume (ml) |", "|---|---|---|---|"]
    for run in runs:
        for s in run["states"]:
            v = "n/a" if s["added_ml"] is None else f"{s['added_ml']:.1f}"
            lines.append(f"| {run['deck']} | {s['name']} | {s['angle']:.2f} | {v} |")
    return "\n".join(lines)


def main():
    p = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("folders", nargs="+", help="output folders (summary.json and <deck>.h5)")
    p.add_argument("--out", default="out/cylinder_states.png", help="PNG to write")
    p.add_argument("--scale", type=float, default=1.0, help="displacement magnification (1: true)")
    p.add_argument("--dpi", type=int, default=150)
    args = p.parse_args()
    try:
        runs = [load_run(folder) for folder in args.folders]
        render(runs, args.out, args.scale, args.dpi)
    except RenderError as e:
        sys.exit(f"render_states: {e}")
    print(table(runs))
    print(f"\nwrote {args.out}", file=sys.stderr)


if __name__ == "__main__":
    main()
