#!/usr/bin/python3
"""The two-finger gripper of input/gripper_grasp.yaml steered through a sweep (docs/control.md).

    /usr/bin/python3 bench/contact/gripper_sweep.py [--repeats 3] [--set KEY=VALUE ...]

Two scenes on the same mesh, one control step a target set, 1 rank (OPENBLAS_NUM_THREADS=1):
`grasp`, each finger's grasp force on the ball from 0.02 N up to 0.08 N and back to 0.03 N
(the first lines close the 0.5 mm gap), and `free`, the ball taken away and each fingertip's
position across the gap steered from 17 mm to 11 mm and back, over the range that the grasp
pressures span. Per scene and mode (the default `newton`, `one_step` with check_equilibrium,
and, on the grasp, `qp`: control.contact_forces qp with newton), the medians over the repeats of the step time's mean, median and p95 (ms)
and, over the target sets after the third, the largest distance of an answer from its target
and from the equilibrium at its pressures (N or mm).
"""
import argparse
import os
import statistics

from runs import ROOT, run, shipped_deck

MODES = {"newton": [], "one_step": ["control.free_solve=one_step",
                                    "control.check_equilibrium=true"],
         "qp": ["control.contact_forces=qp"]}
FORCES = [0.02, 0.03, 0.04, 0.05, 0.06, 0.07, 0.08, 0.07, 0.06, 0.05, 0.04, 0.03]
TIPS = [0.017, 0.016, 0.015, 0.014, 0.013, 0.012, 0.011, 0.012, 0.013, 0.014, 0.015, 0.016]


def scene_deck(scene, folder):
    """The shipped deck with the scene's effectors and targets (and, for `free`, no ball)."""
    return shipped_deck("gripper_grasp", folder, scene, lambda text: scene_text(scene, text))


def scene_text(scene, text):
    head = text[:text.index("\ncontrol:\n") + 1]
    tail = text[text.index("  actuators:"):text.index("  targets:")]
    if scene == "free":
        head = head[:head.index("obstacles:")] + head[head.index("states:"):]
        effectors = ("    - {name: tl, point: tip_left, directions: [y]}\n"
                     "    - {name: tr, point: tip_right, directions: [y]}\n")
        sets = "".join("    - {tl: [0, %g, 0], tr: [0, %g, 0]}\n" % (y, -y) for y in TIPS)
    else:
        effectors = ("    - {name: gl, obstacle: ball, surfaces: [skin_left], directions: [y]}\n"
                     "    - {name: gr, obstacle: ball, surfaces: [skin_right], directions: [y]}\n")
        sets = "".join("    - {gl: [0, %g, 0], gr: [0, %g, 0]}\n" % (-f, f) for f in FORCES)
    return (head + "control:\n  effectors:\n" + effectors + tail + "  targets:\n" + sets +
            "  steps_per_target: 1\n")


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--repeats", type=int, default=3)
    ap.add_argument("--out", default=os.path.join(ROOT, "out", "gripper_sweep"))
    ap.add_argument("--set", action="append", default=[], help="an override for every run")
    a = ap.parse_args()
    os.makedirs(a.out, exist_ok=True)
    print("%-6s %-9s %9s %9s %9s %12s %12s" % ("scene", "mode", "mean ms", "median", "p95",
                                              "to target", "to equil."))
    for scene in ("grasp", "free"):
        deck = scene_deck(scene, a.out)
        unit, scale = ("N", 1.0) if scene == "grasp" else ("mm", 1e3)
        for mode, overrides in MODES.items():
            if mode == "qp" and scene == "free":
                continue  # no obstacle: no contact forces to solve for
            stats = []
            for r in range(a.repeats):
                s = run(deck, overrides + a.set, os.path.join(a.out, f"{scene}_{mode}_{r}"))
                times = s["step_time_ms"]
                later = s["targets"][6:]  # the fourth set on: the first ones close the gap
                target = max(abs(t["reached"][1] - t["target"][1]) for t in later)
                equil = max((abs(t["reached"][1] - t["equilibrium"][1]) for t in later
                             if "equilibrium" in t), default=0.0)
                stats.append((times["mean"], times["median"], times["p95"], target, equil))
            m = [statistics.median(x) for x in zip(*stats)]
            print("%-6s %-9s %9.1f %9.1f %9.1f %9.3g %-2s %9.3g %-2s" %
                  (scene, mode, m[0], m[1], m[2], m[3] * scale, unit, m[4] * scale, unit))


if __name__ == "__main__":
    main()
