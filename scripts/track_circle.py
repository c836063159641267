#!/usr/bin/python3
"""Drives hydrosoft interactively along a circle and plots the tracking error over time.

    /usr/bin/python3 scripts/track_circle.py [--deck input/pendulum.yaml] [--np 1]
        [--radius 0.001] [--centre 0,0,-0.1011] [--points 40] [--turns 1]
        [--steps 1] [--out out/circle_tracking] [--set KEY=VALUE ...]

Starts `mpirun -np NP build/bin/hydrosoft DECK --targets - --set
control.steps_per_target=STEPS` (through python/hydrosoft_control) and, for each point of the circle (in the horizontal plane
through the centre, starting on +x), writes one line "x y z" to its standard input and
waits for its line on standard output (one JSON object: the answer, or why the target was
refused; docs/control.md), so each target is sent only once the previous one is answered:
what a user's interactive loop does. Writes OUT.csv
(one row per target: wall time since the first target was sent, the answer's round-trip
time, target, reached position, error, actuation) and OUT.png (the path in the horizontal
plane over the circle, and the error against time). The output files are written under
temporary names and renamed.
"""
import argparse
import csv
import json
import math
import os
import sys
import tempfile
import time

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
sys.path.insert(0, os.path.join(ROOT, "python"))
from hydrosoft_control import Scene, SceneError, TargetRefused  # noqa: E402


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--deck", default="input/pendulum.yaml")
    ap.add_argument("--np", type=int, default=1)
    ap.add_argument("--radius", type=float, default=0.001)
    ap.add_argument("--centre", default="0,0,-0.1011")
    ap.add_argument("--points", type=int, default=40)
    ap.add_argument("--turns", type=float, default=1.0)
    ap.add_argument("--steps", type=int, default=1)
    ap.add_argument("--out", default="out/circle_tracking")
    ap.add_argument("--set", action="append", default=[], metavar="KEY=VALUE",
                    help="more deck overrides, e.g. control.free_solve=one_step")
    a = ap.parse_args()
    centre = [float(v) for v in a.centre.split(",")]
    if len(centre) != 3 or a.radius <= 0 or a.points < 2 or a.steps < 1:
        sys.exit("track_circle.py: need --centre x,y,z, --radius > 0, --points >= 2, --steps >= 1")
    rows = []
    n = int(round(a.points * a.turns))
    t0 = None
    overrides = ["control.steps_per_target=%d" % a.steps] + a.set
    folder = os.path.join(tempfile.gettempdir(), "hydrosoft_circle")
    try:
        with Scene(os.path.join(ROOT, a.deck), ranks=a.np, overrides=overrides,
                   output_folder=folder) as scene:
            for k in range(n + 1):
                phi = 2 * math.pi * k / a.points
                target = [centre[0] + a.radius * math.cos(phi),
                          centre[1] + a.radius * math.sin(phi), centre[2]]
                sent = time.perf_counter()
                t0 = sent if t0 is None else t0
                answer = scene.reach(target)
                raw = answer.raw
                # The equilibrium's error where the answer has it (one_step with
                # check_equilibrium), else the answer's own (the equilibrium in the newton mode).
                rows.append({"time_s": sent - t0, "answer_ms": answer.round_trip_ms,
                             "step_ms": answer.step_ms, "target": target,
                             "reached": raw.get("equilibrium", raw["reached"]),
                             "error_m": raw.get("equilibrium_error_m", answer.error_m),
                             "actuation": list(answer.actuation)})
    except (SceneError, TargetRefused) as e:
        sys.exit("track_circle.py: target %d: %s" % (len(rows), e))

    os.makedirs(os.path.dirname(os.path.abspath(a.out)), exist_ok=True)
    tmp = a.out + ".csv.tmp"
    with open(tmp, "w", newline="") as f:
        w = csv.writer(f)
        w.writerow(["time_s", "answer_ms", "step_ms", "target_x", "target_y", "target_z", "reached_x",
                    "reached_y", "reached_z", "error_m", "actuation_pa"])
        for r in rows:
            w.writerow(["%.4f" % r["time_s"], "%.2f" % r["answer_ms"], "%.2f" % r["step_ms"]] +
                       ["%.7g" % v for v in r["target"] + r["reached"]] +
                       ["%.4g" % r["error_m"], " ".join("%.1f" % p for p in r["actuation"])])
    os.replace(tmp, a.out + ".csv")

    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    fig, (ax1, ax2) = plt.subplots(1, 2, figsize=(10, 4.2))
    mm = 1e3
    ax1.plot([mm * r["target"][0] for r in rows], [mm * r["target"][1] for r in rows], "o",
             ms=3, color="0.6", label="targets")
    ax1.plot([mm * r["reached"][0] for r in rows], [mm * r["reached"][1] for r in rows], "-",
             color="C0", label="reached")
    ax1.set_aspect("equal")
    ax1.set_xlabel("x (mm)")
    ax1.set_ylabel("y (mm)")
    ax1.legend(loc="upper right", fontsize=8)
    ax1.set_title("effector in the horizontal plane")
    ax2.semilogy([r["time_s"] for r in rows], [max(r["error_m"], 1e-9) * mm for r in rows],
                 "-o", ms=3)
    ax2.set_xlabel("wall time (s)")
    ax2.set_ylabel("tracking error (mm)")
    ax2.set_title("error of each answer")
    ax2.grid(True, which="both", alpha=0.3)
    fig.tight_layout()
    tmp = a.out + ".tmp.png"
    fig.savefig(tmp, dpi=120)
    os.replace(tmp, a.out + ".png")
    errs = sorted(r["error_m"] for r in rows[1:])
    ms = sorted(r["answer_ms"] for r in rows[1:])
    step = sorted(r["step_ms"] for r in rows[1:])
    print("targets %d, error median %.3g mm, max %.3g mm; control step median %.1f ms, max "
          "%.1f ms; answer median %.1f ms, max %.1f ms"
          % (len(rows), mm * errs[len(errs) // 2], mm * errs[-1], step[len(step) // 2],
             step[-1], ms[len(ms) // 2], ms[-1]))


if __name__ == "__main__":
    main()
