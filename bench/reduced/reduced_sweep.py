#!/usr/bin/python3
"""A reduced model against the full model on the same `--targets -` lines (docs/reduced_models.md).

    /usr/bin/python3 bench/reduced/reduced_sweep.py [--deck input/finger_hydraulic.yaml]
        [--h 0.00135] [--lines 40] [--repeats 3] [--samples 17] [--model FILE] [--every N]
        [--pod-tolerance T] [--check-lines N] [--skip-full] [--indicators false,true]
        [--set KEY=VALUE ...]

Trains the deck's reduced model (`hydrosoft reduce`, timed; skipped with --model), then sends
the same tip-height lines, in a fixed shuffled order, to the reduced model and to the full model
(its default `newton` mode, and its real-time `one_step` mode one step a line), no per-step
pressure limit, so that each answer is the equilibrium that meets its target. The lines span the middle 90 % of the
tip's range over the actuator's bounds (measured by the training's own samples), so that none
is a training sample's position. Prints the training time, per model the medians over the
repeats of the step time's mean, median and p95 (ms, the answers' step_ms) and of the client's
round trip (which, back to back, includes writing the last line's output step: `--every N`
writes every N-th, output.every), the largest distance of a reduced answer from the full model's equilibrium at the
same actuation, and from the full model's own answer to the same line (mm); each with the
error indicator off and on, and the error each answer stated against its actual error.
1 rank, OPENBLAS_NUM_THREADS=1.
"""
import argparse
import json
import os
import random
import statistics
import subprocess
import tempfile
import time

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
EXE = os.environ.get("HYDROSOFT", os.path.join(ROOT, "build", "bin", "hydrosoft"))
ENV = dict(os.environ, OPENBLAS_NUM_THREADS="1")


def sets(overrides):
    out = []
    for o in overrides:
        out += ["--set", o]
    return out


def answers(deck, overrides, lines, folder, steps=1):
    cmd = [EXE, deck, "--targets", "-", "--set", f"output.folder={folder}",
           "--set", f"control.steps_per_target={steps}"] + sets(overrides)
    p = subprocess.Popen(cmd, stdin=subprocess.PIPE, stdout=subprocess.PIPE,
                         stderr=subprocess.DEVNULL, text=True, env=ENV)
    out = []
    for line in lines:
        t0 = time.perf_counter()
        p.stdin.write(line + "\n")
        p.stdin.flush()
        a = json.loads(p.stdout.readline())
        a["round_trip_ms"] = 1e3 * (time.perf_counter() - t0)
        out.append(a)
    p.stdin.close()
    p.wait()
    return out


def p95(v):
    v = sorted(v)
    return v[min(len(v) - 1, int(round(0.95 * (len(v) - 1))))]


