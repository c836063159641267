#!/usr/bin/python3
"""Plots a dynamic run with cavities or cables against time: the displacement of a node group
(its mean), each cavity's pressure and volume, and the energy balance (kinetic, stored, work
done on the body, and their balance).

    /usr/bin/python3 postprocess/plot_dynamic.py OUT_FOLDER [--group effector] [--out FILE.png]

OUT_FOLDER is the run's output folder: its history.csv (time_s, the cavity columns, energy_J,
kinetic_energy_J, stored_energy_J, work_J; docs/output.md) and its .h5 (the displacement of
every output step, the group's nodes marked by /mesh/group_<name>). The picture goes to
OUT_FOLDER/pictures/<deck>_dynamic.png unless --out says where. Prints the group's range of
motion and the largest departure of the energy balance from its start.
"""
import argparse
import csv
import glob
import os
import sys


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("folder")
    ap.add_argument("--group", default="effector")
    ap.add_argument("--out")
    a = ap.parse_args()
    with open(os.path.join(a.folder, "history.csv"), newline="") as f:
        rows = list(csv.DictReader(f))
    if not rows or "time_s" not in rows[0] or "energy_J" not in rows[0]:
        sys.exit(f"plot_dynamic.py: {a.folder}: not a dynamic run with cavities or cables")
    col = {k: [float(r[k]) for r in rows] for k in rows[0]}
    h5s = glob.glob(os.path.join(a.folder, "*.h5"))
    h5s = [p for p in h5s if not p.endswith("checkpoint.h5")]
    import h5py
    import numpy as np
    with h5py.File(h5s[0], "r") as f:
        nodes = np.asarray(f["mesh/group_" + a.group][:]) != 0
        steps = sorted((k for k in f if k.startswith("step_")), key=lambda k: int(k[5:]))
        mean = np.array([f[k]["displacement"][:][nodes].mean(axis=0) for k in steps]) * 1e3
    t = col["time_s"]
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    fig, axes = plt.subplots(1, 3, figsize=(13, 3.6))
    for d, name in enumerate("xyz"):
        axes[0].plot(t, mean[:, d], label=name)
    axes[0].set(xlabel="time (s)", ylabel=f"'{a.group}' displacement (mm)")
    axes[0].legend()
    cavities = sorted({k[len("cavity_"):-len("_pressure_Pa")] for k in col
                       if k.startswith("cavity_") and k.endswith("_pressure_Pa")})
    twin = axes[1].twinx()
    for c in cavities:
        axes[1].plot(t, np.array(col[f"cavity_{c}_pressure_Pa"]) * 1e-3, label=f"{c} pressure")
        twin.plot(t, np.array(col[f"cavity_{c}_volume_m3"]) * 1e6, "--", label=f"{c} volume")
    axes[1].set(xlabel="time (s)", ylabel="pressure (kPa, solid)")
    twin.set_ylabel("volume (ml, dashed)")
    for key, label in (("kinetic_energy_J", "kinetic"), ("stored_energy_J", "stored"),
                       ("work_J", "work done on it"), ("energy_J", "balance")):
        axes[2].plot(t, np.array(col[key]) * 1e3, label=label)
    axes[2].set(xlabel="time (s)", ylabel="energy (mJ)")
    axes[2].legend(fontsize=8)
    fig.tight_layout()
    deck = os.path.splitext(os.path.basename(h5s[0]))[0]
    out = a.out or os.path.join(a.folder, "pictures", deck + "_dynamic.png")
    os.makedirs(os.path.dirname(os.path.abspath(out)), exist_ok=True)
    fig.savefig(out + ".tmp.png", dpi=110)
    os.replace(out + ".tmp.png", out)
    e = np.array(col["energy_J"])
    print(f"{a.group}: z from {mean[:, 2].min():.3f} to {mean[:, 2].max():.3f} mm; "
          f"energy balance within {np.abs(e - e[0]).max():.3e} J of its start; {out}")


if __name__ == "__main__":
    main()
