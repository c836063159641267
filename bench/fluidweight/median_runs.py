#!/usr/bin/env python3
"""Medians, cell by cell, of several runs of bench_fluidweight --out (JSON lines), printed as
the markdown tables of docs/fluidweight.md ("Benchmark"), with the smallest and largest value
of the armadillo's and the sphere's one-thread CPU column beside them.

    median_runs.py run1.jsonl run2.jsonl run3.jsonl > tables.md
"""
import json
import statistics
import sys

runs = [[json.loads(line) for line in open(path) if line.strip()] for path in sys.argv[1:]]


def key(r):
    return tuple((k, r[k]) for k in ("table", "mesh", "grid") if k in r)


rows = {}  # key -> list of records, one per run
order = []
for run in runs:
    for r in run:
        if "table" not in r:
            continue
        k = key(r)
        if k not in rows:
            rows[k] = []
            order.append(k)
        rows[k].append(r)


def med(k, field):
    values = [r[field] for r in rows[k] if field in r]
    return statistics.median(values) if values else float("nan")


def spread(k, field):
    values = [r[field] for r in rows[k] if field in r]
    return min(values), max(values)


kernels = ["lev f32 us", "lev f64 us", "tri f32 us", "tri f64 us", "tiled f32 us", "tiled f64 us"]
print(f"runs: {len(runs)}")
for mesh in ("sphere, radius 1", "armadillo"):
    print(f"\n### {mesh}\n")
    print("| grid | column volume | rel. error | CPU 1 thr ms (min-max) | CPU 16 thr ms | lev f32 us |"
          " lev f64 us | tri f32 us | tri f64 us | tiled f32 us | tiled f64 us | call ms |")
    print("|---|---|---|---|---|---|---|---|---|---|---|---|")
    for k in order:
        d = dict(k)
        if d["table"] != "I" or d["mesh"] != mesh:
            continue
        r = rows[k][0]
        error = (r["volume"] - abs(r["signed_volume"])) / abs(r["signed_volume"])
        lo, hi = spread(k, "cpu1_ms")
        cells = " | ".join(f"{med(k, f):.1f}" for f in kernels)
        print(f"| {d['grid']}^2 | {r['volume']:.6f} | {error:.2e} | {med(k, 'cpu1_ms'):.2f} "
              f"({lo:.2f}-{hi:.2f}) | {med(k, 'cpu_all_ms'):.2f} | {cells} | {med(k, 'call_ms'):.3f} |")
print("\n### Four cavities at 200^2\n")
for k in order:
    d = dict(k)
    if d["table"] == "batch":
        cells = " | ".join(f"{med(k, f):.1f}" for f in kernels)
        print(f"| {d['mesh']} | {med(k, 'cpu1_ms'):.2f} | {med(k, 'cpu_all_ms'):.2f} | {cells} |")
print("\n### Kernels on meshes\n")
for k in order:
    d = dict(k)
    if d["table"] == "kernels":
        cells = " | ".join(f"{med(k, f):.1f}" for f in kernels)
        print(f"| {d['mesh']} | {d['grid']}^2 | {cells} |")
print("\n### Alpha\n")
alphas = ["alpha 0.062500", "alpha 0.125000", "alpha 0.250000", "alpha 0.500000", "alpha 1.000000",
          "alpha 2.000000"]
for k in order:
    d = dict(k)
    if d["table"] == "alpha":
        cells = " | ".join(f"{med(k, f):.1f}" for f in alphas)
        print(f"| {d['mesh']} {d['grid']}^2 | {cells} |")
print("\n### Error against run time\n")
error_rows = {}
for k in order:
    d = dict(k)
    if d["table"] == "error":
        error_rows.setdefault(d["grid"], {})[d["mesh"]] = k
for grid, by_mesh in error_rows.items():
    cells = []
    for mesh in ("sphere", "armadillo"):
        k = by_mesh.get(mesh)
        if k is None:
            cells.append("| | | | ")
            continue
        cells.append(f"{med(k, 'force_error'):.2e} | {med(k, 'cpu1_ms'):.2f} | {med(k, 'cpu_all_ms'):.2f}"
                     f" | {med(k, 'tiled f32 us'):.1f} | {med(k, 'tiled f64 us'):.1f}")
    print(f"| {grid}^2 | " + " | ".join(cells) + " |")
print("\n### Hydrostatic\n")
for k in order:
    d = dict(k)
    if d["table"] == "hydrostatic":
        print(f"| {d['mesh']} | {med(k, 'cpu1_ms'):.3f} | {med(k, 'float32 us'):.1f} | "
              f"{med(k, 'float64 us'):.1f} |")
