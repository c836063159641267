#!/usr/bin/pvpython
"""Opens a hydrosoft .xmf with each of ParaView's three XDMF readers and checks what they see.

    /usr/bin/pvpython postprocess/check_xdmf_paraview.py out/lame_sphere/lame_sphere.xmf \
        [--points N] [--cells E] [--times 0.5,1] [--straight-edges]

For every reader (XDMFReader, Xdmf3ReaderS, Xdmf3ReaderT) and every time step it checks
the number of points and cells, the cell type (VTK tetra or quadratic tetra), the point and
cell arrays (each step's datasets: displacement, nodal_load and, with cavities,
cavity_pressure_load and fluid_weight_load; von_mises, J, rank and the tensors stress,
strain, principal_stress, principal_strain; and the mesh's physical
groups: volume_group per cell, group_<name> per node) and the time values; then it compares
the points, the connectivity and every array with the datasets of the .h5 file (read with
h5py), so that a reader that misreads a field or a step is caught.
Expected counts default to those of the .h5 file. Exit status 0 when every reader agrees.
Runs under /usr/bin/pvpython (Debian's paraview, which also has numpy and h5py).
"""
import argparse
import os
import sys

import h5py
import numpy as np
from paraview import servermanager, simple
from vtkmodules.numpy_interface import dataset_adapter as dsa
from vtkmodules.util.numpy_support import vtk_to_numpy


# A step's per-tetrahedron datasets of several columns (the rest of its 2D ones are nodal).
CELL_TENSORS = {"stress", "strain", "principal_stress", "principal_strain"}


def arrays_of(h5, step):
    """The point and cell arrays a step's grid has: {name: dataset}, from the .h5."""
    mesh = h5["mesh"]
    points = {k: mesh[k] for k in mesh if k.startswith("group_")}
    cells = {k: mesh[k] for k in ("volume_group",) if k in mesh}
    for k, data in step.items():
        (points if data.ndim == 2 and k not in CELL_TENSORS else cells)[k] = data
    return points, cells

VTK_TETRA, VTK_QUADRATIC_TETRA = 10, 24

READERS = {
    "XDMFReader": lambda path: simple.XDMFReader(FileNames=[path]),
    "Xdmf3ReaderS": lambda path: simple.Xdmf3ReaderS(FileName=[path]),
    "Xdmf3ReaderT": lambda path: simple.Xdmf3ReaderT(FileName=[path]),
}


def unstructured_grid(data):
    """The single unstructured grid a reader produced (some wrap it in a multiblock)."""
    while data.IsA("vtkMultiBlockDataSet"):
        if data.GetNumberOfBlocks() != 1:
            raise AssertionError(f"expected one block, got {data.GetNumberOfBlocks()}")
        data = data.GetBlock(0)
    if not data.IsA("vtkUnstructuredGrid"):
        raise AssertionError(f"expected an unstructured grid, got {data.GetClassName()}")
    return data


def edges_are_straight(grid):
    """Every edge's middle node halfway between its ends, by VTK's own edge definitions.

    True for meshes with straight edges only; it shows that ParaView reads the Tet10 edge
    nodes in the order they were meant (a swapped pair lands off its edge)."""
    for c in range(grid.GetNumberOfCells()):
        cell = grid.GetCell(c)
        for e in range(cell.GetNumberOfEdges()):
            edge = cell.GetEdge(e)
            if edge.GetNumberOfPoints() < 3:
                continue
            a, b, mid = (np.array(edge.GetPoints().GetPoint(i)) for i in range(3))
            if not np.allclose((a + b) / 2, mid, rtol=0, atol=1e-12 * (1 + np.abs(mid).max())):
                return False
    return True


