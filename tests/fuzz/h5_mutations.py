"""Mutations of a hydrosoft .h5 mesh (`hydrosoft mesh DECK OUT.h5`): bytes flipped, cut or
spliced anywhere, and edits of the datasets found by h5_layout.py: a tetrahedron's node
changed, made out of range or repeated, a tetrahedron row copied over another, two of its
vertices swapped, a node's coordinates NaN, moved onto another node or scaled, a boundary
face flipped, given random nodes or another tetrahedron, a volume index out of range, a
dataset claiming more rows than the file holds, the order attribute changed.

Each mutation says what the run must do: 'reject' (a mesh that is not a mesh: refused),
'same' (the same mesh written otherwise: a real run that accepts it must give the base run's
displacements), or 'any' (accepted or refused, cleanly).
"""
import struct

from h5_layout import H5Layout, read_rows

ODD_NODE_NUMBERS = [-1, -2**31, 2**31, 2**40, 2**63 - 1]
ODD_ROW_COUNTS = [0, 2**31, 2**40, 2**62, 2**64 - 1]


def _put(out, dataset, index, fmt, value):
    struct.pack_into("<" + fmt, out, dataset.address + index * struct.calcsize(fmt), value)


def mutate_h5_mesh(rng, data):
    """One mutation of the bytes of an .h5 mesh: (kind, detail, new bytes, expect)."""
    layout = H5Layout(data)
    sets = layout.datasets
    tets, nodes = sets["/tets"], sets["/nodes"]
    width = tets.shape[1]
    num_nodes, num_tets = nodes.shape[0], tets.shape[0]
    tet_rows = read_rows(data, tets)
    xyz = read_rows(data, nodes)
    surfaces = sorted(p[: -len("/faces")] for p in sets if p.startswith("/surfaces/") and p.endswith("/faces"))
    out = bytearray(data)
    kind = rng.choice(["flip", "flip", "truncate", "splice", "tet_node", "tet_node_out", "tet_copy",
                       "tet_swap", "tet_flat", "node_nan", "node_onto", "node_scale", "face_flip",
                       "face_random", "face_tet", "volume_index", "rows_claimed", "order"])
    if kind == "flip":
        spots = []
        for _ in range(rng.randint(1, 8)):
            at = rng.randrange(len(out))
            out[at] ^= 1 << rng.randrange(8)
            spots.append(str(at))
        return kind, "bytes " + ", ".join(spots), bytes(out), "any"
    if kind == "truncate":
        cut = rng.randrange(len(data))
        return kind, f"{cut} of {len(data)} bytes", data[:cut], "any"
    if kind == "splice":  # a block of the file copied over another place
        size = rng.randint(8, 512)
        src, dst = rng.randrange(len(data) - size), rng.randrange(len(data) - size)
        out[dst : dst + size] = data[src : src + size]
        return kind, f"{size} bytes from {src} over {dst}", bytes(out), "any"
    if kind.startswith("tet_"):
        row = rng.randrange(num_tets)
        corners = tet_rows[row * width : row * width + 4]
        col = rng.randrange(4)
        if kind == "tet_node":  # another node of the mesh: a hole and an overlap, or folded
            value = rng.randrange(num_nodes)
            _put(out, tets, row * width + col, "q", value)
            return kind, f"/tets[{row}][{col}]: {corners[col]} -> {value}", bytes(out), "any"
        if kind == "tet_node_out":
            value = rng.choice(ODD_NODE_NUMBERS + [num_nodes, num_nodes + 7])
            _put(out, tets, row * width + col, "q", value)
            return kind, f"/tets[{row}][{col}]: {value}", bytes(out), "reject"
        if kind == "tet_copy":  # a tetrahedron twice, another gone
            other = rng.choice([r for r in range(num_tets) if r != row])
            for c in range(width):
                _put(out, tets, other * width + c, "q", tet_rows[row * width + c])
            return kind, f"/tets[{other}] made a copy of row {row}", bytes(out), "reject"
        if kind == "tet_swap":  # the opposite orientation: the same mesh
            a, b = rng.sample(range(4), 2)
            _put(out, tets, row * width + a, "q", corners[b])
            _put(out, tets, row * width + b, "q", corners[a])
            expect = "same" if width == 4 else "any"  # P2: the edge nodes would have to follow
            return kind, f"/tets[{row}]: vertices {a} and {b} swapped", bytes(out), expect
        other = (col + rng.randint(1, 3)) % 4  # tet_flat: a vertex repeated
        _put(out, tets, row * width + col, "q", corners[other])
        return kind, f"/tets[{row}]: vertex {col} made vertex {other}", bytes(out), "reject"
    if kind.startswith("node_"):
        node = rng.randrange(num_nodes)
        if kind == "node_nan":
            value = rng.choice([float("nan"), float("inf"), float("-inf")])
            _put(out, nodes, 3 * node + rng.randrange(3), "d", value)
            return kind, f"/nodes[{node}]: {value}", bytes(out), "reject"
        if kind == "node_onto":  # two nodes at one place, used by different tetrahedra
            other = rng.choice([n for n in range(num_nodes) if n != node])
            for c in range(3):
                _put(out, nodes, 3 * node + c, "d", xyz[3 * other + c])
            return kind, f"/nodes[{node}] moved onto node {other}", bytes(out), "reject"
        scale = rng.choice([-1.0, 0.0, 2.0, 1e3, 1e300])
        for c in range(3):
            _put(out, nodes, 3 * node + c, "d", xyz[3 * node + c] * scale)
        return kind, f"/nodes[{node}] times {scale}", bytes(out), "any"
    if kind.startswith("face_"):
        name = rng.choice(surfaces)
        faces, owners = sets[name + "/faces"], sets[name + "/tets"]
        npf = faces.shape[1]
        row = rng.randrange(faces.shape[0])
        face = read_rows(data, faces)[row * npf : row * npf + npf]
        if kind == "face_flip":  # the normal is the tetrahedron's business: the same mesh
            _put(out, faces, row * npf + 1, "q", face[2])
            _put(out, faces, row * npf + 2, "q", face[1])
            if npf == 6:  # the edge nodes follow their corners: (0 1 2 | 01 12 20) -> (0 2 1 | 02 21 10)
                _put(out, faces, row * npf + 3, "q", face[5])
                _put(out, faces, row * npf + 5, "q", face[3])
            return kind, f"{name}/faces[{row}]: {face} flipped", bytes(out), "same"
        if kind == "face_random":
            value = [rng.randrange(num_nodes) for _ in range(3)]
            for c in range(3):
                _put(out, faces, row * npf + c, "q", value[c])
            return kind, f"{name}/faces[{row}]: {face[:3]} -> {value}", bytes(out), "reject"
        # face_tet: a face said to belong to another tetrahedron: refused, or the same result
        owner = read_rows(data, owners)[row]
        value = rng.choice([t for t in range(num_tets) if t != owner])
        _put(out, owners, row, "q", value)
        return kind, f"{name}/tets[{row}]: {owner} -> {value}", bytes(out), "same"
    if kind == "volume_index":
        volumes = sets["/tet_volume"]
        row = rng.randrange(volumes.shape[0])
        value = rng.choice([-1, 1, 7, 2**31 - 1])
        _put(out, volumes, row, "i", value)
        return kind, f"/tet_volume[{row}]: {value}", bytes(out), "reject"
    if kind == "rows_claimed":  # the dataspace claims more (or fewer) rows than are stored
        dataset = sets[rng.choice(sorted(sets))]
        value = rng.choice(ODD_ROW_COUNTS + [dataset.shape[0] + 1, dataset.shape[0] * 1000])
        out[dataset.shape_at : dataset.shape_at + layout.L] = (value % 2**64).to_bytes(layout.L, "little")
        return kind, f"{dataset.path}: {dataset.shape[0]} rows -> {value}", bytes(out), "any"
    order = next(a for a in layout.attributes if a.owner == "/" and a.name == "order")
    value = rng.choice([0, 3, -1, 2 if width == 4 else 1])
    struct.pack_into("<i", out, order.address, value)
    return kind, f"order attribute {value}", bytes(out), "reject"
