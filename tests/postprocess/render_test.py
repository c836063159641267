#!/usr/bin/python3
"""postprocess/render.py on a real run: the air-filled cylinder run into a temporary folder,
then drawn. The last step's PNG has the size asked and shows the body (a tenth of it or more
coloured, neither white nor grey); the GIF has one frame per output step of summary.json,
and the titles count those steps from 1 to their number (before, "step 13 of 13" for 14).

    /usr/bin/python3 tests/postprocess/render_test.py BUILD/bin/hydrosoft
"""
import json
import os
import subprocess
import sys
import tempfile

import numpy as np
from PIL import Image

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
sys.path.insert(0, os.path.join(ROOT, "postprocess"))
from render import step_title  # noqa: E402


def main():
    hydrosoft = sys.argv[1]
    with tempfile.TemporaryDirectory(prefix="hydrosoft_render_test_") as tmp:
        run = os.path.join(tmp, "run")
        subprocess.run([hydrosoft, os.path.join(ROOT, "input", "cylinder_air.yaml"), "-q",
                        # the coarse compressible cylinder of tests/pinned_decks.hpp
                        "--set", "mesh.order=1", "--set", "materials[0].E=2.0e5",
                        "--set", "materials[0].nu=0.45",
                        "--set", f"output.folder={run}"], check=True, stdout=subprocess.DEVNULL)
        pictures = os.path.join(tmp, "pictures")
        subprocess.run(["/usr/bin/python3", os.path.join(ROOT, "postprocess", "render.py"), run,
                        "--out", pictures, "--size", "320x200", "--gif"], check=True)
        png = Image.open(os.path.join(pictures, "cylinder_air_displacement.png")).convert("RGB")
        assert png.size == (320, 200), png.size
        rgb = np.asarray(png).astype(int)
        grey = (np.abs(rgb[..., 0] - rgb[..., 1]) < 8) & (np.abs(rgb[..., 1] - rgb[..., 2]) < 8)
        coloured = float(np.mean(~grey))
        assert coloured > 0.1, f"only {coloured:.3f} of the picture is coloured"
        with open(os.path.join(run, "summary.json")) as f:
            outputs = json.load(f)["outputs"]
        gif = Image.open(os.path.join(pictures, "cylinder_air_displacement.gif"))
        assert gif.n_frames == outputs, (gif.n_frames, outputs)
        titles = [step_title("cylinder_air", k, outputs) for k in range(outputs)]
        assert titles[0] == f"cylinder_air: output 1 of {outputs} (step 0)", titles[0]
        assert titles[-1] == f"cylinder_air: output {outputs} of {outputs} (step {outputs - 1})", \
            titles[-1]
        assert len(set(titles)) == outputs, titles
        print(f"render: {coloured:.2f} of the picture coloured, {gif.n_frames} frames")


if __name__ == "__main__":
    main()
