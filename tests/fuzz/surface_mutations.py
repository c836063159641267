"""Mutations of closed triangle surfaces for the `fluidweight` executable, in its five formats:
.obj, .off, ASCII and binary .stl, and the surface .msh (ASCII 4.1 and 2.2).

The base surfaces are made here, without numpy or gmsh: an icosphere (42 vertices, 80
triangles) and a box of 8 vertices and 6 quadrangles, both oriented outward. A mutation
either changes the surface (a face removed, repeated, flipped; a vertex duplicated; a
coordinate NaN, infinite or huge; an index out of range; the whole surface scaled or flattened)
and then writes it, or changes the written file (truncated, a count inflated, bytes replaced,
a line deleted, the header changed). Every choice is drawn from the `rng` given.

Each case also says what must happen where that is certain: `expect` is "reject" (an open
surface, a NaN coordinate: a weight would be wrong) or "accept" (the surface is still a
valid closed one), else None; `volume` is the enclosed volume an accepted case must report,
where the mutation keeps it known.
"""
import math
import struct

FORMATS = ["obj", "off", "stl", "stl_binary", "msh41", "msh22"]

ODD_COORDINATES = ["nan", "-nan", "NaN", "inf", "-inf", "infinity", "1e308", "-1e308", "1e999",
                   "-1e999", "1e-320", "5e-324", "1e38", "3.5e38", "-0", "x", "0x1p3", "1e", "--1",
                   "1.0.0", "1e+", "9" * 400]
ODD_INDICES = ["0", "-1", "-2", "-99999", "NV", "NV+1", "2147483647", "2147483648", "-2147483649",
               "4294967296", "99999999999999999999", "1.5", "x", "-0", "+1", "1/", "/1", "1//"]
ODD_COUNTS = ["0", "-1", "-2147483648", "2147483648", "4294967297", "9223372036854775807",
              "99999999999999999999", "1e3", "x", ""]
# The bounds of the readers (fluidweight/mesh_io.hpp): a coordinate's magnitude, the surface's
# largest side; beyond them the volume and the weight overflow or underflow a double.
MAX_COORDINATE, MIN_EXTENT = 1e30, 1e-30
SCALES = [1e300, 1e200, 1e150, 1e100, 1e20, 1e-20, 1e-100, 1e-150, 1e-200, 1e-300, 1e-320, 0.0, -1.0]


class Surface:
    """Vertices [x, y, z] and faces [corners]; a coordinate or a corner that is a str is
    written as it is (an odd value), a corner that is an int is a 0-based vertex index."""

    def __init__(self, vertices, faces):
        self.vertices = [list(v) for v in vertices]
        self.faces = [list(f) for f in faces]


def icosphere():
    t = (1 + 5 ** 0.5) / 2
    v = [(-1, t, 0), (1, t, 0), (-1, -t, 0), (1, -t, 0), (0, -1, t), (0, 1, t), (0, -1, -t),
         (0, 1, -t), (t, 0, -1), (t, 0, 1), (-t, 0, -1), (-t, 0, 1)]
    f = [(0, 11, 5), (0, 5, 1), (0, 1, 7), (0, 7, 10), (0, 10, 11), (1, 5, 9), (5, 11, 4),
         (11, 10, 2), (10, 7, 6), (7, 1, 8), (3, 9, 4), (3, 4, 2), (3, 2, 6), (3, 6, 8),
         (3, 8, 9), (4, 9, 5), (2, 4, 11), (6, 2, 10), (8, 6, 7), (9, 8, 1)]
    vertices = [list(p) for p in v]
    middle = {}

    def mid(a, b):
        key = (min(a, b), max(a, b))
        if key not in middle:
            vertices.append([(vertices[a][d] + vertices[b][d]) / 2 for d in range(3)])
            middle[key] = len(vertices) - 1
        return middle[key]

    faces = []
    for a, b, c in f:
        ab, bc, ca = mid(a, b), mid(b, c), mid(c, a)
        faces += [(a, ab, ca), (b, bc, ab), (c, ca, bc), (ab, bc, ca)]
    # On the sphere of radius 1, coordinates rounded so that every format writes them exactly.
    unit = [[round(x / math.sqrt(sum(y * y for y in p)), 6) for x in p] for p in vertices]
    return Surface(unit, faces)


