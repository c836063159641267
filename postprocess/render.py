#!/usr/bin/python3
"""Pictures of a run from one command: the deformed robot of every output step as a PNG, and
the run as an animated GIF, drawn headless by ParaView.

    /usr/bin/python3 postprocess/render.py OUT_FOLDER [--field displacement|von_mises]
        [--out DIR] [--steps last|all] [--gif] [--size 900x520]

OUT_FOLDER is a run's output folder (summary.json and <deck>.xmf; docs/output.md). The body
is cut in half through its centre by the plane that faces the camera, so that the cavities
show as holes in the cut; the camera looks along the axis in which the run moved least (a
finger bending in x-z is seen along y). Colours: the displacement's magnitude in mm or the
von Mises stress in kPa, one scale for every step, with its bar; the outline of the cut face
(its contour and the cavities' rims) deformed in black and undeformed in grey, the grey one
hidden where the body still covers it. Each picture is
titled "<deck>: output k+1 of N (step k)" and named <deck>_<field>_step<k>.png (the last: <deck>_<field>.png) under
--out (default OUT_FOLDER/pictures), written to a temporary name and renamed. --gif also
writes <deck>_<field>.gif of every step (Pillow). docs/gallery.md shows every deck so.

Without a display (a server, CI) it runs itself again under xvfb-run, with -noreset: a virtual
X server that resets when its last client leaves drops ParaView's second connection (about
half the runs aborted with "bad X server connection").
"""
import argparse
import glob
import json
import os
import sys

import h5py
import numpy as np

FIELDS = {  # name in the .xmf, how it is shown, factor to the unit shown
    "displacement": ("displacement", "POINTS", "displacement (mm)", 1e3),
    "von_mises": ("von_mises", "CELLS", "von Mises stress (kPa)", 1e-3),
}


def step_title(deck, k, count):
    """The title of output step k (0-based, as in the picture's name, the .h5's step_<k> and
    history.csv) of `count`: "output 14 of 14 (step 13)" for the last of 14."""
    return f"{deck}: output {k + 1} of {count} (step {k})"


def fail(message):
    sys.exit(f"render.py: {message}")


def run_files(folder):
    path = os.path.join(folder, "summary.json")
    if not os.path.isfile(path):
        fail(f"{folder}: no summary.json (not a hydrosoft output folder)")
    with open(path) as f:
        summary = json.load(f)
    xmfs = glob.glob(os.path.join(folder, "*.xmf"))
    if len(xmfs) != 1:
        fail(f"{folder}: expected one .xmf, found {len(xmfs)}")
    return summary, xmfs[0], os.path.splitext(xmfs[0])[0] + ".h5"


def view_axis(h5):
    """The axis the camera looks along: the one in which the last step moved least."""
    with h5py.File(h5, "r") as f:
        steps = sorted((k for k in f if k.startswith("step_")), key=lambda k: int(k[5:]))
        if not steps:
            fail(f"{h5}: no output step")
        u = f[steps[-1]]["displacement"][()]
        X = f["mesh/coordinates"][()]
    moved = np.abs(u).max(axis=0)
    if moved.max() == 0:  # nothing moved: look along the body's thinnest side
        moved = X.max(axis=0) - X.min(axis=0)
    return int(np.argmin(moved)), X.min(axis=0), X.max(axis=0), len(steps)


def field_range(h5, name, scale):
    with h5py.File(h5, "r") as f:
        values = []
        for k in f:
            if k.startswith("step_") and name in f[k]:
                v = f[k][name][()]
                values.append(np.linalg.norm(v, axis=1) if v.ndim == 2 else v)
    hi = max(float(np.max(v)) for v in values) * scale if values else 1.0
    return 0.0, hi if hi > 0 else 1.0


def plane_slice(source, centre, normal):
    section = simple.Slice(Input=source)
    section.SliceType = "Plane"
    section.SliceType.Origin = list(centre)
    section.SliceType.Normal = list(normal)
    return section


def boundary_edges(source, normal, shift):
    """The boundary edges of the surface `source`, moved by `shift` along `normal`."""
    edges = simple.FeatureEdges(Input=source, BoundaryEdges=1, FeatureEdges=0,
                                NonManifoldEdges=0, ManifoldEdges=0)
    moved = simple.Transform(Input=edges)
    moved.Transform.Translate = [shift * n for n in normal]
    return moved


