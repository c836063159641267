#!/usr/bin/python3
"""Error against time of reduced models as their basis and sampled elements vary
(docs/reduced_models.md, "Error against run time").

    /usr/bin/python3 bench/reduced/pareto.py [--h H] [--lines 20] [--out docs/figures/reduced_pareto.png]

Trains the hydraulic finger's model at each POD tolerance (the basis size) and ECSW tolerance
(the number of elements), answers the same shuffled tip-height lines with it (one control step
a line, no per-step pressure limit), and measures each answer against the full model's
equilibrium at its pressure (control.check_equilibrium). Prints a CSV row per model: the
tolerances, modes, elements, the median and mean step time (ms) of a timed run, and the
largest and mean error (mm); draws error against mean step time. 1 rank.
"""
import argparse
import json
import os
import statistics
import subprocess
import tempfile

import reduced_sweep as rs


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--h", type=float, default=None)
    ap.add_argument("--lines", type=int, default=20)
    ap.add_argument("--pod", default="1e-4,1e-6,1e-8,1e-10")
    ap.add_argument("--ecsw", default="1e-3,1e-4,1e-5,1e-6,1e-7")
    ap.add_argument("--out", default=None, help="a PNG of error against step time")
    a = ap.parse_args()
    work = tempfile.mkdtemp(prefix="reduced_pareto_")
    deck = os.path.join(rs.ROOT, "input", "finger_hydraulic.yaml")
    base = [] if a.h is None else [f"mesh.parameters.h={a.h}"]
    base.append("control.actuators[0].max_pressure_change=1e9")
    zs = None
    rows = []
    print("pod_tolerance,ecsw_tolerance,modes,elements,step_ms_median,step_ms_mean,"
          "error_max_mm,error_mean_mm")
    for pod in a.pod.split(","):
        for ecsw in a.ecsw.split(","):
            model = f"{work}/m_{pod}_{ecsw}.h5"
            trained = subprocess.run(
                [rs.EXE, "reduce", deck, "-o", model, "-q", "--pod-tolerance", pod,
                 "--ecsw-tolerance", ecsw, "--set", f"output.folder={work}/t"] +
                rs.sets(base[:-1]), env=rs.ENV, stdout=subprocess.DEVNULL,
                stderr=subprocess.DEVNULL)
            if trained.returncode != 0:
                print(f"{pod},{ecsw},training failed")
                continue
            with open(f"{work}/t/summary.json") as f:
                r = json.load(f)["reduction"]
            if r["held_back"].get("unsolved", 0):
                print(f"{pod},{ecsw},{r['pod']['modes']},{r['ecsw']['elements']},"
                      f"unsolved at {r['held_back']['unsolved']} held-back samples")
                continue
            reduced = base + [f"control.reduced_model={model}"]
            if zs is None:
                probe = rs.answers(deck, reduced, ["0.09 0 -0.03", "0.09 0 0.01"], f"{work}/p")
                z0, z1 = sorted(p["answer"]["reached"][2] for p in probe)
                lo, hi = z0 + 0.05 * (z1 - z0), z1 - 0.05 * (z1 - z0)
                zs = [lo + (hi - lo) * i / (a.lines - 1) for i in range(a.lines)]
                import random
                random.Random(1).shuffle(zs)
            lines = [f"0.09 0 {z:.6f}" for z in zs]
            timed = rs.answers(deck, reduced, lines, f"{work}/r")
            steps = [x["answer"]["step_ms"] for x in timed]
            checked = rs.answers(deck, reduced + ["control.check_equilibrium=true"], lines,
                                 f"{work}/c")
            d = [rs.dist(x["answer"]["reached"], x["answer"]["equilibrium"]) for x in checked]
            row = (pod, ecsw, r["pod"]["modes"], r["ecsw"]["elements"],
                   statistics.median(steps), statistics.mean(steps), 1e3 * max(d),
                   1e3 * statistics.mean(d))
            rows.append(row)
            print("%s,%s,%d,%d,%.2f,%.2f,%.4f,%.4f" % row, flush=True)
    if a.out:
        import matplotlib
        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
        fig, ax = plt.subplots(figsize=(6, 4))
        for pod in a.pod.split(","):
            pts = [(r[5], r[6]) for r in rows if r[0] == pod]
            ax.loglog([p[0] for p in pts], [p[1] for p in pts], "o-",
                      label=f"POD {pod} ({[r[2] for r in rows if r[0] == pod][0]} modes)")
        ax.set_xlabel("mean control step (ms)")
        ax.set_ylabel("largest distance from the full equilibrium (mm)")
        ax.set_title("hydraulic finger: ECSW tolerance along each line")
        ax.grid(True, which="both", alpha=0.3)
        ax.legend(fontsize=8)
        fig.tight_layout()
        fig.savefig(a.out, dpi=110)


if __name__ == "__main__":
    main()
