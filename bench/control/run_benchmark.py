#!/usr/bin/python3
"""Time per control step of the control decks on a refinement series, split into its parts.

    /usr/bin/python3 bench/control/run_benchmark.py [--np 1] [--repeats 3] [--largest]
        [--out bench/control/results.csv]

For each deck (finger_pneumatic, finger_hydraulic, finger_cable, pendulum), mesh size h
(the .geo's sizes: finger 364, 1,961 and 10,488 nodes, pendulum 2,063 and 10,493) and
control mode (newton: the free configuration converged by Newton; one_step: one
linearisation per step; one_step/4: the same with the factorization kept for up to 4
steps, on the meshes of up to ~2,000 nodes), runs `hydrosoft DECK` on NP ranks with two
reachable target sets and 5 control steps each, REPEATS times, and reads summary.json's
`step_time_ms` (median and p95 over the run's steps; the split medians: assembly, fluid
weight, free solve, factorization, compliance, QP, correction). Reports the median over the
repeats of each figure, as CSV and as a Markdown table. --largest runs only the ~51k-node
meshes, in one_step mode (a factorization there takes seconds; newton would take an hour).
Rows measured replace the rows of the same deck, nodes and mode in the CSV; the others
stay. OPENBLAS_NUM_THREADS=1, so NP ranks use NP cores.

    /usr/bin/python3 bench/control/run_benchmark.py --tracking [--repeats 3]

times the real-time use instead: both fingers (1,961 nodes) follow the tip height from -12
to -8 mm and back in 0.2 mm targets, one control step each (40 steps, after 20 steps that
bring it from rest to -12 mm), with the factorization kept for N = 1, 4 and 10 steps;
besides the step times (median, mean and p95 of the 40 steps; the split medians over all
60) it reports the largest error of the prediction and of the equilibrium at each target's
actuation (check_equilibrium, solved outside the step times). Writes bench/control/tracking.csv.
"""
import argparse
import csv
import json
import os
import statistics
import subprocess
import sys
import tempfile

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
CASES = [  # deck, h, nodes (meshes/*.geo headers)
    ("finger_pneumatic", 0.006, 364), ("finger_pneumatic", 0.0026, 1961),
    ("finger_pneumatic", 0.00135, 10488), ("finger_pneumatic", 0.00074, 51465),
    ("finger_hydraulic", 0.006, 364), ("finger_hydraulic", 0.0026, 1961),
    ("finger_hydraulic", 0.00135, 10488), ("finger_hydraulic", 0.00074, 51465),
    ("finger_cable", 0.0026, 1961), ("finger_cable", 0.00135, 10488),
    ("pendulum", 0.0036, 2063), ("pendulum", 0.00185, 10493), ("pendulum", 0.00103, 51393),
]
MODES = [("newton", 1), ("one_step", 1), ("one_step", 4)]
KEPT_UP_TO = 2100  # nodes: the kept factorization is the real-time mode of small meshes
PARTS = ["assembly", "fluid_weight", "free_solve", "factorization", "compliance", "qp",
         "correction"]


OVERRIDES = []  # --set: an override for every run


