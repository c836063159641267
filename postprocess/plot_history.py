#!/usr/bin/python3
"""Plots a run's per-step history: each cavity's pressure, volume and liquid weight and each
cable's force over the steps, and each cavity's pressure against its volume.

    /usr/bin/python3 postprocess/plot_history.py OUT_FOLDER [--out FILE.png]

OUT_FOLDER is a run's output folder; its history.csv (docs/output.md, "history.csv") has one
row per output step. The time column is the CSV's second (load_factor, time_s or state). The
picture goes to OUT_FOLDER/pictures/<deck>_history.png unless --out says where (written under
a temporary name and renamed). Prints, per cavity, the range of its pressure and volume.
"""
import argparse
import csv
import json
import os
import re
import sys

UNITS = {"Pa": ("kPa", 1e-3), "m3": ("ml", 1e6), "N": ("N", 1.0), "m": ("mm", 1e3)}


def read_history(folder):
    path = os.path.join(folder, "history.csv")
    if not os.path.isfile(path):
        sys.exit(f"plot_history.py: {path}: file not found (is '{folder}' a run's output folder?)")
    with open(path, newline="") as f:
        rows = list(csv.reader(f))
    if len(rows) < 2:
        sys.exit(f"plot_history.py: {path}: no step in it")
    header, data = rows[0], [[float(v) for v in r] for r in rows[1:]]
    return path, header, {name: [r[k] for r in data] for k, name in enumerate(header)}


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("folder")
    ap.add_argument("--out")
    a = ap.parse_args()
    path, header, columns = read_history(a.folder)
    time_name = header[1]
    time = columns[time_name]
    # cavity_<name>_<quantity>_<unit> and cable_<name>_<quantity>_<unit>
    series = []
    for name in header[2:]:
        m = re.fullmatch(r"(cavity|cable)_(.+?)_(pressure|volume|added_volume|fluid_weight|force|pull)_(Pa|m3|N|m)", name)
        if m and m.group(3) != "added_volume":
            series.append((m.group(1), m.group(2), m.group(3), m.group(4), name))
    if not series:
        sys.exit(f"plot_history.py: {path}: no cavity or cable column (a deck without them has "
                 "nothing to plot here)")
    cavities = sorted({s[1] for s in series if s[0] == "cavity"})
    quantities = sorted({(s[0], s[2], s[3]) for s in series}, key=lambda q: (q[0], q[1]))

    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    panels = len(quantities) + (1 if cavities else 0)
    fig, axes = plt.subplots(1, panels, figsize=(3.6 * panels, 3.4), squeeze=False)
    axes = axes[0]
    for ax, (kind, quantity, unit) in zip(axes, quantities):
        label, factor = UNITS[unit]
        for s in series:
            if (s[0], s[2], s[3]) == (kind, quantity, unit):
                ax.plot(time, [factor * v for v in columns[s[4]]], "-o", ms=3, label=s[1])
        ax.set_xlabel(time_name.replace("_", " "))
        ax.set_ylabel(f"{kind} {quantity.replace('_', ' ')} ({label})")
        ax.grid(True, alpha=0.3)
        ax.legend(fontsize=7)
    if cavities:
        ax = axes[-1]
        for c in cavities:
            p, v = columns[f"cavity_{c}_pressure_Pa"], columns[f"cavity_{c}_volume_m3"]
            ax.plot([1e6 * x for x in v], [1e-3 * x for x in p], "-o", ms=3, label=c)
            print(f"cavity {c}: pressure {min(p):.6g} to {max(p):.6g} Pa, volume "
                  f"{1e6 * min(v):.6g} to {1e6 * max(v):.6g} ml over {len(p)} steps")
        ax.set_xlabel("cavity volume (ml)")
        ax.set_ylabel("cavity pressure (kPa)")
        ax.set_title("pressure against volume", fontsize=9)
        ax.grid(True, alpha=0.3)
        ax.legend(fontsize=7)
    deck = "run"
    try:
        with open(os.path.join(a.folder, "summary.json")) as f:
            deck = os.path.splitext(os.path.basename(json.load(f)["deck"]))[0]
    except (OSError, ValueError, KeyError):
        pass
    fig.suptitle(f"{deck}: history of {len(time)} output steps", fontsize=10)
    fig.tight_layout()
    out = a.out or os.path.join(a.folder, "pictures", f"{deck}_history.png")
    os.makedirs(os.path.dirname(os.path.abspath(out)), exist_ok=True)
    tmp = out + ".tmp.png"
    fig.savefig(tmp, dpi=110)
    os.replace(tmp, out)
    print(f"wrote {out}")


if __name__ == "__main__":
    main()
