#!/usr/bin/python3
"""Steers the pendulum's bottom along a figure eight and plots target against reached.

    /usr/bin/python3 python/examples/figure_eight.py [--deck input/pendulum.yaml] [--ranks 1]
        [--size 0.001] [--centre 0,0,-0.1011] [--points 40] [--out out/figure_eight]
        [--set KEY=VALUE ...]

Uses the hydrosoft_control package (python/hydrosoft_control): one target a point of the
figure eight x = a sin t, y = a sin t cos t in the horizontal plane through the centre,
each sent once the last one is answered. Writes OUT.csv (one row per target: target,
reached, error, actuation, round trip) and OUT.png (the path over the targets, and the
error of each answer); nothing into docs/ unless --out says so.
"""
import argparse
import csv
import math
import os
import sys

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), ".."))
from hydrosoft_control import Scene  # noqa: E402

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--deck", default=os.path.join(ROOT, "input", "pendulum.yaml"))
    ap.add_argument("--ranks", type=int, default=1)
    ap.add_argument("--size", type=float, default=0.001, help="half width a of the eight (m)")
    ap.add_argument("--centre", default="0,0,-0.1011")
    ap.add_argument("--points", type=int, default=40)
    ap.add_argument("--out", default="out/figure_eight")
    ap.add_argument("--set", action="append", default=[], metavar="KEY=VALUE")
    a = ap.parse_args()
    centre = [float(v) for v in a.centre.split(",")]
    if len(centre) != 3 or a.size <= 0 or a.points < 4:
        sys.exit("figure_eight.py: need --centre x,y,z, --size > 0 and --points >= 4")

    rows = []
    with Scene(a.deck, ranks=a.ranks, overrides=["control.steps_per_target=1"] + a.set) as scene:
        for k in range(a.points + 1):
            t = 2 * math.pi * k / a.points
            target = [centre[0] + a.size * math.sin(t),
                      centre[1] + a.size * math.sin(t) * math.cos(t), centre[2]]
            rows.append(scene.reach(target))
    # The run's folder was temporary and went with the scene; its summary stays.
    print("run %s: %d targets answered" % (scene.summary["status"],
                                           scene.summary["input"]["answered"]))

    os.makedirs(os.path.dirname(os.path.abspath(a.out)), exist_ok=True)
    with open(a.out + ".csv.tmp", "w", newline="") as f:
        w = csv.writer(f)
        w.writerow(["line", "target_x_m", "target_y_m", "target_z_m", "reached_x_m", "reached_y_m",
                    "reached_z_m", "error_m", "round_trip_ms", "actuation"])
        for r in rows:
            w.writerow([r.line] + ["%.7g" % v for v in list(r.target) + list(r.reached)] +
                       ["%.4g" % r.error_m, "%.1f" % r.round_trip_ms,
                        " ".join("%.1f" % p for p in r.actuation)])
    os.replace(a.out + ".csv.tmp", a.out + ".csv")

    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    mm = 1e3
    fig, (ax1, ax2) = plt.subplots(1, 2, figsize=(10, 4.2))
    ax1.plot([mm * r.target[0] for r in rows], [mm * r.target[1] for r in rows], "o", ms=4,
             color="0.6", label="target")
    ax1.plot([mm * r.reached[0] for r in rows], [mm * r.reached[1] for r in rows], "-x", ms=4,
             color="C0", label="reached")
    ax1.set_aspect("equal")
    ax1.set_xlabel("x (mm)")
    ax1.set_ylabel("y (mm)")
    ax1.legend(loc="upper center", fontsize=8)
    ax1.set_title("pendulum bottom, horizontal plane z = %.1f mm" % (mm * centre[2]))
    ax2.semilogy([r.line for r in rows], [max(r.error_m, 1e-9) * mm for r in rows], "-o", ms=3)
    ax2.set_xlabel("target (input line)")
    ax2.set_ylabel("error (mm)")
    ax2.set_title("distance from target after one control step")
    ax2.grid(True, which="both", alpha=0.3)
    fig.tight_layout()
    fig.savefig(a.out + ".tmp.png", dpi=120)
    os.replace(a.out + ".tmp.png", a.out + ".png")
    errors = sorted(r.error_m for r in rows[2:])
    trips = sorted(r.round_trip_ms for r in rows[2:])
    print("targets %d; after the first two: error median %.3g mm, max %.3g mm; round trip "
          "median %.0f ms" % (len(rows), mm * errors[len(errors) // 2], mm * errors[-1],
                              trips[len(trips) // 2]))
    print("wrote %s.csv and %s.png" % (a.out, a.out))


if __name__ == "__main__":
    main()
