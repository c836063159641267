"""Mutations of a binary gmsh .msh (formats 4.1 and 2.2, P1 and P2): the counts of the
headers ($Entities, $Nodes, $Elements, each entity block's), the tags and counts inside the
entities and blocks (numPhysicalTags, numBounding..., 2.2's numTags), element types, element
and node tags, the nodes an element names, coordinates, bytes flipped, spliced or cut.

The file is parsed once into its fields (offset, width, what it is); a mutation writes an
odd value into one of them or edits the bytes. Choices come from `rng`.
"""
import struct

# Values written into a count or a tag: as an unsigned field of its width, -1 is all ones.
ODD_COUNTS = [0, -1, 2**31 - 1, 2**31, 2**32 + 1, 2**40, 2**62, 2**63 - 1]
ODD_NODE_TAGS = [0, -1, -5, 2**31, 2**63, 2**64 - 1]
ODD_COORDINATES = [float("nan"), float("inf"), float("-inf"), 1e308, -1e308, 1e-320]
NODES_PER_TYPE = {1: 2, 2: 3, 4: 4, 8: 3, 9: 6, 11: 10, 15: 1}


class Field:
    def __init__(self, offset, width, what, label, value):
        self.offset, self.width, self.what, self.label, self.value = offset, width, what, label, value


