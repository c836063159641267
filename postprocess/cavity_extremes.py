#!/usr/bin/python3
"""Stiff and extreme cavity cases (docs/stiff_cases.md, "Cavities"), all in one command.

    /usr/bin/python3 postprocess/cavity_extremes.py [--hydrosoft build/bin/hydrosoft]
        [--out out/extremes] [--csv docs/figures/cavity_extremes.csv] [--only CASE ...]

Runs build/bin/hydrosoft on the cylinder decks with --set overrides, one output folder per
run (out/extremes/<case>/<variant>), reads summary.json and the HDF5 file, and writes one
CSV row per reported state (or per failed run) and the same table in markdown on stdout.

Cases:
  inflation   the air cylinder inflated by volume control until the wall stretch passes 2
              (and past the pressure peak); inflation_limit: on until the solver stops;
              suction: air withdrawn by volume control down to 9 ml of the 79
  density     the water deck with liquid densities 0, 1000 and 13600 kg/m^3
  nu          Poisson ratios 0.45 (the decks'), 0.49, 0.499, 0.4999 with P1 and P2
  contrast    meshes/cylinder.geo split = 1: two materials, E ratio 1000:1 either way
  bad         inputs that have no solution: a negative density, withdrawing more than the
              cavity holds, a pressure past the peak, suction that collapses the cavity

Stretches: the largest principal stretch sqrt(eig(F^T F)) of each P1 element (vertices only
on P2), its maximum over the body (stretch_max) and its 90th percentile over the elements
(stretch_p90: a tenth of the body is stretched at least this much). Every output is checked for NaN (summary.json and
all HDF5 datasets); a failed run must leave neither its folder nor a .partial folder.
"""
import argparse
import csv
import json
import math
import os
import shutil
import subprocess
import sys
import time

import h5py
import numpy as np

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
AIR = "input/cylinder_air.yaml"
WATER = "input/cylinder_water.yaml"

COLUMNS = ["case", "variant", "state", "rc", "tip_angle_deg", "volume_ml", "added_ml",
           "pressure_pa", "fluid_weight_n", "rho_g_v_n", "stretch_max", "stretch_p90",
           "min_J", "newton_iterations", "cutbacks", "run_s", "nan_free", "message"]


def states_flow(steps_rest, targets, steps=5, key="added_volume"):
    """YAML flow list of states: rest, then one state per (name, value) target."""
    items = ["{name: rest, steps: %d}" % steps_rest]
    for name, value in targets:
        items.append("{name: %s, steps: %d, cavities: {cavity: {%s: %g}}}"
                     % (name, steps, key, value))
    return "[" + ", ".join(items) + "]"


def materials_flow(e_upper, e_lower, nu=0.45):
    m = "{group: %s, model: neo_hookean, E: %g, nu: %g, density: 1070}"
    return "[" + m % ("body_upper", e_upper, nu) + ", " + m % ("body_lower", e_lower, nu) + "]"


def nan_free_json(x):
    if isinstance(x, dict):
        return all(nan_free_json(v) for v in x.values())
    if isinstance(x, list):
        return all(nan_free_json(v) for v in x)
    if isinstance(x, float):
        return math.isfinite(x)
    return True


def nan_free_h5(path):
    ok = True

    def visit(_, obj):
        nonlocal ok
        if isinstance(obj, h5py.Dataset) and obj.dtype.kind == "f":
            ok &= bool(np.all(np.isfinite(obj[()])))
    with h5py.File(path) as f:
        f.visititems(visit)
    return ok


def stretches(h5path, step):
    """(largest principal stretch of any element, its 90th percentile over the elements,
    min J). On the coarse mesh nearly every element touches the cavity wall."""
    with h5py.File(h5path) as f:
        X = f["mesh/coordinates"][:]
        tets = f["mesh/topology"][:, :4]
        x = X + f["step_%d/displacement" % step][:]
        min_j = float(f["step_%d/J" % step][:].min())
    D0 = np.stack([X[tets[:, i]] - X[tets[:, 0]] for i in (1, 2, 3)], axis=2)
    D = np.stack([x[tets[:, i]] - x[tets[:, 0]] for i in (1, 2, 3)], axis=2)
    F = D @ np.linalg.inv(D0)
    lam = np.sqrt(np.linalg.eigvalsh(np.transpose(F, (0, 2, 1)) @ F))[:, -1]
    return float(lam.max()), float(np.percentile(lam, 90)), min_j