def stats(v):
    return statistics.mean(v), statistics.median(v), p95(v)


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--deck", default=os.path.join(ROOT, "input", "finger_hydraulic.yaml"))
    ap.add_argument("--h", type=float, default=None, help="mesh.parameters.h")
    ap.add_argument("--lines", type=int, default=40)
    ap.add_argument("--repeats", type=int, default=3)
    ap.add_argument("--samples", type=int, default=17)
    ap.add_argument("--model", default=None, help="a model already trained for this mesh")
    ap.add_argument("--pod-tolerance", default=None, help="the training's POD tolerance")
    ap.add_argument("--every", type=int, default=1, help="output.every of the reduced runs")
    ap.add_argument("--skip-full", action="store_true")
    ap.add_argument("--indicators", default="false,true",
                    help="control.error_indicator values to time, in order")
    ap.add_argument("--full-lines", type=int, default=1000, help="lines the full model answers")
    ap.add_argument("--check-lines", type=int, default=1000,
                    help="lines whose full equilibrium is solved for the model's error")
    ap.add_argument("--full-steps", type=int, default=10, help="its control steps a line")
    ap.add_argument("--set", action="append", default=[],
                    help="a deck override for every run (training too), e.g. materials[0].nu=0.4995")
    a = ap.parse_args()
    work = tempfile.mkdtemp(prefix="reduced_sweep_")
    base = ([] if a.h is None else [f"mesh.parameters.h={a.h}"]) + a.set
    trained = list(base)
    change = "max_force_change" if "cable" in os.path.basename(a.deck) else "max_pressure_change"
    base.append(f"control.actuators[0].{change}=1e9")
    model = a.model or os.path.join(work, "model.h5")
    if not a.model:
        t0 = time.perf_counter()
        pod = [] if a.pod_tolerance is None else ["--pod-tolerance", a.pod_tolerance]
        subprocess.run([EXE, "reduce", a.deck, "-o", model, "-q", "--samples", str(a.samples),
                        "--set", f"output.folder={work}/train"] + pod + sets(trained),
                       check=True, env=ENV, stdout=subprocess.DEVNULL)
        print(f"training: {time.perf_counter() - t0:.1f} s")
        with open(f"{work}/train/summary.json") as f:
            r = json.load(f)["reduction"]
        patches = (f", patches {r['ecsw']['patches']} of {r['ecsw']['of_patches']}"
                   if r['ecsw'].get('patches') else "")
        print(f"  modes {r['pod']['modes']}, elements {r['ecsw']['elements']} of "
              f"{r['ecsw']['of']}{patches}, held-back effector error max "
              f"{1e3 * r['held_back']['max_effector_error_m']:.3f} mm")
    # The tip's range: the full model at the bounds, from the training summary's states.
    probe = answers(a.deck, base + [f"control.reduced_model={model}"], ["0.09 0 -0.03", "0.09 0 0.01"],
                    f"{work}/probe")
    z0, z1 = sorted(p["answer"]["reached"][2] for p in probe)
    lo, hi = z0 + 0.05 * (z1 - z0), z1 - 0.05 * (z1 - z0)
    zs = [lo + (hi - lo) * i / (a.lines - 1) for i in range(a.lines)]
    random.Random(1).shuffle(zs)
    lines = [f"0.09 0 {z:.6f}" for z in zs]
    reduced = base + [f"control.reduced_model={model}"]
    for indicator in a.indicators.split(","):  # the same lines without, then with, the indicator
        timing = []
        for rep in range(a.repeats):
            ans = answers(a.deck, reduced + [f"output.every={a.every}",
                                             f"control.error_indicator={indicator}"],
                          lines, f"{work}/reduced{rep}")
            timing.append(stats([x["answer"]["step_ms"] for x in ans]) +
                          stats([x["round_trip_ms"] for x in ans[1:]]))  # [0] waits for set-up
        med = [statistics.median(r[i] for r in timing) for i in range(6)]
        print(f"reduced, error_indicator {indicator}: step ms mean {med[0]:.2f} median "
              f"{med[1]:.2f} p95 {med[2]:.2f}; round trip (output step included) mean "
              f"{med[3]:.2f} median {med[4]:.2f} p95 {med[5]:.2f}")
    # The model's error: the full model's equilibrium at each answer's actuation, against the
    # error each answer stated.
    if a.check_lines == 0:
        return
    checked = answers(a.deck, reduced + ["control.check_equilibrium=true",
                                         "control.error_indicator=true"],
                      lines[:a.check_lines], f"{work}/checked")
    d = [dist(x["answer"]["reached"], x["answer"]["equilibrium"]) for x in checked]
    print(f"reduced answer vs the full equilibrium at its actuation: max {1e3 * max(d):.3f} mm, "
          f"mean {1e3 * statistics.mean(d):.3f} mm over {len(d)} lines")
    for key in ("held_back_error_m", "indicator_m", "estimated_error_m"):
        stated = [x["answer"]["reduced"][key] for x in checked]
        ratios = [e / s for e, s in zip(d, stated) if s]
        if ratios:
            print(f"  {key}: max {1e3 * max(s for s in stated if s):.4f} mm; actual / it min "
                  f"{min(ratios):.2f} median {statistics.median(ratios):.2f} max "
                  f"{max(ratios):.2f}; actual above it on {sum(r > 1 for r in ratios)} of "
                  f"{len(ratios)} lines")
    if a.skip_full:
        return
    # The full model's own answers (default newton mode, steps until the target is met).
    full_lines = lines[:a.full_lines]
    t0 = time.perf_counter()
    full = answers(a.deck, base, full_lines, f"{work}/full", steps=a.full_steps)
    elapsed = time.perf_counter() - t0
    steps = [x["answer"]["step_ms"] for x in full]
    d = [dist(x["answer"]["reached"], y["answer"]["reached"]) for x, y in zip(checked, full)]
    e = [x["answer"]["error_m"] for x in full]
    print(f"full ({a.full_steps} steps a line, {len(full)} lines, {elapsed:.0f} s): step ms "
          f"median {statistics.median(steps):.1f}; largest distance to target "
          f"{1e3 * max(e):.3f} mm")
    print(f"reduced vs full answers: max {1e3 * max(d):.3f} mm, mean "
          f"{1e3 * statistics.mean(d):.3f} mm over {len(d)} lines")
    # The full model's real-time mode (free_solve: one_step, refined to the equilibrium), one
    # step a line as the reduced model answers.
    fast = answers(a.deck, base + ["control.free_solve=one_step"], full_lines, f"{work}/one_step")
    steps = [x["answer"]["step_ms"] for x in fast]
    e = [x["answer"]["error_m"] for x in fast]
    d = [dist(x["answer"]["reached"], y["answer"]["reached"]) for x, y in zip(checked, fast)]
    mean, median, tail = stats(steps)
    print(f"full one_step (1 step a line, {len(fast)} lines): step ms mean {mean:.1f} median "
          f"{median:.1f} p95 {tail:.1f}; largest distance to target {1e3 * max(e):.3f} mm")
    print(f"reduced vs one_step answers: max {1e3 * max(d):.3f} mm, mean "
          f"{1e3 * statistics.mean(d):.3f} mm over {len(d)} lines")


def dist(x, y):
    return sum((x[i] - y[i]) ** 2 for i in range(3)) ** 0.5


if __name__ == "__main__":
    main()
