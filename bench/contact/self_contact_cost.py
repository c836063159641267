#!/usr/bin/python3
"""What self-contact costs a run: input/pneunet_self_contact.yaml against the same deck without
its `contact` section, where the chamber walls pass through each other (docs/contact.md).

    /usr/bin/python3 bench/contact/self_contact_cost.py [--repeats 3] [--ranks 1] [--set KEY=VALUE ...]

Per scene, the medians over the repeats of the run's wall time and of its Newton iterations,
the time an iteration takes, the assembly and solve shares, and the tip's rotation; 1 BLAS
thread a rank (OPENBLAS_NUM_THREADS=1).
"""
import argparse
import os
import statistics
import tempfile

from runs import run, shipped_deck


def scene_deck(scene, folder):
    """The shipped deck; for `free`, without contact."""
    def edit(text):
        if scene == "free":
            lines = text.splitlines(True)
            return "".join(line for line in lines if not line.startswith("contact:"))
        return text
    return shipped_deck("pneunet_self_contact", folder, scene, edit)


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeats", type=int, default=3)
    parser.add_argument("--ranks", type=int, default=1)
    parser.add_argument("--set", action="append", default=[], dest="overrides")
    args = parser.parse_args()
    print("| scene | nodes | Newton iterations | run (s) | per iteration (ms) | assembly (s) "
          "| solve (s) | tip rotation (deg) |")
    print("|---|---|---|---|---|---|---|---|")
    with tempfile.TemporaryDirectory() as tmp:
        for scene in ("self_contact", "free"):
            deck = scene_deck(scene, tmp)
            runs = [run(deck, args.overrides, os.path.join(tmp, f"{scene}_{k}"), args.ranks)
                    for k in range(args.repeats)]
            med = lambda f: statistics.median(f(s) for s in runs)
            total = med(lambda s: s["time_s"]["total"])
            its = med(lambda s: s["newton_iterations"])
            print(f"| {scene} | {runs[0]['nodes']:,} | {its:.0f} | {total:.2f} "
                  f"| {1000 * total / its:.1f} | {med(lambda s: s['time_s']['assembly']):.2f} "
                  f"| {med(lambda s: s['time_s']['solve']):.2f} "
                  f"| {med(lambda s: s['states'][-1]['tip']['rotation_deg']):.1f} |")


if __name__ == "__main__":
    main()