def box():
    v = [(0, 0, 0), (2, 0, 0), (2, 1, 0), (0, 1, 0), (0, 0, 3), (2, 0, 3), (2, 1, 3), (0, 1, 3)]
    f = [(0, 3, 2, 1), (4, 5, 6, 7), (0, 1, 5, 4), (1, 2, 6, 5), (2, 3, 7, 6), (3, 0, 4, 7)]
    return Surface([[float(x) for x in p] for p in v], f)


BASES = {"sphere": icosphere, "box": box}


def enclosed_volume(s):
    """Volume by the divergence theorem over the fan triangles (the surface must be valid)."""
    total = 0.0
    for f in s.faces:
        a = s.vertices[f[0]]
        for k in range(1, len(f) - 1):
            b, c = s.vertices[f[k]], s.vertices[f[k + 1]]
            total += (a[0] * (b[1] * c[2] - b[2] * c[1]) + a[1] * (b[2] * c[0] - b[0] * c[2])
                      + a[2] * (b[0] * c[1] - b[1] * c[0]))
    return total / 6


# ---- writers: each returns (bytes, counts), counts the places of the file's count fields:
# (line, field) of a text file or ("byte", offset) of the binary STL's facet count.

def _not_finite(text):
    try:
        return not math.isfinite(float(text))
    except ValueError:
        return True


def _num(x):
    return x if isinstance(x, str) else repr(float(x))


def _index(c, base, nv):
    if isinstance(c, int):
        return str(c + base)
    return c.replace("NV+1", str(nv + 1)).replace("NV", str(nv))


def write_obj(s):
    lines = ["# fuzz surface", "o surface"]
    lines += ["v " + " ".join(_num(x) for x in v) for v in s.vertices]
    lines += ["f " + " ".join(_index(c, 1, len(s.vertices)) for c in f) for f in s.faces]
    return ("\n".join(lines) + "\n").encode(), []


def write_off(s):
    nv = len(s.vertices)
    lines = ["OFF", f"{nv} {len(s.faces)} 0"]
    lines += [" ".join(_num(x) for x in v) for v in s.vertices]
    lines += [" ".join([str(len(f))] + [_index(c, 0, nv) for c in f]) for f in s.faces]
    return ("\n".join(lines) + "\n").encode(), [(1, 0), (1, 1)]


def _facets(s):
    """Fan triangles of every face, as corner coordinates (indices out of range: skipped)."""
    for f in s.faces:
        for k in range(1, len(f) - 1):
            corners = [f[0], f[k], f[k + 1]]
            if all(isinstance(c, int) and 0 <= c < len(s.vertices) for c in corners):
                yield [s.vertices[c] for c in corners]


def write_stl(s):
    lines = ["solid surface"]
    for tri in _facets(s):
        lines += ["  facet normal 0 0 0", "    outer loop"]
        lines += ["      vertex " + " ".join(_num(x) for x in p) for p in tri]
        lines += ["    endloop", "  endfacet"]
    lines.append("endsolid surface")
    return ("\n".join(lines) + "\n").encode(), []


def _float32(x):
    try:
        v = float(x)
    except ValueError:
        v = 0.0
    try:
        return struct.unpack("<f", struct.pack("<f", v))[0]
    except OverflowError:  # beyond float32: infinite, as a C cast gives
        return math.copysign(math.inf, v)


def write_stl_binary(s):
    facets = list(_facets(s))
    out = bytearray(b"binary surface written by tests/fuzz".ljust(80, b" "))
    out += struct.pack("<I", len(facets))
    for tri in facets:
        out += struct.pack("<3f", 0, 0, 0)
        for p in tri:
            out += struct.pack("<3f", *(_float32(x) for x in p))
        out += b"\0\0"
    return bytes(out), [("byte", 80)]


