#!/usr/bin/python3
"""FEM core benchmark: assembly rate, Newton solve time and peak memory over a refinement
series, on 1 and 2 ranks, with MUMPS (LU) and with GAMG (CG/GMRES + rigid-body near-null space).

    /usr/bin/python3 bench/fem/run_benchmark.py [--sizes 0.1 0.05 ...] [--repeats 3]

Writes bench/fem/results.csv and prints a Markdown table (medians over the repeats) for
docs/benchmarks.md. Timings come from each run's summary.json.
"""
import argparse
import csv
import json
import os
import platform
import statistics
import subprocess
import sys

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(os.path.dirname(HERE))


def run(binary, deck, np, order, h, preset, folder):
    cmd = ["mpirun", "--oversubscribe", "-np", str(np)]
    if os.geteuid() == 0:
        cmd.append("--allow-run-as-root")
    cmd += [binary, deck, "--set", f"mesh.order={order}", "--set", f"mesh.parameters.h={h}",
            "--set", f"solver.preset={preset}", "--set", f"output.folder={folder}"]
    env = dict(os.environ, OPENBLAS_NUM_THREADS="1")
    r = subprocess.run(cmd, capture_output=True, text=True, env=env)
    if r.returncode != 0:
        sys.exit(f"run_benchmark: {' '.join(cmd)} failed:\n{r.stderr[-3000:]}")
    with open(os.path.join(folder, "summary.json")) as f:
        return json.load(f)


def cpu_name():
    try:
        with open("/proc/cpuinfo") as f:
            for line in f:
                if line.startswith("model name"):
                    return line.split(":", 1)[1].strip()
    except OSError:
        pass
    return platform.processor()


def main():
    p = argparse.ArgumentParser(description=__doc__)
    p.add_argument("--binary", default=os.path.join(ROOT, "build/bin/hydrosoft"))
    p.add_argument("--deck", default=os.path.join(HERE, "bench_sphere.yaml"))
    p.add_argument("--order", type=int, default=1)
    p.add_argument("--sizes", type=float, nargs="+", default=[0.1, 0.05, 0.035, 0.025, 0.02])
    p.add_argument("--ranks", type=int, nargs="+", default=[1, 2])
    p.add_argument("--presets", nargs="+", default=["mumps", "gamg"])
    p.add_argument("--repeats", type=int, default=3)
    p.add_argument("--mumps-min-h", type=float, default=0.035,
                   help="skip MUMPS below this mesh size (its 3D fill outgrows 24 GB near 1M dofs)")
    p.add_argument("--single-run-min-elements", type=float, default=1.0e6,
                   help="above this many elements, one run instead of --repeats")
    p.add_argument("--out", default=os.path.join(ROOT, "out/bench_fem"))
    args = p.parse_args()

    rows = []
    for h in args.sizes:
        for preset in args.presets:
            if preset == "mumps" and h < args.mumps_min_h:
                continue
            for np in args.ranks:
                folder = lambda k: os.path.join(args.out, f"h{h}_{preset}_np{np}_{k}")
                runs = [run(args.binary, args.deck, np, args.order, h, preset, folder(0))]
                repeats = 1 if runs[0]["elements"] > args.single_run_min_elements else args.repeats
                runs += [run(args.binary, args.deck, np, args.order, h, preset, folder(k))
                         for k in range(1, repeats)]
                med = lambda f: statistics.median(f(s) for s in runs)
                row = dict(repeats=len(runs), order=args.order, h=h, dofs=runs[0]["dofs"], elements=runs[0]["elements"],
                           ranks=np, preset=preset, newton=runs[0]["newton_iterations"],
                           linear=runs[0]["linear_iterations"],
                           elements_per_s=med(lambda s: s["assembly"]["elements_per_second"]),
                           assembly_s=med(lambda s: s["time_s"]["assembly"]),
                           solve_s=med(lambda s: s["time_s"]["solve"]),
                           total_s=med(lambda s: s["time_s"]["total"]),
                           peak_mb=med(lambda s: s["memory_mb"]["peak_total"]))
                rows.append(row)
                print(json.dumps(row), flush=True)

    with open(os.path.join(HERE, "results.csv"), "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=list(rows[0].keys()))
        w.writeheader()
        w.writerows(rows)
    print(f"\nMachine: {cpu_name()}, {os.cpu_count()} cores; medians over the runs\n")
    print("| dofs | elements | ranks | solver | runs | Newton its | KSP its | assembly (elem/s) | "
          "assembly s | solve s | total s | peak memory MB |")
    print("|---|---|---|---|---|---|---|---|---|---|---|---|")
    for r in rows:
        print(f"| {r['dofs']} | {r['elements']} | {r['ranks']} | {r['preset']} | {r['repeats']} | "
              f"{r['newton']} | {r['linear']} | {r['elements_per_s']:.3g} | {r['assembly_s']:.2f} | "
              f"{r['solve_s']:.2f} | {r['total_s']:.2f} | {r['peak_mb']:.0f} |")


if __name__ == "__main__":
    main()
