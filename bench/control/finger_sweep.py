#!/usr/bin/python3
"""The hydraulic finger's tip height swept in 0.35 mm lines through `--targets -` (docs/control.md).

    /usr/bin/python3 bench/control/finger_sweep.py [--repeats 3]

From -18.0 mm (next to its rest, -18.1 mm) up to -6.0 mm, one line each, one control step a
line, 1 rank (OPENBLAS_NUM_THREADS=1), per mode: the default (`newton`), `one_step`, and
`one_step/threads` (`factor_threads: 1`). Each repeat runs the sweep twice: once timed, once with
check_equilibrium (each answer's distance from the equilibrium at its actuation). Prints per
mode the medians over the repeats of the step time's mean, median and p95 (ms), the largest
distance of an answer from its target, of its equilibrium from the target and of the answer
from its equilibrium (mm; the default mode answers the equilibrium), and whether the
actuation rose at every line.
"""
import argparse
import json
import math
import os
import statistics
import subprocess

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
MODES = {"newton": [],  # the default
         "one_step": ["control.free_solve=one_step"],
         "one_step/threads": ["control.free_solve=one_step", "control.factor_threads=1"]}


def run(overrides, lines, folder):
    exe = os.environ.get("HYDROSOFT", os.path.join(ROOT, "build", "bin", "hydrosoft"))
    cmd = [exe, os.path.join(ROOT, "input", "finger_hydraulic.yaml"), "--targets", "-",
           "--set", f"output.folder={folder}", "--set", "control.steps_per_target=1"]
    for o in overrides:
        cmd += ["--set", o]
    env = dict(os.environ, OPENBLAS_NUM_THREADS="1")
    p = subprocess.Popen(cmd, stdin=subprocess.PIPE, stdout=subprocess.PIPE,
                         stderr=subprocess.DEVNULL, text=True, env=env)
    answers = []
    for line in lines:
        p.stdin.write(line + "\n")
        p.stdin.flush()
        answers.append(json.loads(p.stdout.readline()))
    p.stdin.close()
    p.wait()
    return answers


def p95(v):
    v = sorted(v)
    return v[min(len(v) - 1, int(round(0.95 * (len(v) - 1))))]


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--repeats", type=int, default=3)
    ap.add_argument("--out", default=os.path.join(ROOT, "out", "finger_sweep"))
    ap.add_argument("--modes", default=",".join(MODES), help="comma-separated, of: " +
                    ", ".join(MODES))
    ap.add_argument("--set", action="append", default=[], help="an override for every run")
    a = ap.parse_args()
    n = round((18.0 - 6.0) / 0.35)
    lines = [f"0.09 0 {(-18.0 + 12.0 * k / n) * 1e-3:.7f}" for k in range(n + 1)]
    print("| mode | step mean (ms) | median | p95 | max answer - target (mm) | max equilibrium - "
          "target | max answer - equilibrium | actuation monotone |")
    print("|---|---|---|---|---|---|---|---|")
    for mode in a.modes.split(","):
        overrides = MODES[mode] + a.set
        rows = []
        for r in range(a.repeats):
            timed = run(overrides, lines, f"{a.out}/{r}")
            checked = run(overrides + (["control.check_equilibrium=true"] if "one_step" in mode
                                       else []), lines, f"{a.out}/{r}c")
            ans = [x["answer"] for x in timed]
            chk = [x["answer"] for x in checked]
            t = [x["step_ms"] for x in ans]
            p = [x["actuation"][0] for x in chk]
            eq = [x.get("equilibrium_error_m", x["error_m"]) for x in chk]
            apart = [math.dist(x["reached"], x.get("equilibrium", x["reached"])) for x in chk]
            rows.append((statistics.mean(t), statistics.median(t), p95(t),
                         1e3 * max(x["error_m"] for x in chk), 1e3 * max(eq), 1e3 * max(apart),
                         all(b >= c for b, c in zip(p[1:], p[:-1]))))
        med = [statistics.median(r[i] for r in rows) for i in range(6)]
        print(f"| {mode} | {med[0]:.1f} | {med[1]:.1f} | {med[2]:.1f} | {med[3]:.3f} | "
              f"{med[4]:.3f} | {med[5]:.3f} | {'yes' if all(r[6] for r in rows) else 'no'} |",
              flush=True)


if __name__ == "__main__":
    main()
