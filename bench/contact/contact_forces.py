#!/usr/bin/python3
"""Contact in the controller two ways (docs/control.md, "Contact forces in the QP").

    /usr/bin/python3 bench/contact/contact_forces.py [--repeats 3]

control.contact_forces `free_step` (the barrier inside each free configuration, the compliance
including it) against `qp` (the obstacles' normal forces among the QP's unknowns, under
complementarity), 1 rank (OPENBLAS_NUM_THREADS=1), on two scenes:

- `grasp`: input/gripper_grasp.yaml as shipped (0.04, 0.08, then 0.06/0.03 N per finger, six
  steps a set). Per mode, medians over the repeats: the run, the step's median and its free
  solve, assembly and QP parts (ms; the QP's with the candidates' responses), each set's pressures and largest force error, and the gap at which the fingers
  press (the smallest gap of a contact node; with qp also the largest gap of a loaded node).
- `landing`: a finger resting on a ball, its tip steered to -9 mm (pressed on the ball), up off
  it, and down onto it at -10 mm. Per mode, and for the barrier at its default reach and two
  smaller ones (contact.distance), each set's pressure after eight steps a set, and the tip's
  distance from the first and the last target after 1, 2, 3, 4 and 8 steps a set.
"""
import argparse
import os
import statistics

from runs import ROOT, run, shipped_deck

LANDING = """mesh:
  file: {root}/meshes/finger.geo
  order: 1
  parameters: {{h: 0.004}}
materials:
  - {{group: body, model: neo_hookean, E: 2.0e5, nu: 0.45, density: 1070}}
boundary:
  - {{group: base}}
loads: {{gravity: [0, 0, -9.81]}}
cavities:
  - {{group: cavity, kind: pneumatic}}
obstacles:
  - {{name: ball, type: sphere, center: [0.07, 0, -0.026], radius: 0.01}}
contact: {{surfaces: [outer, tip]}}
states:
  - {{name: rest, steps: 4}}
control:
  effectors:
    - {{name: tip, point: effector, directions: [z]}}
  actuators:
    - {{cavity: cavity, min_pressure: 0, max_pressure: 30000}}
  targets:
    - {{tip: [0.09, 0, -0.009]}}
    - {{tip: [0.09, 0, -0.002]}}
    - {{tip: [0.09, 0, -0.0015]}}
    - {{tip: [0.09, 0, -0.010]}}
"""
STEPS = (1, 2, 3, 4, 8)


def grasp(a):
    deck = shipped_deck("gripper_grasp", a.out, "grasp")
    print("grasp: input/gripper_grasp.yaml, medians of %d runs" % a.repeats)
    print("%-10s %6s %7s %7s %7s %7s %-40s %9s %9s %9s" %
          ("mode", "run s", "step ms", "free", "assem.", "qp", "pressures per set (kPa)",
           "force err", "min gap", "loaded"))
    for mode in ("free_step", "qp"):
        rows = []
        for r in range(a.repeats):
            s = run(deck, ["control.contact_forces=" + mode], os.path.join(a.out, f"g_{mode}_{r}"))
            answers = s["targets"]
            split = s["step_time_ms"]["split_median"]
            rows.append((s["time_s"]["total"], s["step_time_ms"]["median"], split["free_solve"],
                         split["assembly"], split["qp"]))
        t = [statistics.median(x) for x in zip(*rows)]
        pressures = " ".join("%.2f/%.2f" % (answers[k]["actuation"][0] / 1e3,
                                            answers[k]["actuation"][1] / 1e3)
                             for k in range(0, len(answers), 2))
        error = max(t2["error_N"] for t2 in answers)
        contact = s["contact"]
        print("%-10s %6.2f %7.1f %7.1f %7.1f %7.1f %-40s %9.2g %9.2g %9s" %
              (mode, t[0], t[1], t[2], t[3], t[4], pressures, error, contact["min_gap_m"],
               "%.2g" % contact["loaded_gap_m"] if "loaded_gap_m" in contact else "-"))


def landing(a):
    deck = os.path.join(a.out, "landing.yaml")
    with open(deck, "w") as f:
        f.write(LANDING.format(root=ROOT))
    print("\nlanding: each set's pressure (kPa) after %d steps, and the tip's distance from its "
          "target after 1, 2, 3, 4, %d steps a set (um): set 1 (pressed on the ball) | set 4 "
          "(landing on it)" % (STEPS[-1], STEPS[-1]))
    modes = [("free_step", []), ("free_step dhat 30 um", ["contact.distance=3e-5"]),
             ("free_step dhat 10 um", ["contact.distance=1e-5"]), ("qp", [])]
    for name, extra in modes:
        errors = []
        for steps in STEPS:
            folder = os.path.join(a.out, "landing_%s_%d" % (name.replace(" ", "_"), steps))
            s = run(deck, ["control.contact_forces=" + name.split()[0],
                           "control.steps_per_target=%d" % steps] + extra, folder)
            answers = s["targets"]
            errors.append((1e6 * answers[0]["error_m"], 1e6 * answers[3]["error_m"]))
        pressures = " ".join("%.2f" % (t["actuation"][0] / 1e3) for t in answers)
        print("%-22s %-24s %s | %s" % (name, pressures,
                                       " ".join("%.3g" % e[0] for e in errors),
                                       " ".join("%.3g" % e[1] for e in errors)))


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--repeats", type=int, default=3)
    ap.add_argument("--out", default=os.path.join(ROOT, "out", "contact_forces"))
    a = ap.parse_args()
    os.makedirs(a.out, exist_ok=True)
    grasp(a)
    landing(a)


if __name__ == "__main__":
    main()