def run(args, case, variant, deck, sets, np_=1, extra=()):
    """Runs one deck; returns the rows (one per state, or one for a failure)."""
    slug = "".join(ch if ch.isalnum() or ch in ".-" else "_" for ch in variant)
    folder = os.path.join(args.out, case, slug)
    for f in (folder, folder + ".partial", folder + ".old"):
        if os.path.isdir(f) and (os.path.exists(os.path.join(f, ".hydrosoft_output"))
                                 or not os.listdir(f)):
            shutil.rmtree(f)
    cmd = ["mpirun", "--allow-run-as-root", "--oversubscribe", "-np", str(np_),
           args.hydrosoft, deck, "--set", "output.folder=" + folder]
    for s in sets:
        cmd += ["--set", s]
    cmd += list(extra)
    env = dict(os.environ, OMPI_MCA_rmaps_base_oversubscribe="1", OPENBLAS_NUM_THREADS="1")
    for _ in range(30):  # the binary may be missing for a moment while it is being rebuilt
        t0 = time.time()
        p = subprocess.run(cmd, cwd=ROOT, stdout=subprocess.PIPE, stderr=subprocess.STDOUT,
                           text=True, env=env)
        seconds = time.time() - t0
        if "unable to launch the specified application" not in p.stdout:
            break
        time.sleep(10)
    base = {"case": case, "variant": variant, "rc": p.returncode, "run_s": round(seconds, 1)}
    if p.returncode != 0:
        message = "; ".join(line.split("hydrosoft: error: ", 1)[1] for line in
                            p.stdout.splitlines() if "hydrosoft: error: " in line)
        left = [f for f in (folder, folder + ".partial") if os.path.exists(f)]
        row = dict(base, state="(failed)", message=message or p.stdout[-300:],
                   nan_free="nothing written" if not left else "LEFT " + " ".join(left))
        return [row]
    summary = json.load(open(os.path.join(folder, "summary.json")))
    deck_name = os.path.splitext(os.path.basename(deck))[0]
    h5 = os.path.join(folder, deck_name + ".h5")
    nan_free = nan_free_json(summary) and nan_free_h5(h5)
    gravity = 9.81
    rows = []
    for s in summary["states"]:
        c = s["cavities"][0]
        lam_max, lam_p90, min_j = stretches(h5, s["step"])
        rho = args.density.get((case, variant), 0.0)
        rows.append(dict(
            base, state=s["name"], tip_angle_deg=s.get("tip", {}).get("inclination_deg"),
            volume_ml=c["volume_ml"], added_ml=c["added_volume_ml"], pressure_pa=c["pressure"],
            fluid_weight_n=c["fluid_weight_total"],
            rho_g_v_n=rho * gravity * c["volume"] if rho else 0.0,
            stretch_max=lam_max, stretch_p90=lam_p90, min_J=min_j,
            newton_iterations=summary["newton_iterations"], cutbacks=summary["cutbacks"],
            nan_free="yes" if nan_free else "NO", message=""))
    return rows


