#!/usr/bin/python3
"""Compares the numbers of two hydrosoft runs: two summary.json files, or two folders of
<deck>/summary.json (as scripts/run_all_decks.sh writes them).

    compare_summaries.py A B [--rtol 1e-9] [--atol 1e-14]

Every value is compared recursively, key by key and list entry by list entry: numbers must
agree to |a - b| <= rtol scale + atol, strings and booleans exactly, and both sides must hold
the same keys and list lengths. The scale of a number is the largest magnitude of the same
quantity anywhere in the two summaries, a quantity being a key name with the indices of the
lists of numbers below it: every `pressure` (of each state's cavities and the final ones) is
one quantity, and `actuation[1]` is actuator 1 of every target. So a pressure that is the
round-off of zero (1e-12 Pa) is judged against the run's pressures, not against itself. A
number with no larger value of its quantity, such as the energy drift of a conservative run
(1e-10 of 0.1 stored, different from one run of the same binary to the next), is judged
against itself: give --atol for it. In the control decks (finger_*, pendulum) the counters
assembly.jacobian_calls and parts.fluid_weight.calls, the round-off pressure of a cavity
at rest, and qp.kkt_residual_max (the pendulum's 4.8e-14 and 1.1e-13), differ between two
runs of one binary too (e.g. 210, 204 and 225 calls): judge those against a second run of
the reference binary.

Each difference is printed with its JSON path, e.g.
    finger_hydraulic: targets[1].reached[2]: 0.091 != 0.092 (rel 1.1e-02, scale 0.092)
Exit status 1 on any difference (or a deck present on one side only), 0 otherwise.

Ignored keys (at any depth), being timings or the environment of the run rather than its
results:
    time_s, step_time_ms, step_ms, answer_ms, memory_mb, elements_per_second  timings and memory
    deck, output                                                    paths of the deck and output
    ranks, host, date, version, seconds, wall                       environment of the run
and any key ending in _seconds or _ms. The key `time` is kept: in summary.json it is the
simulated time of a state, a result.
"""
import argparse
import json
import math
import sys
from pathlib import Path

IGNORED_KEYS = {
    "time_s", "step_time_ms", "step_ms", "answer_ms", "memory_mb", "elements_per_second",
    "deck", "output",
    "ranks", "host", "date", "version", "seconds", "wall",
}
IGNORED_SUFFIXES = ("_seconds", "_ms")


def ignored(key):
    return key in IGNORED_KEYS or key.endswith(IGNORED_SUFFIXES)


def is_number(x):
    return isinstance(x, (int, float)) and not isinstance(x, bool)


def scales(value, path, found):
    """Records in found the largest magnitude of every quantity (see quantity()) of value."""
    if isinstance(value, dict):
        for key, sub in value.items():
            if not ignored(key):
                scales(sub, key, found)
    elif isinstance(value, list):
        objects = any(isinstance(x, (dict, list)) for x in value)
        for i, sub in enumerate(value):
            scales(sub, f"{path}[]" if objects else f"{path}[{i}]", found)
    elif is_number(value) and not math.isnan(value):
        found[path] = max(found.get(path, 0.0), abs(value))


def compare(a, b, path, rtol, atol, out, scale_of=None, quantity_path=""):
    """Appends 'path: reason' for every difference between a and b to out."""
    if isinstance(a, dict) and isinstance(b, dict):
        for key in sorted(set(a) | set(b)):
            if ignored(key):
                continue
            sub = f"{path}.{key}" if path else key
            q = key
            if key not in a or key not in b:
                out.append(f"{sub}: only in {'B' if key not in a else 'A'}")
            else:
                compare(a[key], b[key], sub, rtol, atol, out, scale_of, q)
    elif isinstance(a, list) and isinstance(b, list):
        if len(a) != len(b):
            out.append(f"{path}: {len(a)} entries != {len(b)} entries")
        objects = any(isinstance(x, (dict, list)) for x in a + b)
        for i, (x, y) in enumerate(zip(a, b)):
            q = f"{quantity_path}[]" if objects else f"{quantity_path}[{i}]"
            compare(x, y, f"{path}[{i}]", rtol, atol, out, scale_of, q)
    elif is_number(a) and is_number(b):
        if math.isnan(a) and math.isnan(b):
            return
        scale = max(abs(a), abs(b), (scale_of or {}).get(quantity_path, 0.0))
        if not abs(a - b) <= rtol * scale + atol:
            rel = abs(a - b) / scale if scale > 0 else math.inf
            out.append(f"{path}: {a!r} != {b!r} (rel {rel:.1e}, scale {scale:.3g})")
    elif a != b or type(a) is not type(b):
        out.append(f"{path}: {a!r} != {b!r}")


def summaries(path):
    """{deck name: summary.json path} of a folder of runs, or {'': path} of one file."""
    path = Path(path)
    if path.is_file():
        return {"": path}
    if not path.is_dir():
        sys.exit(f"compare_summaries.py: {path}: no such file or folder")
    return {p.parent.name: p for p in sorted(path.glob("*/summary.json"))}


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("a", help="summary.json or a folder of <deck>/summary.json")
    parser.add_argument("b", help="the same kind as A")
    parser.add_argument("--rtol", type=float, default=1e-9)
    parser.add_argument("--atol", type=float, default=1e-14)
    args = parser.parse_args()

    runs_a, runs_b = summaries(args.a), summaries(args.b)
    if not runs_a and not runs_b:
        sys.exit(f"compare_summaries.py: no summary.json in {args.a} or {args.b}")
    differences = 0
    for deck in sorted(set(runs_a) | set(runs_b)):
        prefix = f"{deck}: " if deck else ""
        if deck not in runs_a or deck not in runs_b:
            print(f"{prefix}only in {'A' if deck in runs_a else 'B'}")
            differences += 1
            continue
        a, b = json.loads(runs_a[deck].read_text()), json.loads(runs_b[deck].read_text())
        scale_of = {}
        scales(a, "", scale_of)
        scales(b, "", scale_of)
        found = []
        compare(a, b, "", args.rtol, args.atol, found, scale_of)
        for line in found:
            print(prefix + line)
        differences += len(found)
        if deck and not found:
            print(f"{prefix}same")
    print(f"{differences} difference(s) beyond rtol {args.rtol:g}, atol {args.atol:g}")
    return 1 if differences else 0


if __name__ == "__main__":
    sys.exit(main())
