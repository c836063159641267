"""Mutations of an ASCII gmsh .msh (formats 4.1 and 2.2): truncation, counts inflated,
coordinates NaN, infinite or huge, duplicated nodes, folded and inverted tetrahedra, element
nodes that do not exist, sections and physical names removed.

The file is read once into its lines and the places that matter (count fields, node
coordinate lines, tetrahedra); each mutation edits those lines. Choices come from `rng`.
"""

ODD_COORDINATES = ["nan", "-nan", "inf", "-inf", "1e308", "-1e308", "1e999", "1e-320", "x", ""]
ODD_COUNTS = ["0", "-1", "-2147483648", "2147483648", "4294967297", "9223372036854775807", "1e3", "x"]


class MshLayout:
    """Where the counts, nodes and tetrahedra of a .msh are, by line."""

    def __init__(self, text):
        self.lines = text.split("\n")
        self.version = self.lines[1].split()[0]
        self.counts = []  # (line, field)
        self.nodes = {}  # tag -> line of its coordinates (first field of them)
        self.tets = []  # (line, first node field)
        self.sections = {}  # name -> (first line, end line)
        for n, line in enumerate(self.lines):
            if line.startswith("$") and not line.startswith("$End"):
                end = self.lines.index("$End" + line[1:], n)
                self.sections[line[1:]] = (n, end)
        if self.version.startswith("4"):
            self._read_v4()
        else:
            self._read_v2()

    def _read_v4(self):
        first, end = self.sections["Nodes"]
        n = first + 1
        self.counts.append((n, 0))
        self.counts.append((n, 1))
        n += 1
        while n < end:
            count = int(self.lines[n].split()[3])
            self.counts.append((n, 3))
            tags = [int(self.lines[n + 1 + i]) for i in range(count)]
            for i, tag in enumerate(tags):
                self.nodes[tag] = n + 1 + count + i
            n += 1 + 2 * count
        first, end = self.sections["Elements"]
        n = first + 1
        self.counts.append((n, 0))
        self.counts.append((n, 1))
        n += 1
        while n < end:
            _, _, kind, count = (int(w) for w in self.lines[n].split())
            self.counts.append((n, 3))
            if kind in (4, 11):
                self.tets += [(n + 1 + i, 1) for i in range(count)]
            n += 1 + count

    def _read_v2(self):
        first, end = self.sections["Nodes"]
        self.counts.append((first + 1, 0))
        for n in range(first + 2, end):
            tag, _ = self.lines[n].split(" ", 1)
            self.nodes[int(tag)] = n
        first, end = self.sections["Elements"]
        self.counts.append((first + 1, 0))
        for n in range(first + 2, end):
            w = self.lines[n].split()
            if w[1] in ("4", "11"):
                self.tets.append((n, 3 + int(w[2])))

    def coordinate_fields(self, tag):
        line = self.nodes[tag]
        return line, (1 if self.version.startswith("2") else 0)

    def tet_nodes(self, tet):
        line, first = tet
        return [int(w) for w in self.lines[line].split()[first : first + 4]]


def _set_field(lines, n, field, value):
    words = lines[n].split()
    words[field] = value
    lines[n] = " ".join(words)


def mutate_msh(rng, text):
    """One mutation of a .msh's text: (kind, detail, new text)."""
    m = MshLayout(text)
    lines = m.lines
    kinds = ["truncate", "count", "count", "coordinate", "coordinate", "duplicate_node"]
    kinds += ["fold_node", "swap_tet_nodes", "flatten_tet", "missing_node", "drop_section"]
    kinds += ["rename_group", "delete_line", "duplicate_line", "format_header", "repeat_tet"]
    kinds += ["element_tag"]
    kind = rng.choice(kinds)
    tags = sorted(m.nodes)
    detail = ""
    if kind == "truncate":
        cut = rng.randrange(len(text))
        return kind, f"{cut} of {len(text)} bytes", text[:cut]
    if kind == "count":
        n, field = rng.choice(m.counts)
        value = rng.choice(ODD_COUNTS + [str(int(lines[n].split()[field]) * 1000 + 1)])
        detail = f"line {n + 1} field {field + 1}: {value}"
        _set_field(lines, n, field, value)
    elif kind == "coordinate":
        tag = rng.choice(tags)
        n, first = m.coordinate_fields(tag)
        field = first + rng.randrange(3)
        value = rng.choice(ODD_COORDINATES)
        detail = f"node {tag}: {value}"
        words = lines[n].split()
        words[field] = value
        lines[n] = " ".join(w for w in words if w)
    elif kind == "duplicate_node":
        a, b = rng.sample(tags, 2)
        (na, fa), (nb, fb) = m.coordinate_fields(a), m.coordinate_fields(b)
        detail = f"node {b} moved onto node {a}"
        xyz = lines[na].split()[fa : fa + 3]
        lines[nb] = " ".join(lines[nb].split()[:fb] + xyz)
    elif kind == "fold_node":  # a node pulled across its neighbours: folded tetrahedra
        tag = rng.choice(tags)
        n, first = m.coordinate_fields(tag)
        scale = rng.choice([-1.0, 2.0, 1e3, 0.0])
        detail = f"node {tag} times {scale}"
        words = lines[n].split()
        words[first : first + 3] = [repr(float(w) * scale) for w in words[first : first + 3]]
        lines[n] = " ".join(words)
    elif kind in ("swap_tet_nodes", "flatten_tet", "missing_node", "repeat_tet", "element_tag"):
        tet = rng.choice(m.tets)
        n, first = tet
        words = lines[n].split()
        detail = f"line {n + 1}"
        if kind == "swap_tet_nodes":  # negative orientation: renumbered, not an error
            words[first], words[first + 1] = words[first + 1], words[first]
        elif kind == "flatten_tet":  # a vertex repeated: zero volume
            words[first + 3] = words[first]
        elif kind == "missing_node":
            words[first + rng.randrange(4)] = rng.choice(
                ["0", "-1", "-5", str(max(tags) + 7), "4294967296", "18446744073709551615", "1.5"])
        elif kind == "element_tag":
            words[0] = rng.choice(["0", "-1", "1", "18446744073709551615", "99999999999"])
        else:
            lines.insert(n, lines[n])
        if kind != "repeat_tet":
            lines[n] = " ".join(words)
    elif kind == "drop_section":
        name = rng.choice([s for s in m.sections if s != "MeshFormat"] + ["MeshFormat"])
        first, end = m.sections[name]
        detail = name
        del lines[first : end + 1]
    elif kind == "rename_group":
        first, end = m.sections["PhysicalNames"]
        n = rng.randrange(first + 2, end)
        detail = lines[n]
        lines[n] = lines[n].rsplit(" ", 1)[0] + rng.choice([' "renamed"', ' ""', " noquotes", ' "' + "g" * 5000 + '"'])
    elif kind in ("delete_line", "duplicate_line"):
        n = rng.randrange(len(lines))
        detail = f"line {n + 1}"
        if kind == "delete_line":
            del lines[n]
        else:
            lines.insert(n, lines[n])
    elif kind == "format_header":
        value = rng.choice(["9.9 0 8", "1.0 0 8", "4.1 1 8", "4.1 0 4", "2.2 0 8", "4.1 0 8", "x", ""])
        detail = value
        lines[1] = value
    return kind, detail, "\n".join(lines)
