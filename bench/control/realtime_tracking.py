#!/usr/bin/python3
"""The real-time loop (`hydrosoft DECK --targets -`, one control step a line) per scene and mode.

    /usr/bin/python3 bench/control/realtime_tracking.py [--repeats 3] [--out out/realtime]

Scenes: the hydraulic finger (1,961 nodes) along its tip-height sweep (from rest to -12 mm
in 20 lines, then -12 -> -8 -> -12 mm in 0.2 mm lines) and the pendulum (2,063 nodes) along
the circle of scripts/track_circle.py. Modes: `in line` (one_step, a factorization every
step), `kept/4` (refactor_every 4) and `background` (factor_threads 1: 1 rank + 1 thread).
Each run (a hydrosoft_control.Scene, the executable of $HYDROSOFT or build/bin) sends one
line, waits for its answer, then sends the next; the latency is the time from the write of a
line to the read of its answer. A second run with check_equilibrium
gives each answer's equilibrium error (its distance from a converged Newton solve at the
same actuation, solved outside the step times). Figures over the tracking lines (after the
approach from rest): step time median/mean/p95/max (the step's own time, slowest rank) and
latency mean/p95, error median/max; medians over the repeats. Writes NAME.csv and an
error-against-run-time plot NAME.png under --out.
"""
import argparse
import csv
import json
import math
import os
import statistics
import sys

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
sys.path.insert(0, os.path.join(ROOT, "python"))
from hydrosoft_control import Scene  # noqa: E402
MODES = {"in line": ["control.refactor_every=1"], "kept/4": ["control.refactor_every=4"],
         "background": ["control.factor_threads=1"]}


def finger_sweep():
    z = [-0.0181 + (0.0181 - 0.012) * k / 20 for k in range(1, 21)]
    z += [-0.012 + 2e-4 * k for k in range(1, 21)] + [-0.008 - 2e-4 * k for k in range(1, 21)]
    return [f"0.09 0 {v:.6f}" for v in z], 20


def pendulum_circle(n=40, r=0.0015, z=-0.1012):
    lead = [f"{r * k / 4:.6f} 0 {z}" for k in range(1, 5)]
    return lead + [f"{r * math.cos(2 * math.pi * k / n):.6f} "
                   f"{r * math.sin(2 * math.pi * k / n):.6f} {z}" for k in range(n + 1)], 4


SCENES = {"finger_hydraulic": finger_sweep, "pendulum": pendulum_circle}


OVERRIDES = []  # --set: an override for every run


def run(deck, lines, mode, check, folder):
    """(answers as hydrosoft wrote them, each line's round trip in ms) of one run."""
    overrides = ["control.free_solve=one_step", "control.steps_per_target=1",
                 f"control.check_equilibrium={'true' if check else 'false'}"] + MODES[mode]
    overrides += OVERRIDES
    with Scene(os.path.join(ROOT, "input", deck + ".yaml"), overrides=overrides,
               output_folder=folder) as scene:
        answers = [scene.send_line(line) for line in lines]
    return [a.raw for a in answers], [a.round_trip_ms for a in answers]


def p95(v):
    v = sorted(v)
    return v[min(len(v) - 1, int(round(0.95 * (len(v) - 1))))]


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--repeats", type=int, default=3)
    ap.add_argument("--out", default=os.path.join(ROOT, "out", "realtime"))
    ap.add_argument("--scenes", default=",".join(SCENES))
    ap.add_argument("--set", action="append", default=[],
                    help="an override for every run, e.g. materials[0].nu=0.45")
    a = ap.parse_args()
    OVERRIDES.extend(a.set)
    os.makedirs(a.out, exist_ok=True)
    rows = []
    for scene in a.scenes.split(","):
        lines, lead = SCENES[scene]()
        for mode in MODES:
            reps = []
            for r in range(a.repeats):
                folder = os.path.join(a.out, "runs", f"{scene}_{mode.replace(' ', '_').replace('/', '')}")
                ans, lat = run(scene, lines, mode, False, folder)
                chk, _ = run(scene, lines, mode, True, folder)
                t = [x["step_ms"] for x in ans[lead:]]
                err = [1e3 * math.dist(x["reached"], x["equilibrium"]) for x in chk[lead:]]
                reps.append({"median": statistics.median(t), "mean": statistics.mean(t),
                             "p95": p95(t), "max": max(t), "latency_mean": statistics.mean(lat[lead:]),
                             "latency_p95": p95(lat[lead:]), "err_median": statistics.median(err),
                             "err_max": max(err),
                             "staleness_mean": statistics.mean([x.get("staleness", 0) for x in ans[lead:]]),
                             "iterations_mean": statistics.mean(
                                 [x.get("correction_iterations", 0) for x in ans[lead:]])})
            row = {"scene": scene, "mode": mode, "cores": 2 if mode == "background" else 1,
                   "repeats": a.repeats}
            for k in reps[0]:
                row[k] = round(statistics.median(rep[k] for rep in reps), 4)
            rows.append(row)
            print(json.dumps(row), flush=True)
    with open(os.path.join(a.out, "realtime_tracking.csv"), "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=list(rows[0]))
        w.writeheader()
        w.writerows(rows)
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    fig, ax = plt.subplots(figsize=(6, 4))
    for row in rows:
        ax.errorbar(row["mean"], row["err_max"], fmt="o", label=f"{row['scene']}, {row['mode']}")
    ax.axhline(0.1, color="grey", ls="--", lw=0.8)
    ax.axvline(4, color="grey", ls=":", lw=0.8)
    ax.set_xlabel("mean step time (ms)")
    ax.set_ylabel("max equilibrium error (mm)")
    ax.set_xscale("log")
    ax.set_yscale("log")
    ax.legend(fontsize=7)
    fig.tight_layout()
    fig.savefig(os.path.join(a.out, "realtime_tracking.png"), dpi=120)


if __name__ == "__main__":
    main()
