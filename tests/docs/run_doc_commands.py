#!/usr/bin/python3
"""Runs every command of a page of docs/ as a reader would, and checks what the page says.

    /usr/bin/python3 tests/docs/run_doc_commands.py docs/tutorial_cad.md --hydrosoft BUILD/bin/hydrosoft

A command is a line of an indented (4-space) code block that starts with one of PROGRAMS;
a line ending in a backslash goes on. The lines under a command in the same block, up to the
next command, are what the page says it prints: each (but "...") must appear in the
command's output. Commands run in order, with bash, in a temporary copy of input/, meshes/,
postprocess/ and python/, with build/bin/hydrosoft the executable given, so that they can
write what they write (out/, a remade STEP file) without touching the source tree. A command
with `--targets -` must answer every line with an answer, not an error. Exit 1 on the first
failure, with the command and its output.
"""
import argparse
import json
import os
import shutil
import subprocess
import sys
import tempfile

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
PROGRAMS = ("build/bin/hydrosoft", "mpirun ", "gmsh ", "/usr/bin/python3 ", "printf ", "echo ")
COPIED = ("input", "meshes", "postprocess", "python")


def commands_of(page):
    """[(command, [expected output lines])] in the page's order."""
    found, block, previous_blank = [], None, True
    with open(page) as f:
        lines = f.read().splitlines()
    k = 0
    while k < len(lines):
        line = lines[k]
        indented = line.startswith("    ") and (block is not None or previous_blank)
        if not indented:
            block = None
            previous_blank = not line.strip()
            k += 1
            continue
        block = True
        text = line[4:]
        if text.startswith(PROGRAMS):
            while text.endswith("\\") and k + 1 < len(lines):
                k += 1
                text = text[:-1] + " " + lines[k].strip()
            found.append((text, []))
        elif found and text.strip() and text.strip() != "..." and block:
            found[-1][1].append(text.strip())
        k += 1
    return found


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("page")
    ap.add_argument("--hydrosoft", required=True)
    a = ap.parse_args()
    commands = commands_of(a.page)
    if not commands:
        sys.exit("%s: no command found" % a.page)
    env = dict(os.environ, OPENBLAS_NUM_THREADS="1", OMPI_MCA_rmaps_base_oversubscribe="1",
               OMPI_ALLOW_RUN_AS_ROOT="1", OMPI_ALLOW_RUN_AS_ROOT_CONFIRM="1")
    with tempfile.TemporaryDirectory(prefix="hydrosoft_doc_") as tmp:
        for name in COPIED:
            shutil.copytree(os.path.join(ROOT, name), os.path.join(tmp, name),
                            ignore=shutil.ignore_patterns("__pycache__"))
        os.makedirs(os.path.join(tmp, "build", "bin"))
        os.symlink(os.path.abspath(a.hydrosoft), os.path.join(tmp, "build", "bin", "hydrosoft"))
        for command, expected in commands:
            print("$ " + command, flush=True)
            run = subprocess.run(["bash", "-o", "pipefail", "-c", command], cwd=tmp, env=env,
                                 stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True,
                                 timeout=600)
            output = run.stdout + run.stderr
            problems = [] if run.returncode == 0 else ["exit %d" % run.returncode]
            problems += ["does not print %r" % e for e in expected if e not in output]
            if "--targets -" in command:
                answers = [json.loads(l) for l in run.stdout.splitlines() if l.strip()]
                problems += ["line %s refused: %s" % (m.get("line"), m["error"])
                             for m in answers if "error" in m]
                if not answers:
                    problems.append("no answer")
            if problems:
                print(output[-4000:])
                sys.exit("%s: %s: %s" % (a.page, command, "; ".join(problems)))
        print("%s: %d commands ran as the page says" % (a.page, len(commands)))


if __name__ == "__main__":
    main()
