"""Line mutations of the fuzz harness's base meshes, run through `hydrosoft --check`.

Every line of $MeshFormat and $PhysicalNames, every section line, count line and entity
block header, the first and last lines of $Entities, $Nodes and $Elements and of their first
entity blocks, and a few drawn lines of each are mutated one at a time: the line deleted or doubled, its first or last field
dropped, a field added, a field (first, middle, last) replaced by a non-number. Each case is
classified as tests/fuzz/classify.py does; the defects (a crash, a dump, a message that does
not name the file) and the cases accepted are listed. Usage:

  python3 tests/mesh/msh_line_sweep.py BUILD/bin/hydrosoft OUT [--jobs 2]
"""
import argparse
import collections
import concurrent.futures
import os
import random
import shutil
import sys

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.join(HERE, "..", "fuzz"))
from classify import run_case  # noqa: E402
from fuzz import BASE_MESHES, MESH_DECK  # noqa: E402

# The fuzz harness's mesh cases: the same deck and base meshes (name: the deck's order).
BASES = {name: order for name, _, order in BASE_MESHES}
DECK = MESH_DECK
DATA_LINES_DRAWN = 5


def chosen_lines(lines, v4, rng):
    """Indices of the lines to mutate: all structure lines, some data lines per block."""
    chosen, section, first = set(), None, 0
    for n, line in enumerate(lines):
        if line.startswith("$"):
            chosen.add(n)
            section = None if line.startswith("$End") else line[1:]
            first = n + 1
            continue
        if section in ("MeshFormat", "PhysicalNames") or n == first:
            chosen.add(n)  # and the count line of every section
    for name in ("Entities", "Nodes", "Elements"):
        if "$" + name not in lines:
            continue
        start = lines.index("$" + name) + 2
        end = lines.index("$End" + name)
        chosen.update({start, end - 1})
        if name == "Entities":
            chosen.update(rng.sample(range(start, end), min(DATA_LINES_DRAWN, end - start)))
            continue
        if v4:  # every block header; the first and last lines of the first blocks
            n = start
            while n < end:
                count = int(lines[n].split()[3])
                per_item = 2 if name == "Nodes" else 1
                chosen.add(n)
                if count and n < start + 3:
                    chosen.update({n + 1, n + count, n + per_item * count})
                    if per_item == 2:
                        chosen.add(n + count + 1)
                n += 1 + per_item * count
        chosen.update(rng.sample(range(start, end), min(DATA_LINES_DRAWN, end - start)))
    return sorted(chosen)


def mutations(lines, n):
    """(kind, new lines) of line n."""
    words = lines[n].split()
    yield "delete", lines[:n] + lines[n + 1 :]
    yield "double", lines[:n] + [lines[n]] + lines[n:]
    variants = {}
    if words:
        variants["drop_last"] = words[:-1]
        variants["drop_first"] = words[1:]
        variants["extra"] = words + ["7"]
        for where, i in (("first", 0), ("middle", len(words) // 2), ("last", len(words) - 1)):
            variants["nan_" + where] = words[:i] + ["x"] + words[i + 1 :]
    for kind, new in variants.items():
        yield kind, lines[:n] + [" ".join(new)] + lines[n + 1 :]


def make_cases(base_folder, seed):
    cases = []
    for name, order in sorted(BASES.items()):
        with open(os.path.join(base_folder, name + ".msh")) as f:
            text = f.read()
        lines = text.split("\n")
        rng = random.Random(f"{seed}-{name}")
        seen = {text}
        for n in chosen_lines(lines, lines[1].startswith("4"), rng):
            for kind, new in mutations(lines, n):
                mesh = "\n".join(new)
                if mesh in seen:
                    continue
                seen.add(mesh)
                cases.append({"id": len(cases), "base": name, "line": n + 1, "kind": kind,
                              "mesh": mesh, "deck": DECK.format(order=order)})
    return cases


def run_one(case, hydrosoft, out):
    work = os.path.join(out, "work", str(case["id"]))
    os.makedirs(work, exist_ok=True)
    for file, text in (("deck.yaml", case["deck"]), ("mesh.msh", case["mesh"])):
        with open(os.path.join(work, file), "w") as f:
            f.write(text)
    cls, reason, code, stderr, _ = run_case(hydrosoft, "deck.yaml", [], ["deck.yaml", "mesh.msh"],
                                            False, work, 60, 4096)
    if cls == "defect":
        kept = os.path.join(out, "defects", str(case["id"]))
        shutil.rmtree(kept, ignore_errors=True)
        shutil.move(work, kept)
        with open(os.path.join(kept, "stderr.txt"), "w") as f:
            f.write(stderr)
    else:
        shutil.rmtree(work, ignore_errors=True)
    return case, cls, reason, stderr


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("hydrosoft")
    parser.add_argument("out")
    parser.add_argument("--jobs", type=int, default=2)
    parser.add_argument("--seed", type=int, default=1)
    parser.add_argument("--base-meshes", default=os.path.join(HERE, "..", "fuzz", "base_meshes"))
    args = parser.parse_args()
    cases = make_cases(args.base_meshes, args.seed)
    counts = collections.Counter()
    defects, accepted = [], []
    with concurrent.futures.ThreadPoolExecutor(args.jobs) as pool:
        for case, cls, reason, stderr in pool.map(lambda c: run_one(c, os.path.abspath(args.hydrosoft),
                                                                    os.path.abspath(args.out)), cases):
            counts[cls] += 1
            where = f"{case['id']} {case['base']} line {case['line']} {case['kind']}"
            if cls == "defect":
                defects.append(f"{where}: {reason}")
            elif cls == "accepted":
                accepted.append(where)
    print(f"{len(cases)} cases: " + ", ".join(f"{k} {v}" for k, v in sorted(counts.items())))
    for a in accepted:
        print("accepted", a)
    for d in defects:
        print("defect", d)
    return 1 if defects else 0


if __name__ == "__main__":
    sys.exit(main())
