#!/usr/bin/python3
"""A run's wall time by the BLAS threads it is given: OPENBLAS_NUM_THREADS set to each count
asked for, and unset (hydrosoft then sets OpenBLAS to one thread itself), the median over
--repeats runs of each, one rank; with --load N, beside N busy processes (other work on the
machine: another run, a build).

    /usr/bin/python3 bench/fem/blas_threads.py input/pneunet_water.yaml --threads 1 2 --load 2 \\
        --set mesh.order=1 --set mesh.parameters.h=0.008 --set 'states[1].steps=4'
"""
import argparse
import os
import statistics
import subprocess
import tempfile
import time


def main():
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("deck")
    p.add_argument("--threads", type=int, nargs="+", default=[1, 2])
    p.add_argument("--repeats", type=int, default=3)
    p.add_argument("--set", action="append", default=[], help="a deck override, key=value")
    p.add_argument("--binary", default="build/bin/hydrosoft")
    p.add_argument("--load", type=int, default=0, help="busy processes beside the runs")
    a = p.parse_args()
    overrides = [x for kv in a.set for x in ("--set", kv)]
    busy = [subprocess.Popen(["/usr/bin/python3", "-c", "while True: pass"])
            for _ in range(a.load)]
    try:
        table(a, overrides)
    finally:
        for b in busy:
            b.kill()


def table(a, overrides):
    print("| OPENBLAS_NUM_THREADS | median wall time (s) | runs (s) |")
    print("|---|---|---|")
    for threads in [None] + a.threads:
        env = {k: v for k, v in os.environ.items()
               if k not in ("OPENBLAS_NUM_THREADS", "GOTO_NUM_THREADS", "OMP_NUM_THREADS")}
        if threads is not None:
            env["OPENBLAS_NUM_THREADS"] = str(threads)
        times = []
        for _ in range(a.repeats):
            with tempfile.TemporaryDirectory(prefix="hydrosoft_blas_") as out:
                start = time.perf_counter()
                subprocess.run([a.binary, a.deck, "-q", "--set", "output.folder=" + out + "/run"]
                               + overrides, env=env, check=True, stdout=subprocess.DEVNULL)
                times.append(time.perf_counter() - start)
        label = "unset" if threads is None else str(threads)
        print("| %s | %.2f | %s |" % (label, statistics.median(times),
                                      ", ".join("%.2f" % t for t in times)))


if __name__ == "__main__":
    main()