def check_reader(name, xmf, h5, expected):
    errors = []

    def expect(condition, message):
        if not condition:
            errors.append(f"{name}: {message}")

    reader = READERS[name](xmf)
    times = reader.TimestepValues
    times = [times] if isinstance(times, float) else list(times)
    expect(np.allclose(times, expected["times"], rtol=0, atol=1e-12),
           f"time steps {times}, expected {expected['times']}")
    coordinates = h5["mesh/coordinates"][:]
    topology = h5["mesh/topology"][:]
    for k, t in enumerate(times[: len(expected["times"])]):
        reader.UpdatePipeline(t)
        grid = dsa.WrapDataObject(unstructured_grid(servermanager.Fetch(reader)))
        where = f"step {k} (time {t})"
        errors_before = len(errors)
        expect(grid.GetNumberOfPoints() == expected["points"],
               f"{where}: {grid.GetNumberOfPoints()} points, expected {expected['points']}")
        expect(grid.GetNumberOfCells() == expected["cells"],
               f"{where}: {grid.GetNumberOfCells()} cells, expected {expected['cells']}")
        cell_type = VTK_TETRA if topology.shape[1] == 4 else VTK_QUADRATIC_TETRA
        expect(set(np.unique(grid.CellTypes)) == {cell_type},
               f"{where}: cell types {set(np.unique(grid.CellTypes))}, expected {cell_type}")
        point_names = sorted(grid.PointData.keys())
        cell_names = sorted(grid.CellData.keys())
        point_arrays, cell_arrays = arrays_of(h5, h5[f"step_{k}"])
        expect(point_names == sorted(point_arrays), f"{where}: point arrays {point_names}")
        expect(cell_names == sorted(cell_arrays), f"{where}: cell arrays {cell_names}")
        if len(errors) > errors_before:
            break  # the values cannot be compared
        # The values, against the .h5 file: points, connectivity (in VTK order) and fields.
        expect(np.array_equal(grid.Points, coordinates), f"{where}: points differ from the .h5")
        vtk_grid = grid.VTKObject
        cells = np.array([[vtk_grid.GetCell(c).GetPointId(i) for i in range(topology.shape[1])]
                          for c in range(vtk_grid.GetNumberOfCells())])
        expect(np.array_equal(cells, topology), f"{where}: connectivity differs from the .h5")
        if expected["straight_edges"]:
            expect(edges_are_straight(vtk_grid), f"{where}: a mid-edge node is off its edge")
        for array, data in point_arrays.items():
            expect(np.array_equal(grid.PointData[array], data[:]),
                   f"{where}: {array} differs from the .h5")
        for array, data in cell_arrays.items():
            # The raw components: the numpy adapter shows a 9-component array as 3 x 3
            # matrices, transposed.
            values = vtk_to_numpy(vtk_grid.GetCellData().GetArray(array))
            expect(np.array_equal(values, data[:]), f"{where}: {array} differs from the .h5")
    simple.Delete(reader)
    return errors


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("xmf")
    parser.add_argument("--points", type=int, help="expected number of points")
    parser.add_argument("--cells", type=int, help="expected number of cells")
    parser.add_argument("--times", help="expected time values, comma-separated")
    parser.add_argument("--straight-edges", action="store_true",
                        help="the mesh has straight edges: check that every mid-edge node "
                             "lies halfway along its edge (Tet10 node order)")
    args = parser.parse_args()

    xmf = os.path.abspath(args.xmf)
    h5 = h5py.File(os.path.splitext(xmf)[0] + ".h5", "r")
    steps = sorted((k for k in h5.keys() if k.startswith("step_")), key=lambda k: int(k[5:]))
    expected = {
        "points": args.points if args.points is not None else h5["mesh/coordinates"].shape[0],
        "cells": args.cells if args.cells is not None else h5["mesh/topology"].shape[0],
        "times": ([float(t) for t in args.times.split(",")] if args.times
                  else [float(h5[s].attrs["time"]) for s in steps]),
        "straight_edges": args.straight_edges,
    }
    errors = []
    for name in READERS:
        found = check_reader(name, xmf, h5, expected)
        print(f"{name}: {'ok' if not found else 'FAILED'} ({expected['points']} points, "
              f"{expected['cells']} cells, {len(expected['times'])} time steps)")
        errors += found
    for e in errors:
        print(e, file=sys.stderr)
    return 1 if errors else 0


if __name__ == "__main__":
    sys.exit(main())