def write_msh41(s):
    nv = len(s.vertices)
    tris = [f for f in s.faces if len(f) == 3]
    quads = [f for f in s.faces if len(f) == 4]
    others = [f for f in s.faces if len(f) not in (3, 4)]
    blocks = [(2, tris), (3, quads), (2, others)]  # a face of other size: as a (bad) triangle
    blocks = [(t, fs) for t, fs in blocks if fs]
    lines = ["$MeshFormat", "4.1 0 8", "$EndMeshFormat", "$Entities", "0 0 1 0",
             "1 -1 -1 -1 1 1 1 0 0", "$EndEntities", "$Nodes", f"1 {nv} 1 {nv}", f"2 1 0 {nv}"]
    counts = [(8, 0), (8, 1), (9, 3)]
    lines += [str(k + 1) for k in range(nv)]
    lines += [" ".join(_num(x) for x in v) for v in s.vertices]
    lines += ["$EndNodes", "$Elements"]
    ne = sum(len(fs) for _, fs in blocks)
    counts += [(len(lines), 0), (len(lines), 1)]
    lines.append(f"{len(blocks) + 1} {ne + 1} 1 {ne + 1}")
    # A point element first: the reader must skip what is not 2D.
    counts.append((len(lines), 3))
    lines += ["0 1 15 1", "1 1"]
    tag = 2
    for kind, fs in blocks:
        counts.append((len(lines), 3))
        lines.append(f"2 1 {kind} {len(fs)}")
        for f in fs:
            lines.append(" ".join([str(tag)] + [_index(c, 1, nv) for c in f]))
            tag += 1
    lines.append("$EndElements")
    return ("\n".join(lines) + "\n").encode(), counts


def write_msh22(s):
    nv = len(s.vertices)
    lines = ["$MeshFormat", "2.2 0 8", "$EndMeshFormat", "$Nodes", str(nv)]
    counts = [(4, 0)]
    lines += [" ".join([str(k + 1)] + [_num(x) for x in v]) for k, v in enumerate(s.vertices)]
    lines += ["$EndNodes", "$Elements"]
    counts.append((len(lines), 0))
    lines.append(str(len(s.faces) + 1))
    lines.append("1 15 2 1 1 1")
    for k, f in enumerate(s.faces):
        kind = 3 if len(f) == 4 else 2
        lines.append(" ".join([str(k + 2), str(kind), "2", "1", "1"] + [_index(c, 1, nv) for c in f]))
    lines.append("$EndElements")
    return ("\n".join(lines) + "\n").encode(), counts


WRITERS = {"obj": write_obj, "off": write_off, "stl": write_stl, "stl_binary": write_stl_binary,
           "msh41": write_msh41, "msh22": write_msh22}
EXTENSION = {"obj": "obj", "off": "off", "stl": "stl", "stl_binary": "stl", "msh41": "msh", "msh22": "msh"}


# ---- mutations of the surface ----

def _edge_faces(s):
    """Face ids of each undirected edge of the (unmutated) surface."""
    edges = {}
    for i, f in enumerate(s.faces):
        for k in range(len(f)):
            a, b = f[k], f[(k + 1) % len(f)]
            edges.setdefault((min(a, b), max(a, b)), []).append(i)
    return edges