def run(deck, h, np_, folder, mode, targets=None, extra=()):
    cmd = ["mpirun", "--oversubscribe", "-np", str(np_)]
    if os.geteuid() == 0:
        cmd.append("--allow-run-as-root")
    cmd += [os.path.join(ROOT, "build", "bin", "hydrosoft"), f"input/{deck}.yaml",
            "--set", f"mesh.parameters.h={h}", "--set", "control.steps_per_target=5",
            "--set", f"control.free_solve={mode[0]}", "--set", f"control.refactor_every={mode[1]}",
            "--set", f"output.folder={folder}"]
    if targets is None:
        targets = "control.targets=" + {
            "pendulum": "[{bottom: [0, 0, -0.1015]}, {bottom: [0.002, 0, -0.1012]}]",
            "finger_cable": "[{tip: [0.09, 0, -0.02]}, {tip: [0.09, 0, -0.025]}]"}.get(
            deck, "[{tip: [0.09, 0, -0.012]}, {tip: [0.09, 0, -0.008]}]")
    cmd += ["--set", targets, *extra]
    for o in OVERRIDES:
        cmd += ["--set", o]
    env = dict(os.environ, OPENBLAS_NUM_THREADS="1")
    p = subprocess.run(cmd, cwd=ROOT, env=env, capture_output=True, text=True)
    if p.returncode != 0:
        sys.exit(f"run_benchmark.py: {deck} h={h} failed:\n{p.stdout[-2000:]}{p.stderr[-2000:]}")
    with open(os.path.join(folder, "summary.json")) as f:
        return json.load(f)


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--np", type=int, default=1)
    ap.add_argument("--repeats", type=int, default=3)
    ap.add_argument("--largest", action="store_true")
    ap.add_argument("--tracking", action="store_true")
    ap.add_argument("--out", default=os.path.join(ROOT, "bench", "control", "results.csv"))
    ap.add_argument("--set", action="append", default=[],
                    help="an override for every run, e.g. materials[0].nu=0.45")
    a = ap.parse_args()
    OVERRIDES.extend(a.set)
    if a.tracking:
        return tracking(a)
    rows = []
    for deck, h, nodes in CASES:
        if (nodes > 50000) != a.largest:
            continue
        for mode in MODES:
            if a.largest and mode != ("one_step", 1):
                continue
            if mode[1] > 1 and nodes > KEPT_UP_TO:
                continue
            reps = []
            for r in range(a.repeats):
                folder = os.path.join(tempfile.gettempdir(),
                                      f"hydrosoft_bench_control_{deck}_{r}")
                reps.append(run(deck, h, a.np, folder, mode))
            st = [s["step_time_ms"] for s in reps]
            row = {"deck": deck, "h": h, "nodes": nodes, "dofs": reps[0]["dofs"],
                   "ranks": a.np, "mode": mode[0] + ("" if mode[1] == 1 else f"/{mode[1]}"),
                   "steps": st[0]["steps"],
                   "median_ms": statistics.median(s["median"] for s in st),
                   "p95_ms": statistics.median(s["p95"] for s in st)}
            for part in PARTS:
                row[part + "_ms"] = statistics.median(s["split_median"][part] for s in st)
            rows.append(row)
            print(row, flush=True)
    rows = merged(a.out, rows)
    tmp = a.out + ".tmp"
    with open(tmp, "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=list(rows[0].keys()))
        w.writeheader()
        for row in rows:
            w.writerow({k: (("%g" if k == "h" else "%.3f") % float(v)
                            if isinstance(v, float) else v) for k, v in row.items()})
    os.replace(tmp, a.out)
    print("| deck | nodes | mode | step median (ms) | p95 | " + " | ".join(PARTS) + " |")
    print("|---|---|---|---|---|" + "---|" * len(PARTS))
    for r in rows:
        print(f"| {r['deck']} | {int(r['nodes']):,} | {r['mode']} | {float(r['median_ms']):.1f} | "
              f"{float(r['p95_ms']):.1f} | " +
              " | ".join("%.2f" % float(r[p + "_ms"]) for p in PARTS) + " |")


def tracking(a):
    """The fingers following a slow sweep of the tip height, one control step a target."""
    lead = 20  # steps that take the finger from rest to the sweep's start, left out below
    heights = [-0.012 + 0.0002 * k for k in range(21)]
    heights = [-0.012] * lead + heights[1:] + heights[-2::-1]
    targets = "control.targets=[" + ", ".join(
        "{tip: [0.09, 0, %.4f]}" % z for z in heights) + "]"
    extra = ("--set", "control.steps_per_target=1", "--set", "control.check_equilibrium=true")
    rows = []
    for deck in ("finger_pneumatic", "finger_hydraulic"):
        for n in (1, 4, 10):
            reps = []
            for r in range(a.repeats):
                folder = os.path.join(tempfile.gettempdir(), f"hydrosoft_bench_track_{deck}_{r}")
                reps.append(run(deck, 0.0026, a.np, folder, ("one_step", n), targets, extra))
            st = [s["step_time_ms"] for s in reps]
            t = reps[0]["targets"][lead:]
            # One step a target: each target's step_ms is its step's time.
            times = [sorted(x["step_ms"] for x in s["targets"][lead:]) for s in reps]
            row = {"deck": deck, "nodes": 1961, "refactor_every": n, "steps": len(t),
                   "median_ms": statistics.median(statistics.median(v) for v in times),
                   "mean_ms": statistics.median(statistics.mean(v) for v in times),
                   "p95_ms": statistics.median(v[int(0.95 * (len(v) - 1))] for v in times),
                   "max_prediction_error_mm": 1e3 * max(x["error_m"] for x in t),
                   "max_equilibrium_error_mm": 1e3 * max(x["equilibrium_error_m"] for x in t)}
            for part in PARTS:
                row[part + "_ms"] = statistics.median(s["split_median"][part] for s in st)
            rows.append(row)
            print(row, flush=True)
    out = os.path.join(os.path.dirname(a.out), "tracking.csv")
    with open(out + ".tmp", "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=list(rows[0].keys()))
        w.writeheader()
        for row in rows:
            w.writerow({k: ("%.4f" % v if isinstance(v, float) else v) for k, v in row.items()})
    os.replace(out + ".tmp", out)
    print("| deck | refactor_every | step median (ms) | mean | p95 | max prediction error (mm) | "
          "max equilibrium error (mm) | " + " | ".join(PARTS) + " |")
    print("|---|---|---|---|---|---|---|" + "---|" * len(PARTS))
    for r in rows:
        print(f"| {r['deck']} | {r['refactor_every']} | {r['median_ms']:.2f} | {r['mean_ms']:.1f} | "
              f"{r['p95_ms']:.1f} | "
              f"{r['max_prediction_error_mm']:.4f} | {r['max_equilibrium_error_mm']:.4f} | " +
              " | ".join("%.2f" % r[p + "_ms"] for p in PARTS) + " |")


def merged(path, new_rows):
    """The CSV's rows with those measured now replaced or added, in the order of CASES."""
    key = lambda r: (r["deck"], int(r["nodes"]), r["mode"])
    rows = {}
    if os.path.exists(path):
        with open(path, newline="") as f:
            for r in csv.DictReader(f):
                rows[key(r)] = {k: (float(v) if k == "h" or k.endswith("_ms") else v)
                                for k, v in r.items()}
    for r in new_rows:
        rows[key(r)] = r
    order = {(d, n): i for i, (d, _, n) in enumerate(CASES)}
    modes = [m[0] + ("" if m[1] == 1 else f"/{m[1]}") for m in MODES]
    return sorted(rows.values(), key=lambda r: (order.get((r["deck"], int(r["nodes"])), 99),
                                                modes.index(r["mode"])))


if __name__ == "__main__":
    main()