class BinaryMsh:
    """The fields of a binary .msh that the mutations edit, by kind:
    count (a header's or a block's count), inner_count (numPhysicalTags, numBounding..., numTags),
    entity (a block's dimension or entity tag), element_type, node_ref (a node an element
    names), node_tag, coordinate, element_tag; `tets` lists the node_ref fields of each
    tetrahedron."""

    def __init__(self, data):
        self.data = data
        self.fields = []
        self.tets = []
        self.max_node = 0
        self.at = 0
        self.version = None
        while self.at < len(data):
            line = self._line()
            if line == "$MeshFormat":
                self.version = self._line().split()[0]
                self.at += 4  # the one in binary
                self._expect("$EndMeshFormat")
            elif line == "$Entities":
                self._entities()
            elif line == "$Nodes":
                self._nodes_v4() if self.version.startswith("4") else self._nodes_v2()
            elif line == "$Elements":
                self._elements_v4() if self.version.startswith("4") else self._elements_v2()
            elif line.startswith("$") and not line.startswith("$End"):
                end = data.index(("\n$End" + line[1:]).encode(), self.at)
                self.at = end + 1
                self._line()

    # ---- reading ----
    def _line(self):
        end = self.data.index(b"\n", self.at)
        text = self.data[self.at : end].decode("latin-1").strip()
        self.at = end + 1
        return text

    def _expect(self, text):
        if self.data[self.at : self.at + 1] == b"\n":
            self.at += 1
        line = self._line()
        if line != text:
            raise ValueError(f"expected {text}, got {line[:40]!r}")

    def _read(self, fmt, what, label):
        width = struct.calcsize(fmt)
        (value,) = struct.unpack_from("<" + fmt, self.data, self.at)
        self.fields.append(Field(self.at, width, what, label, value))
        self.at += width
        return value

    def _entities(self):
        counts = [self._read("Q", "count", f"$Entities count {k}") for k in range(4)]
        for dim, count in enumerate(counts):
            for _ in range(count):
                tag = self._read("i", "entity", f"$Entities dim {dim} tag")
                self.at += 8 * (3 if dim == 0 else 6)
                physicals = self._read("Q", "inner_count", f"$Entities {dim}/{tag} numPhysicalTags")
                self.at += 4 * physicals
                if dim > 0:
                    bounding = self._read("Q", "inner_count", f"$Entities {dim}/{tag} numBounding")
                    self.at += 4 * bounding
        self._expect("$EndEntities")

    def _nodes_v4(self):
        blocks = self._read("Q", "count", "$Nodes numEntityBlocks")
        self._read("Q", "count", "$Nodes numNodes")
        self._read("Q", "count", "$Nodes minNodeTag")
        self._read("Q", "count", "$Nodes maxNodeTag")
        for b in range(blocks):
            dim = self._read("i", "entity", f"$Nodes block {b} entityDim")
            self._read("i", "entity", f"$Nodes block {b} entityTag")
            parametric = self._read("i", "entity", f"$Nodes block {b} parametric")
            count = self._read("Q", "count", f"$Nodes block {b} numNodesInBlock")
            for _ in range(count):
                self.max_node = max(self.max_node, self._read("Q", "node_tag", f"$Nodes block {b} tag"))
            for _ in range(count):
                for c in range(3 + (dim if parametric else 0)):
                    self._read("d", "coordinate", f"$Nodes block {b} coordinate")
        self._expect("$EndNodes")

    def _nodes_v2(self):
        start = self.at
        count = int(self._line())
        self.fields.append(Field(start, self.at - 1 - start, "ascii_count", "$Nodes count", count))
        for _ in range(count):
            self.max_node = max(self.max_node, self._read("i", "node_tag", "$Nodes tag"))
            for _ in range(3):
                self._read("d", "coordinate", "$Nodes coordinate")
        self._expect("$EndNodes")

    def _elements_v4(self):
        blocks = self._read("Q", "count", "$Elements numEntityBlocks")
        for label in ("numElements", "minElementTag", "maxElementTag"):
            self._read("Q", "count", "$Elements " + label)
        for b in range(blocks):
            self._read("i", "entity", f"$Elements block {b} entityDim")
            self._read("i", "entity", f"$Elements block {b} entityTag")
            kind = self._read("i", "element_type", f"$Elements block {b} elementType")
            count = self._read("Q", "count", f"$Elements block {b} numElementsInBlock")
            for _ in range(count):
                self._read("Q", "element_tag", f"$Elements block {b} element tag")
                refs = [self._read("Q", "node_ref", f"$Elements block {b} node") for _ in range(NODES_PER_TYPE[kind])]
                if kind in (4, 11):
                    self.tets.append(self.fields[-len(refs) :])
        self._expect("$EndElements")

    def _elements_v2(self):
        start = self.at
        total = int(self._line())
        self.fields.append(Field(start, self.at - 1 - start, "ascii_count", "$Elements count", total))
        done = 0
        while done < total:
            kind = self._read("i", "element_type", "$Elements block elm-type")
            count = self._read("i", "count", "$Elements block num-elm-follow")
            tags = self._read("i", "inner_count", "$Elements block num-tags")
            for _ in range(count):
                self._read("i", "element_tag", "$Elements element tag")
                for _ in range(tags):
                    self._read("i", "entity", "$Elements element tag (physical, elementary)")
                refs = [self._read("i", "node_ref", "$Elements node") for _ in range(NODES_PER_TYPE[kind])]
                if kind in (4, 11):
                    self.tets.append(self.fields[-len(refs) :])
            done += count
        self._expect("$EndElements")

    def of(self, *whats):
        return [f for f in self.fields if f.what in whats]


def _pack(field, value):
    if field.what == "coordinate":
        return struct.pack("<d", value)
    bits = 8 * field.width
    return (value % (1 << bits)).to_bytes(field.width, "little")


def _write(data, field, value):
    if field.what == "ascii_count":
        return data[: field.offset] + str(value).encode() + data[field.offset + field.width :]
    return data[: field.offset] + _pack(field, value) + data[field.offset + field.width :]