def cases(args):
    rows = []
    want = lambda name: not args.only or name in args.only  # noqa: E731
    if want("inflation"):
        ml = [15, 30, 60, 100, 150, 200, 300, 400]
        rows += run(args, "inflation", "air P1",
                    AIR, ["states=" + states_flow(4, [("v%d" % v, v * 1e-6) for v in ml])])
    if want("inflation_limit"):
        ml = [700, 1500, 3000]
        rows += run(args, "inflation_limit", "air P1",
                    AIR, ["states=" + states_flow(4, [("v%d" % v, v * 1e-6) for v in ml])])
    if want("suction"):
        ml = [10, 20, 30, 40, 50, 60, 70]
        rows += run(args, "suction", "air P1",
                    AIR, ["states=" + states_flow(4, [("m%d" % v, -v * 1e-6) for v in ml])])
    if want("density"):
        for rho in (0, 1000, 13600):
            args.density[("density", "rho %d" % rho)] = rho
            rows += run(args, "density", "rho %d" % rho, WATER,
                        ["cavities[0].density=%g" % rho])
    if want("nu"):
        for order in (1, 2):
            for nu in (0.45, 0.49, 0.499, 0.4999):
                rows += run(args, "nu", "P%d nu %g" % (order, nu), AIR,
                            ["materials[0].nu=%g" % nu, "mesh.order=%d" % order],
                            np_=2 if order == 2 else 1)
    if want("contrast"):
        for eu, el in ((2e5, 2e5), (2e8, 2e5), (2e5, 2e8), (2e5, 200)):
            rows += run(args, "contrast", "upper %g, lower %g" % (eu, el), AIR,
                        ["mesh.parameters.split=1", "materials=" + materials_flow(eu, el)])
    if want("bad"):
        rows += run(args, "bad", "density -1000", WATER, ["cavities[0].density=-1000"])
        rows += run(args, "bad", "added -2e-4 (later state)", AIR,
                    ["states[1].cavities.cavity.added_volume=-2e-4"])
        rows += run(args, "bad", "added -2e-4 (first state)", AIR,
                    ["cavities[0].added_volume=-2e-4", "states=[{name: rest, steps: 4}]"])
        rows += run(args, "bad", "added -70 ml (9 ml left)", AIR,
                    ["states[1].cavities.cavity.added_volume=-7e-5"])
        rows += run(args, "bad", "pressure 30 kPa", AIR,
                    ["states[1].cavities.cavity={pressure: 3e4}"])
        rows += run(args, "bad", "pressure -50 kPa", AIR,
                    ["states[1].cavities.cavity={pressure: -5e4}"])
    return rows


def fmt(v, key):
    if v is None or v == "":
        return ""
    if isinstance(v, float):
        if key in ("volume_ml", "added_ml", "tip_angle_deg"):
            return "%.2f" % v
        if key in ("pressure_pa",):
            return "%.0f" % v
        if key in ("fluid_weight_n", "rho_g_v_n", "stretch_max", "stretch_p90", "min_J"):
            return "%.3f" % v
        return "%g" % v
    return str(v)


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--hydrosoft", default=os.path.join(ROOT, "build/bin/hydrosoft"))
    ap.add_argument("--out", default=os.path.join(ROOT, "out/extremes"))
    ap.add_argument("--csv", default=os.path.join(ROOT, "docs/figures/cavity_extremes.csv"))
    ap.add_argument("--only", nargs="*", help="case names to run (default: all)")
    args = ap.parse_args()
    args.density = {}
    t0 = time.time()
    rows = cases(args)
    total = time.time() - t0
    os.makedirs(os.path.dirname(args.csv), exist_ok=True)
    with open(args.csv, "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=COLUMNS)
        w.writeheader()
        for r in rows:
            w.writerow({k: fmt(r.get(k), k) for k in COLUMNS})
    shown = [c for c in COLUMNS if c not in ("rc",)]
    print("| " + " | ".join(shown) + " |")
    print("|" + "---|" * len(shown))
    for r in rows:
        print("| " + " | ".join(fmt(r.get(k), k).replace("|", "/") for k in shown) + " |")
    print("\n%d runs' rows written to %s in %.0f s" % (len(rows), os.path.relpath(args.csv, ROOT),
                                                      total))
    bad = [r for r in rows if r.get("nan_free") not in ("yes", "nothing written")]
    if bad:
        print("NaN or leftovers in: " + ", ".join(r["variant"] for r in bad), file=sys.stderr)
        return 1
    return 0


if __name__ == "__main__":
    sys.exit(main())
