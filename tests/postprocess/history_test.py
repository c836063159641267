#!/usr/bin/python3
"""postprocess/plot_history.py on a real run: the water cylinder run into a temporary folder,
then plotted. The ranges it prints are the history's, and their ends are summary.json's
cavity at the end of the run; the picture is written and not blank.

    /usr/bin/python3 tests/postprocess/history_test.py BUILD/bin/hydrosoft
"""
import json
import os
import re
import subprocess
import sys
import tempfile

import numpy as np
from PIL import Image

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))


def main():
    hydrosoft = sys.argv[1]
    with tempfile.TemporaryDirectory(prefix="hydrosoft_history_test_") as tmp:
        run = os.path.join(tmp, "run")
        subprocess.run([hydrosoft, os.path.join(ROOT, "input", "cylinder_water.yaml"), "-q",
                        # the coarse compressible cylinder of tests/pinned_decks.hpp
                        "--set", "mesh.order=1", "--set", "materials[0].E=2.0e5",
                        "--set", "materials[0].nu=0.45",
                        "--set", f"output.folder={run}"], check=True, stdout=subprocess.DEVNULL,
                       stderr=subprocess.DEVNULL)
        png = os.path.join(tmp, "history.png")
        out = subprocess.run(["/usr/bin/python3", os.path.join(ROOT, "postprocess", "plot_history.py"),
                              run, "--out", png], check=True, capture_output=True, text=True).stdout
        m = re.search(r"cavity cavity: pressure (\S+) to (\S+) Pa, volume (\S+) to (\S+) ml over (\d+) steps", out)
        assert m, out
        with open(os.path.join(run, "summary.json")) as f:
            summary = json.load(f)
        end = summary["end_of_run"]["cavities"][0]
        # The pressure and volume grow to their end values; printed with 6 digits.
        assert abs(float(m.group(2)) - end["pressure"]) <= 1e-5 * end["pressure"], (m.group(2), end)
        assert abs(float(m.group(4)) - end["volume_ml"]) <= 1e-5 * end["volume_ml"], (m.group(4), end)
        assert float(m.group(1)) == 0.0  # open at gauge 0 in the rest state
        assert int(m.group(5)) == summary["outputs"], (m.group(5), summary["outputs"])
        rgb = np.asarray(Image.open(png).convert("RGB")).astype(int)
        assert (rgb < 250).any(axis=2).mean() > 0.02, "the picture is blank"
        print(f"history: p to {m.group(2)} Pa, V to {m.group(4)} ml, {m.group(5)} steps")


if __name__ == "__main__":
    main()
