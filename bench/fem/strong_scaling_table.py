#!/usr/bin/python3
"""The strong-scaling table of docs/benchmarks.md from the folder of bench/fem/strong_scaling.sh:

    /usr/bin/python3 bench/fem/strong_scaling_table.py OUTDIR [OUTDIR ...]

One row per mesh size and rank count: dofs, Newton and Krylov iterations, the whole run and its
parts (s), speed-up of the whole run and of the solve against 1 rank, peak memory of the
largest rank (MB); with several folders (repeats), each size and rank count's run of median
whole time; where the runs had contact, its own seconds (time_s.contact) and share of the
whole run.
"""
import glob
import json
import os
import re
import sys


def main(folders):
    repeats = {}
    for folder in folders:
        for path in glob.glob(os.path.join(folder, "h*_np*.json")):
            h, n = re.match(r"h([^_]+)_np(\d+)\.json", os.path.basename(path)).groups()
            with open(path) as f:
                repeats.setdefault((h, int(n)), []).append(json.load(f))
    runs = {}
    for key, found in repeats.items():
        found.sort(key=lambda r: r["time_s"]["total"])
        runs[key] = found[(len(found) - 1) // 2]
    contact = any("contact" in r["time_s"] for r in runs.values())
    print("| dofs | ranks | Newton its | KSP its | read s | partition s | setup s | assembly s |"
          " solve s | output s | whole s | speed-up whole | speed-up solve |"
          " peak MB (largest rank) |" + (" contact s | contact share |" if contact else ""))
    print("|---" * (16 if contact else 14) + "|")
    for h, n in sorted(runs, key=lambda k: (runs[k]["dofs"], k[1])):
        s, t = runs[(h, n)], runs[(h, n)]["time_s"]
        one = runs.get((h, 1))
        up = lambda key: f"{one['time_s'][key] / t[key]:.1f}" if one else ""
        part = t.get("setup_partition", 0) + t.get("setup_distribute", 0)
        print(f"| {s['dofs']:,} | {n} | {s['newton_iterations']} | {s['linear_iterations']} |"
              f" {t['setup_mesh']:.2f} | {part:.2f} | {t['setup']:.2f} | {t['assembly']:.2f} |"
              f" {t['solve']:.2f} | {t.get('output', 0):.2f} | {t['total']:.2f} |"
              f" {up('total')} | {up('solve')} | {s['memory_mb']['peak_rank_max']:.0f} |" +
              (f" {t['contact']:.3f} | {100 * t['contact'] / t['total']:.2g} % |" if contact else ""))


if __name__ == "__main__":
    main(sys.argv[1:])
