"""What the contact benchmarks share: the project's root, a shipped deck copied with its mesh
path made absolute, and one run of hydrosoft (1 BLAS thread a rank) returning its summary."""
import json
import os
import subprocess

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))


def shipped_deck(name, folder, scene, edit=lambda text: text):
    """input/NAME.yaml as folder/SCENE.yaml, its meshes found from anywhere, changed by edit."""
    text = open(os.path.join(ROOT, "input", name + ".yaml")).read()
    text = edit(text.replace("../meshes/", os.path.join(ROOT, "meshes") + "/"))
    deck = os.path.join(folder, scene + ".yaml")
    with open(deck, "w") as f:
        f.write(text)
    return deck


def run(deck, overrides, folder, ranks=1):
    """hydrosoft DECK into folder with the overrides (KEY=VALUE), on `ranks` ranks."""
    exe = os.environ.get("HYDROSOFT", os.path.join(ROOT, "build", "bin", "hydrosoft"))
    cmd = [exe, deck, "--set", f"output.folder={folder}"]
    if ranks > 1:
        cmd = ["mpirun", "--oversubscribe", "-np", str(ranks)] + cmd
        if os.geteuid() == 0:
            cmd.insert(1, "--allow-run-as-root")
    for o in overrides:
        cmd += ["--set", o]
    env = dict(os.environ, OPENBLAS_NUM_THREADS="1")
    subprocess.run(cmd, check=True, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL, env=env)
    with open(os.path.join(folder, "summary.json")) as f:
        return json.load(f)