def _mutate_surface(rng, s, fmt):
    """Changes s in place: (kind, detail, expect, volume)."""
    binary = fmt == "stl_binary"
    indexed = not fmt.startswith("stl")
    kinds = ["open", "open", "repeat_face", "fin", "flip_face", "flip_face", "flip_all",
             "duplicate_vertex", "merge_vertices", "degenerate_face", "collinear", "coordinate",
             "coordinate", "coordinate", "scale", "scale", "flatten", "few_corners",
             "many_corners", "no_faces", "shuffle", "jitter_corner"]
    if indexed:
        kinds += ["index", "index", "index", "no_vertices"]
    kind = rng.choice(kinds)
    nv, nf = len(s.vertices), len(s.faces)
    base_volume = enclosed_volume(s)
    if kind == "open":
        i = rng.randrange(nf)
        del s.faces[i]
        return kind, f"face {i} removed", "reject", None
    if kind == "repeat_face":  # an edge of three or four faces: not manifold
        i = rng.randrange(nf)
        f = s.faces[i]
        s.faces.insert(rng.randrange(nf + 1), f[::-1] if rng.random() < 0.5 else list(f))
        return kind, f"face {i}", "reject", None
    if kind == "fin":  # a triangle hanging on an edge, out to a new vertex
        f = s.faces[rng.randrange(nf)]
        a, b = f[0], f[1]
        s.vertices.append([x + 5 for x in s.vertices[a]])
        s.faces.append([b, a, nv])
        return kind, f"edge ({a}, {b})", "reject", None
    if kind == "flip_face":
        i = rng.randrange(nf)
        s.faces[i].reverse()
        return kind, f"face {i}", "reject", None
    if kind == "flip_all":  # inward: a valid orientation, the same volume
        for f in s.faces:
            f.reverse()
        return kind, "", "accept", base_volume
    if kind == "duplicate_vertex":  # the same point twice: the faces of one copy do not meet the other's
        v = rng.randrange(nv)
        users = [f for f in s.faces if v in f]
        s.vertices.append(list(s.vertices[v]))
        f = rng.choice(users)
        f[f.index(v)] = nv
        return kind, f"vertex {v}", "reject" if indexed else "accept", None if indexed else base_volume
    if kind == "merge_vertices":  # one vertex moved onto another: touching, still closed by index
        a, b = rng.sample(range(nv), 2)
        s.vertices[b] = list(s.vertices[a])
        return kind, f"vertex {b} onto {a}", None, None
    if kind == "degenerate_face":  # a face that repeats a vertex
        i = rng.randrange(nf)
        f = s.faces[i]
        f[1] = f[0]
        return kind, f"face {i}", "reject", None
    if kind == "collinear":  # a vertex on the midpoint of two others: zero-area faces may arise
        a, b, c = rng.sample(range(nv), 3)
        s.vertices[c] = [(s.vertices[a][d] + s.vertices[b][d]) / 2 for d in range(3)]
        return kind, f"vertex {c}", None, None
    if kind == "coordinate":
        v, d = rng.randrange(nv), rng.randrange(3)
        value = rng.choice(ODD_COORDINATES)
        if binary:  # a float32 can hold only numbers
            value = rng.choice(["nan", "inf", "-inf", "1e38", "3.5e38", "1e-45", "-0"])
        s.vertices[v][d] = value
        # NaN, inf, numbers beyond a double (or a float32, in binary STL) and words carry no
        # geometry; "0x1p3" is C's hexadecimal 8.0 and may be read.
        refused = value not in ("0x1p3",) and (_not_finite(value) or abs(float(value)) > MAX_COORDINATE)
        return kind, f"vertex {v} axis {d}: {value[:20]}", "reject" if refused else None, None
    if kind == "scale":
        k = rng.choice(SCALES)
        largest = max(abs(x) for v in s.vertices for x in v)
        extent = max(max(v[d] for v in s.vertices) - min(v[d] for v in s.vertices) for d in range(3))
        for v in s.vertices:
            v[:] = [x * k for x in v]
        if largest * abs(k) > MAX_COORDINATE or extent * abs(k) < MIN_EXTENT:
            return kind, f"times {k}", "reject", None
        return kind, f"times {k}", "accept", base_volume * k ** 3
    if kind == "flatten":  # every vertex on one plane: closed, no volume
        d = rng.randrange(3)
        for v in s.vertices:
            v[d] = 0.0
        # STL names vertices by position: there the halves merge, an edge of four facets.
        return kind, f"axis {d}", None if fmt.startswith("stl") else "accept", 0.0
    if kind == "few_corners":
        i = rng.randrange(nf)
        s.faces[i] = s.faces[i][: rng.choice([0, 1, 2])] if indexed else s.faces[i][:2]
        return kind, f"face {i}", "reject", None
    if kind == "many_corners":
        i = rng.randrange(nf)
        s.faces[i] = [rng.randrange(nv) for _ in range(rng.choice([5, 20, 300]))]
        return kind, f"face {i}", None, None
    if kind == "no_faces":
        s.faces = []
        return kind, "", "reject", None
    if kind == "no_vertices":
        s.vertices = []
        return kind, "", "reject", None
    if kind == "shuffle":  # faces in another order, each rotated: the same surface
        rng.shuffle(s.faces)
        for f in s.faces:
            r = rng.randrange(len(f))
            f[:] = f[r:] + f[:r]
        return kind, "", "accept", base_volume
    if kind == "jitter_corner":  # one face's corner moved a little off the vertex it shared
        v = rng.randrange(nv)
        f = rng.choice([f for f in s.faces if v in f])
        s.vertices.append(list(s.vertices[v]))
        s.vertices[nv][rng.randrange(3)] += rng.choice([1e-3, 1e-9, -1e-5])
        f[f.index(v)] = nv
        # Open; but a float32 may round the move away, and then the binary STL is closed.
        return kind, f"vertex {v}", None if binary else "reject", None
    # index
    i = rng.randrange(nf)
    k = rng.randrange(len(s.faces[i]))
    value = rng.choice(ODD_INDICES)
    s.faces[i][k] = value
    return kind, f"face {i} corner {k}: {value}", None, None


# ---- mutations of the written file ----

