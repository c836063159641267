#!/usr/bin/python3
"""postprocess/refinement_study.py on real runs: the air-filled cylinder, P1, at three mesh
sizes with the default quantities. Each level's value in the CSV is its summary.json's; the
Markdown table has every quantity, the tip displacement a finite order, and its (p, q_inf)
reproduces all three levels as q_inf + C h_eff^p; the plot is drawn. A quantity the summary
lacks is refused after one run, naming the key and listing what is there; a missing deck
before any run.

    /usr/bin/python3 tests/postprocess/refinement_study_test.py BUILD/bin/hydrosoft
"""
import csv
import json
import os
import re
import subprocess
import sys
import tempfile

import numpy as np
from PIL import Image

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
SCRIPT = os.path.join(ROOT, "postprocess", "refinement_study.py")
DECK = os.path.join(ROOT, "input", "cylinder_air.yaml")
SIZES = ["0.011", "0.008", "0.0055"]
TIP = "states[-1].tip.displacement_magnitude_m"


# The compressible silicone of the mechanism tests (tests/pinned_decks.hpp): the study's
# fit is what is tested, not the deck's material.
COARSE = ["--set", "materials[0].E=2.0e5", "--set", "materials[0].nu=0.45"]


def study(hydrosoft, out, *extra):
    return subprocess.run(["/usr/bin/python3", SCRIPT, "--binary", hydrosoft, "--order", "1",
                           *COARSE, "--out", out, *extra], capture_output=True, text=True)


def check_bad_input(hydrosoft, tmp):
    out = os.path.join(tmp, "bad")
    r = study(hydrosoft, out, DECK, "--h", *SIZES, "--quantity", "end_of_run.cavities[0].presure")
    assert r.returncode != 0 and "no key 'presure'" in r.stderr and "pressure, volume" in r.stderr, r.stderr
    assert sorted(os.listdir(out)) == ["p1_h0.011"], os.listdir(out)  # stopped after the first run
    missing = os.path.join(tmp, "no_such_deck.yaml")
    r = study(hydrosoft, os.path.join(tmp, "missing"), missing)
    assert r.returncode != 0 and f"deck '{missing}' not found" in r.stderr, r.stderr
    assert not os.path.exists(os.path.join(tmp, "missing"))


def main():
    hydrosoft = sys.argv[1]
    with tempfile.TemporaryDirectory(prefix="hydrosoft_refinement_test_") as tmp:
        out = os.path.join(tmp, "study")
        r = study(hydrosoft, out, DECK, "--h", *SIZES)
        assert r.returncode == 0, r.stderr
        with open(os.path.join(out, "refinement.csv")) as f:
            rows = list(csv.DictReader(f))
        assert [row["h"] for row in rows] == SIZES, rows
        for row, h in zip(rows, SIZES):
            with open(os.path.join(out, f"p1_h{h}", "summary.json")) as f:
                s = json.load(f)
            assert float(row[TIP]) == s["states"][-1]["tip"]["displacement_magnitude_m"], (row, h)
            assert float(row["end_of_run.cavities[cavity].pressure"]) == s["end_of_run"]["cavities"][0]["pressure"]
            assert int(row["elements"]) == s["elements"] and float(row["time_total_s"]) == s["time_s"]["total"]
        with open(os.path.join(out, "refinement.md")) as f:
            md = f.read()
        for q in (TIP, "states[-1].tip.inclination_deg", "end_of_run.cavities[cavity].volume_ml",
                  "end_of_run.cavities[cavity].pressure", "reactions_N.top[1]"):
            assert f"| P1 | `{q}` |" in md, (q, md)
        m = re.search(r"\| P1 \| `" + re.escape(TIP) + r"` \| (\S+) \| (\S+) \| (\S+) \| (\S+) \|", md)
        assert m and m.group(2) != "-", md
        p, q_inf = float(m.group(2)), float(m.group(3))
        assert 0 < p < 20, p
        error = float(m.group(4))
        assert abs(error - abs(float(rows[-1][TIP]) - q_inf)) <= 0.01 * error, (error, rows[-1][TIP], q_inf)
        # The printed p and q_inf (rounded) reproduce the levels: q = q_inf + C h^p.
        h = np.array([int(row["elements"]) for row in rows], float) ** (-1 / 3)
        q = np.array([float(row[TIP]) for row in rows])
        c = (q[2] - q_inf) / h[2] ** p
        assert np.allclose(q_inf + c * h**p, q, rtol=2e-3, atol=0), (q_inf + c * h**p, q)
        rgb = np.asarray(Image.open(os.path.join(out, "refinement.png")).convert("RGB")).astype(int)
        assert (rgb < 250).any(axis=2).mean() > 0.02, "the plot is blank"
        check_bad_input(hydrosoft, tmp)
        print(f"refinement study: tip displacement p = {p:.2f}, q_inf = {q_inf:.6g} m")


if __name__ == "__main__":
    main()