def mutate_binary_msh(rng, data):
    """One mutation of a binary .msh: (kind, detail, new bytes, expect); expect is 'reject'
    where the file must be refused (a NaN coordinate, a node that does not exist, a repeated
    tetrahedron), else 'any'."""
    m = BinaryMsh(data)
    kind = rng.choice(["count", "count", "inner_count", "entity", "element_type", "node_ref", "node_ref",
                       "element_tag", "node_tag", "coordinate", "repeat_tet", "flip", "flip", "truncate", "splice",
                       "header"])
    if kind in ("count", "inner_count"):
        field = rng.choice(m.of(kind, "ascii_count") if kind == "count" else m.of(kind))
        value = rng.choice(ODD_COUNTS + [field.value * 1000 + 1, field.value + 1, field.value - 1])
        return kind, f"{field.label} at {field.offset}: {field.value} -> {value}", _write(data, field, value), "any"
    if kind == "entity":
        field = rng.choice(m.of("entity"))
        value = rng.choice([0, -1, 4, 99, 2**31 - 1, field.value + 1])
        return kind, f"{field.label} at {field.offset}: {field.value} -> {value}", _write(data, field, value), "any"
    if kind == "element_type":
        field = rng.choice(m.of("element_type"))
        value = rng.choice([0, -1, 3, 5, 11 if field.value == 4 else 4, 99, 2**31 - 1])
        return kind, f"{field.label} at {field.offset}: {field.value} -> {value}", _write(data, field, value), "any"
    if kind == "node_ref":
        tet = rng.choice(m.tets)
        field = rng.choice(tet[:4])
        odd = rng.random() < 0.5
        value = rng.choice(ODD_NODE_TAGS + [m.max_node + 7]) if odd else rng.choice([f.value for f in tet[:4] if f is not field])
        detail = f"tetrahedron node at {field.offset}: {field.value} -> {value}"
        return kind, detail, _write(data, field, value), "reject"
    if kind in ("element_tag", "node_tag"):  # a tag odd, or another's (two elements or nodes of one tag)
        fields = m.of(kind)
        field = rng.choice(fields)
        value = rng.choice(ODD_NODE_TAGS + [rng.choice(fields).value])
        return kind, f"{field.label} at {field.offset}: {field.value} -> {value}", _write(data, field, value), "any"
    if kind == "coordinate":
        field = rng.choice(m.of("coordinate"))
        value = rng.choice(ODD_COORDINATES)
        expect = "reject" if value != value or abs(value) == float("inf") else "any"
        return kind, f"{field.label} at {field.offset}: {value}", _write(data, field, value), expect
    if kind == "repeat_tet":
        a, b = rng.sample(range(len(m.tets)), 2)
        out = data
        for fa, fb in zip(m.tets[a], m.tets[b]):
            out = _write(out, fb, fa.value)
        return kind, f"tetrahedron {b} made a copy of {a}", out, "reject"
    if kind == "flip":
        binary = [f for f in m.fields if f.what != "ascii_count"]
        out = bytearray(data)
        spots = []
        for _ in range(rng.randint(1, 4)):
            f = rng.choice(binary)
            at = f.offset + rng.randrange(f.width)
            out[at] ^= 1 << rng.randrange(8)
            spots.append(f"{f.label} byte {at}")
        return kind, "; ".join(spots)[:200], bytes(out), "any"
    if kind == "truncate":
        cut = rng.randrange(len(data))
        return kind, f"{cut} of {len(data)} bytes", data[:cut], "any"
    if kind == "splice":
        at = rng.randrange(len(data))
        junk = bytes(rng.randrange(256) for _ in range(rng.randint(1, 64)))
        replace = rng.random() < 0.5
        out = data[:at] + junk + data[at + (len(junk) if replace else 0) :]
        return kind, f"{len(junk)} random bytes {'over' if replace else 'into'} byte {at}", out, "any"
    # header: the format line or the endianness one
    start = data.index(b"\n") + 1
    end = data.index(b"\n", start)
    line = rng.choice([b"4.1 1 4", b"4.1 1 16", b"2.2 1 8", b"4.1 1 8", b"4.0 1 8", b"4.1 0 8", b"2.2 0 8"])
    if rng.random() < 0.5:
        return kind, line.decode(), data[:start] + line + data[end:], "any"
    return kind, "the one written big-endian", data[: end + 1] + struct.pack(">i", 1) + data[end + 5 :], "any"