def _mutate_file(rng, data, counts, fmt):
    """(kind, detail, expect, new bytes)."""
    kinds = ["truncate", "truncate", "empty", "garbage", "splice", "delete_line", "duplicate_line",
             "header", "long_token", "crlf", "nul"]
    if counts:
        kinds += ["count", "count", "count"]
    kind = rng.choice(kinds)
    if kind == "truncate":
        cut = rng.randrange(len(data))
        return kind, f"{cut} of {len(data)} bytes", None, data[:cut]
    if kind == "empty":
        return kind, "", "reject", b""
    if kind == "garbage":
        n = rng.choice([1, 4, 84, 134, 1000, 4096])
        return kind, f"{n} random bytes", None, bytes(rng.randrange(256) for _ in range(n))
    if kind == "splice":
        at = rng.randrange(len(data))
        n = rng.choice([1, 8, 64])
        junk = bytes(rng.randrange(256) for _ in range(n))
        return kind, f"{n} bytes at {at}", None, data[:at] + junk + data[at + n :]
    if kind == "count":
        place = rng.choice(counts)
        value = rng.choice(ODD_COUNTS + ["COUNT*1000+1", "COUNT+1", "COUNT-1"])
        if place[0] == "byte":
            count = struct.unpack_from("<I", data, 80)[0]
            number = {"COUNT*1000+1": count * 1000 + 1, "COUNT+1": count + 1, "COUNT-1": count - 1}.get(
                value, rng.choice([0, 1, 2 ** 31, 2 ** 32 - 1, 85899345]))
            out = bytearray(data)
            struct.pack_into("<I", out, 80, number % 2 ** 32)
            return kind, f"facet count {number % 2 ** 32}", None, bytes(out)
        lines = data.decode().split("\n")
        n, field = place
        words = lines[n].split(" ")
        count = int(words[field])
        words[field] = {"COUNT*1000+1": str(count * 1000 + 1), "COUNT+1": str(count + 1),
                        "COUNT-1": str(count - 1)}.get(value, value)
        lines[n] = " ".join(w for w in words if w)
        return kind, f"line {n + 1} field {field + 1}: {words[field]}", None, "\n".join(lines).encode()
    if kind == "crlf":
        return kind, "", "accept" if fmt != "stl_binary" else None, data.replace(b"\n", b"\r\n")
    if kind == "header":
        if fmt == "stl_binary":  # the header starts like an ASCII STL's; the size still says binary
            return kind, "'solid' header", "accept", b"solid" + data[5:]
        lines = data.split(b"\n")
        n = {"obj": 0, "off": 0, "stl": 0, "msh41": 1, "msh22": 1}[fmt]
        value = rng.choice([b"", b"OFF4", b"COFF", b"off", b"solid", b"solidx", b"4.1 1 8", b"9.9 0 8",
                            b"2.2 0 8", b"4.1 0 8", b"\xef\xbb\xbf" + lines[n], b"x"])
        lines[n] = value
        return kind, value.decode("utf-8", "replace"), None, b"\n".join(lines)
    if kind == "long_token":  # a token of a million characters in a random place
        at = rng.randrange(len(data) + 1)
        token = rng.choice([b"1", b"9", b"x", b" "]) * 1000000
        return kind, f"at {at}: {token[:1]!r} x 10^6", None, data[:at] + token + data[at:]
    if kind == "nul":
        at = rng.randrange(len(data) + 1)
        return kind, f"at {at}", None, data[:at] + b"\0" + data[at:]
    lines = data.split(b"\n")
    n = rng.randrange(len(lines))
    if kind == "delete_line":
        del lines[n]
    else:
        lines.insert(n, lines[n])
    return kind, f"line {n + 1}", None, b"\n".join(lines)


def mutate_surface(rng, formats=FORMATS):
    """One case: (base, format, kind, detail, expect, volume, file extension, bytes); the format
    one of `formats`."""
    base = rng.choice(sorted(BASES))
    fmt = rng.choice(formats)
    s = BASES[base]()
    if rng.random() < 0.55:
        kind, detail, expect, volume = _mutate_surface(rng, s, fmt)
        data, _ = WRITERS[fmt](s)
    else:
        data, counts = WRITERS[fmt](s)
        volume = enclosed_volume(s)
        kind, detail, expect, data = _mutate_file(rng, data, counts, fmt)
        if expect != "accept":
            volume = None
    return base, fmt, kind, detail, expect, volume, EXTENSION[fmt], data