def main():
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("folder")
    p.add_argument("--field", choices=sorted(FIELDS), default="displacement")
    p.add_argument("--out")
    p.add_argument("--steps", choices=["last", "all"], default="last")
    p.add_argument("--gif", action="store_true")
    p.add_argument("--size", default="900x520")
    a = p.parse_args()
    summary, xmf, h5 = run_files(a.folder)
    deck = os.path.splitext(os.path.basename(xmf))[0]
    out = a.out or os.path.join(a.folder, "pictures")
    os.makedirs(out, exist_ok=True)
    width, height = (int(v) for v in a.size.split("x"))
    array, association, title, scale = FIELDS[a.field]
    axis, lo, hi, nsteps = view_axis(h5)
    centre = 0.5 * (lo + hi)

    reader = simple.Xdmf3ReaderS(FileName=[xmf])
    steps = reader.TimestepValues  # a number when the run has one output step
    times = [float(steps)] if isinstance(steps, (int, float)) else list(steps) or [0.0]
    normal = [0.0, 0.0, 0.0]
    normal[axis] = 1.0
    # Cut before warping, in the reference configuration: the same material half at every step.
    cut = simple.Clip(Input=reader, ClipType="Plane", Crinkleclip=0, Invert=0)
    cut.ClipType.Origin = list(centre)
    cut.ClipType.Normal = normal
    warped = simple.WarpByVector(Input=cut, Vectors=["POINTS", "displacement"], ScaleFactor=1.0)
    shown = simple.Calculator(Input=warped, AttributeType="Point Data" if association == "POINTS"
                              else "Cell Data", ResultArrayName="shown",
                              Function=f"mag({array})*{scale}")
    # The outlines are the edges of the cut face (its outer contour and the cavities' rims), in
    # the reference configuration (grey) and warped (black). Feature edges of the whole surface,
    # drawn before, left stray bits: the facets of a curved wall meet at more than their 30
    # degrees (wavy lines inside the cylinders), and the grey outline, in the plane of the cut
    # face, fought it for depth where the body had not moved (dashed lines on the finger). So
    # the grey one is moved a hair away from the camera (the body hides it where it still is)
    # and the black one a hair towards it (always on the cut face).
    hair = 1e-3 * float(np.max(hi - lo))  # the camera is on the normal's negative side
    section = plane_slice(reader, centre, normal)
    outline = boundary_edges(section, normal, hair)
    rims = boundary_edges(simple.WarpByVector(Input=section, Vectors=["POINTS", "displacement"],
                                              ScaleFactor=1.0), normal, -hair)

    view = simple.CreateView("RenderView")
    view.ViewSize = [width, height]
    view.OrientationAxesVisibility = 1
    view.Background = [1, 1, 1]
    try:
        view.UseColorPaletteForBackground = 0
    except AttributeError:
        pass
    body = simple.Show(shown, view)
    simple.ColorBy(body, (association, "shown"))
    lut = simple.GetColorTransferFunction("shown")
    lut.ApplyPreset("Viridis (matplotlib)", True)
    lut.RescaleTransferFunction(*field_range(h5, array, scale))
    lut.AutomaticRescaleRangeMode = "Never"
    bar = simple.GetScalarBar(lut, view)
    bar.Title, bar.ComponentTitle = title, ""
    bar.TitleColor = bar.LabelColor = [0, 0, 0]
    bar.Visibility = 1
    edges = simple.Show(outline, view)
    simple.ColorBy(edges, None)
    edges.DiffuseColor = edges.AmbientColor = [0.55, 0.55, 0.55]
    edges.LineWidth = 1.5
    rim = simple.Show(rims, view)
    simple.ColorBy(rim, None)
    rim.DiffuseColor = rim.AmbientColor = [0.1, 0.1, 0.1]
    rim.LineWidth = 1.0
    label = simple.Text(Text="")
    text = simple.Show(label, view)
    text.Color = [0, 0, 0]
    text.FontSize = 14
    text.WindowLocation = "Upper Left Corner"

    # The camera looks along the chosen axis; fitted to the last step and the reference body.
    up = [0.0, 0.0, 0.0]
    up[2 if axis != 2 else 1] = 1.0
    view.CameraFocalPoint = list(centre)
    position = list(centre)
    position[axis] -= 10 * float(np.max(hi - lo))  # the kept half shows its cut face
    view.CameraPosition = position
    view.CameraViewUp = up
    view.ViewTime = times[-1]
    simple.ResetCamera(view)
    view.CameraParallelProjection = 1

    chosen = range(len(times)) if (a.steps == "all" or a.gif) else [len(times) - 1]
    frames = []
    for k in chosen:
        view.ViewTime = times[k]
        label.Text = step_title(deck, k, len(times))
        last = k == len(times) - 1
        name = f"{deck}_{a.field}.png" if last else f"{deck}_{a.field}_step{k}.png"
        path = os.path.join(out, name)
        simple.SaveScreenshot(path + ".tmp.png", view, ImageResolution=[width, height])
        os.replace(path + ".tmp.png", path)
        frames.append(path)
        print(path)
    if a.gif:
        from PIL import Image
        images = [Image.open(f).convert("P", palette=Image.ADAPTIVE) for f in frames]
        gif = os.path.join(out, f"{deck}_{a.field}.gif")
        images[0].save(gif + ".tmp.gif", save_all=True, append_images=images[1:], duration=250,
                       loop=0)
        os.replace(gif + ".tmp.gif", gif)
        if a.steps == "last":
            for f in frames[:-1]:
                os.remove(f)
        print(gif)


if __name__ == "__main__":
    # Here, not on import: a test imports step_title without ParaView or a display.
    if not os.environ.get("DISPLAY"):
        os.execvp("xvfb-run", ["xvfb-run", "-a", "-s", "-screen 0 1600x1200x24 -noreset",
                               sys.executable, os.path.abspath(__file__)] + sys.argv[1:])
    from paraview import simple
    main()
