"""Where the datasets and attributes of a small HDF5 file lie, read with the standard library
alone (the fuzz harness runs where there is no h5py), and HDF5's metadata checksum.

Enough of the format (https://docs.hdfgroup.org/hdf5/v1_10/_f_m_t3.html) for the files that
hydrosoft writes: superblocks 0 to 3, object headers 1 and 2 (with continuation chunks),
groups as symbol tables (a version-1 B-tree, its symbol nodes and a local heap) or as link
messages in the header, datasets of contiguous or compact layout, attributes in the header.
Anything else (dense link or attribute storage, chunked datasets, external links) raises
H5LayoutError: the harness then falls back on blind byte mutations.
"""
import struct


class H5LayoutError(ValueError):
    pass


SIGNATURE = b"\x89HDF\r\n\x1a\n"
UNDEFINED = 0xFFFFFFFFFFFFFFFF


def lookup3(data, initval=0):
    """Bob Jenkins' lookup3 hashlittle(), HDF5's metadata checksum (H5_checksum_lookup3)."""
    mask = 0xFFFFFFFF

    def rot(x, k):
        return ((x << k) | (x >> (32 - k))) & mask

    length = len(data)
    a = b = c = (0xDEADBEEF + length + initval) & mask
    k = 0
    while length > 12:
        x, y, z = struct.unpack_from("<III", data, k)
        a, b, c = (a + x) & mask, (b + y) & mask, (c + z) & mask
        a = ((a - c) & mask) ^ rot(c, 4); c = (c + b) & mask
        b = ((b - a) & mask) ^ rot(a, 6); a = (a + c) & mask
        c = ((c - b) & mask) ^ rot(b, 8); b = (b + a) & mask
        a = ((a - c) & mask) ^ rot(c, 16); c = (c + b) & mask
        b = ((b - a) & mask) ^ rot(a, 19); a = (a + c) & mask
        c = ((c - b) & mask) ^ rot(b, 4); b = (b + a) & mask
        length -= 12
        k += 12
    if length == 0:
        return c
    x, y, z = struct.unpack("<III", bytes(data[k : k + length]) + bytes(12 - length))
    a, b, c = (a + x) & mask, (b + y) & mask, (c + z) & mask
    c ^= b; c = (c - rot(b, 14)) & mask
    a ^= c; a = (a - rot(c, 11)) & mask
    b ^= a; b = (b - rot(a, 25)) & mask
    c ^= b; c = (c - rot(b, 16)) & mask
    a ^= c; a = (a - rot(c, 4)) & mask
    b ^= a; b = (b - rot(a, 14)) & mask
    c ^= b; c = (c - rot(b, 24)) & mask
    return c


class Dataset:
    """A dataset: its raw data's place and size in the file, shape and element type.

    kind: 'i' (signed integer), 'u', 'f' or 's' (string); itemsize in bytes. `shape_at` is the
    file offset of the first dimension of its dataspace (so that a test can claim other sizes),
    `chunk` the object header chunk (start, end) that holds it when that chunk has a checksum.
    """

    def __init__(self, path, address, size, shape, kind, itemsize, shape_at, chunk):
        self.path, self.address, self.size, self.shape = path, address, size, shape
        self.kind, self.itemsize, self.shape_at, self.chunk = kind, itemsize, shape_at, chunk

    def __repr__(self):
        return f"Dataset({self.path}, at {self.address}, {self.size} B, {self.shape}, {self.kind}{self.itemsize})"


class Attribute:
    """An attribute kept in its object's header: its value's place and size in the file."""

    def __init__(self, owner, name, address, size, kind, chunk):
        self.owner, self.name, self.address, self.size, self.kind, self.chunk = owner, name, address, size, kind, chunk


class H5Layout:
    def __init__(self, data):
        self.data = bytes(data)
        self.datasets = {}
        self.attributes = []
        self.groups = ["/"]
        self.chunks = []  # (start, end, checksum offset) of every checksummed header chunk
        if not self.data.startswith(SIGNATURE):
            raise H5LayoutError("no HDF5 signature at the start")
        version = self.data[8]
        if version in (0, 1):
            self.O, self.L = self.data[13], self.data[14]
            at = 24 + (4 if version == 1 else 0)
            self.base = self._uint(at, self.O)
            root_entry = at + 4 * self.O
            root = self._uint(root_entry + self.O, self.O)
        elif version in (2, 3):
            self.O, self.L = self.data[9], self.data[10]
            self.base = self._uint(12, self.O)
            root = self._uint(12 + 3 * self.O, self.O)
        else:
            raise H5LayoutError(f"superblock version {version}")
        self._visit("/", root, set())

    # ---- little helpers ----
    def _uint(self, at, size):
        if at < 0 or at + size > len(self.data):
            raise H5LayoutError(f"read past the end at {at}")
        return int.from_bytes(self.data[at : at + size], "little")

    def _addr(self, at):
        value = self._uint(at, self.O)
        return value if value == (1 << (8 * self.O)) - 1 else value + self.base

    # ---- object headers ----
    def _messages(self, address):
        """[(type, data offset, size, chunk)] of the object header at `address`."""
        data = self.data
        found = []
        if data[address : address + 4] == b"OHDR":
            flags = data[address + 5]
            at = address + 6 + (16 if flags & 0x20 else 0) + (4 if flags & 0x10 else 0)
            width = 1 << (flags & 3)
            size = self._uint(at, width)
            start = at + width
            chunk = (address, start + size + 4, start + size)
            self.chunks.append(chunk)
            pending = [(start, start + size, chunk)]
            while pending:
                begin, end, chunk = pending.pop(0)
                header = 4 + (2 if flags & 0x04 else 0)
                at = begin
                while at + header <= end:
                    mtype, msize = data[at], self._uint(at + 1, 2)
                    body = at + header
                    if body + msize > end:
                        raise H5LayoutError(f"a message runs past its chunk at {at}")
                    found.append((mtype, body, msize, chunk))
                    if mtype == 0x10:
                        where, length = self._addr(body), self._uint(body + self.O, self.L)
                        if data[where : where + 4] != b"OCHK":
                            raise H5LayoutError(f"no OCHK at {where}")
                        cont = (where, where + length, where + length - 4)
                        self.chunks.append(cont)
                        pending.append((where + 4, where + length - 4, cont))
                    at = body + msize
            return found
        if data[address] != 1:
            raise H5LayoutError(f"object header version {data[address]} at {address}")
        count = self._uint(address + 2, 2)
        pending = [(address + 16, address + 16 + self._uint(address + 8, 4))]
        while pending and len(found) < count:
            at, end = pending.pop(0)
            while at + 8 <= end and len(found) < count:
                mtype, msize = self._uint(at, 2), self._uint(at + 2, 2)
                body = at + 8
                found.append((mtype, body, msize, None))
                if mtype == 0x10:
                    pending.append((self._addr(body), self._addr(body) + self._uint(body + self.O, self.L)))
                at = body + msize
        return found

    def _dataspace(self, at):
        version, rank, flags = self.data[at], self.data[at + 1], self.data[at + 2]
        first = at + (8 if version == 1 else 4)
        return [self._uint(first + i * self.L, self.L) for i in range(rank)], first

    def _datatype(self, at):
        cls = self.data[at] & 0x0F
        size = self._uint(at + 4, 4)
        if cls == 0:
            kind = "i" if self.data[at + 1] & 0x08 else "u"
        else:
            kind = {1: "f", 3: "s"}.get(cls, "?")
        return kind, size

    def _attribute(self, owner, at, chunk):
        version = self.data[at]
        name_size, type_size, space_size = (self._uint(at + 2 + 2 * i, 2) for i in range(3))
        pad = (lambda n: (n + 7) // 8 * 8) if version == 1 else (lambda n: n)
        at += 8 if version in (1, 2) else 9
        name = self.data[at : at + name_size].rstrip(b"\0").decode("utf-8", "replace")
        at += pad(name_size)
        kind, itemsize = self._datatype(at)
        at += pad(type_size)
        dims, _ = self._dataspace(at)
        at += pad(space_size)
        count = 1
        for d in dims:
            count *= d
        self.attributes.append(Attribute(owner, name, at, count * itemsize, kind, chunk))

    def _visit(self, path, address, seen):
        if address in seen:
            raise H5LayoutError(f"{path}: a cycle of links")
        seen.add(address)
        shape = layout = dtype = None
        children = []
        for mtype, at, size, chunk in self._messages(address):
            if mtype == 0x01:
                shape = self._dataspace(at) + (chunk,)
            elif mtype == 0x03:
                dtype = self._datatype(at)
            elif mtype == 0x08:
                layout = self._layout(at)
            elif mtype == 0x0C:
                self._attribute(path, at, chunk)
            elif mtype == 0x11:
                children += self._symbol_table(self._addr(at), self._addr(at + self.O))
            elif mtype == 0x06:
                children.append(self._link(at))
            elif mtype in (0x02, 0x15):  # link or attribute info: dense storage if it has a heap
                heap = self._addr(at + 2 + (8 if self.data[at + 1] & 1 else 0))
                if heap != UNDEFINED:
                    raise H5LayoutError(f"{path}: dense link or attribute storage")
        if layout is not None:
            dims, shape_at, chunk = shape
            self.datasets[path] = Dataset(path, layout[0], layout[1], dims, dtype[0], dtype[1], shape_at, chunk)
            return
        if path != "/":
            self.groups.append(path)
        for name, child in children:
            self._visit(path.rstrip("/") + "/" + name, child, seen)

    def _layout(self, at):
        version, cls = self.data[at], self.data[at + 1]
        if version != 3:
            raise H5LayoutError(f"layout message version {version}")
        if cls == 0:
            return at + 4, self._uint(at + 2, 2)
        if cls == 1:
            return self._addr(at + 2), self._uint(at + 2 + self.O, self.L)
        raise H5LayoutError("a chunked dataset")

    def _link(self, at):
        flags = self.data[at + 1]
        at += 2
        kind = 0
        if flags & 0x08:
            kind = self.data[at]
            at += 1
        at += (8 if flags & 0x04 else 0) + (1 if flags & 0x10 else 0)
        width = 1 << (flags & 3)
        length = self._uint(at, width)
        name = self.data[at + width : at + width + length].decode("utf-8", "replace")
        if kind != 0:
            raise H5LayoutError(f"link {name}: not a hard link")
        return name, self._addr(at + width + length)

    def _symbol_table(self, tree, heap):
        if self.data[heap : heap + 4] != b"HEAP":
            raise H5LayoutError(f"no local heap at {heap}")
        names = self._addr(heap + 8 + 2 * self.L)
        children = []
        pending = [tree]
        while pending:
            node = pending.pop()
            if self.data[node : node + 4] != b"TREE":
                raise H5LayoutError(f"no B-tree node at {node}")
            level, used = self.data[node + 5], self._uint(node + 6, 2)
            at = node + 8 + 2 * self.O + self.L  # past the siblings and the first key
            for _ in range(used):
                child = self._addr(at)
                if level > 0:
                    pending.append(child)
                else:
                    children += self._symbols(child, names)
                at += self.O + self.L
        return children

    def _symbols(self, node, names):
        if self.data[node : node + 4] != b"SNOD":
            raise H5LayoutError(f"no symbol node at {node}")
        found = []
        at = node + 8
        for _ in range(self._uint(node + 6, 2)):
            offset = self._uint(at, self.O)
            end = self.data.index(b"\0", names + offset)
            found.append((self.data[names + offset : end].decode("utf-8", "replace"), self._addr(at + self.O)))
            at += 2 * self.O + 24
        return found

    # ---- editing ----
    def chunk_holding(self, offset):
        """The checksummed header chunk (start, end, checksum offset) that holds `offset`, or None."""
        for chunk in self.chunks:
            if chunk[0] <= offset < chunk[2]:
                return chunk
        return None


def fix_checksums(data, layout):
    """Recomputes the checksum of every checksummed header chunk of `layout` in `data`
    (a bytearray of the same length): an edit inside a chunk then reads as the file's own."""
    for start, _, at in layout.chunks:
        if at + 4 <= len(data):
            data[at : at + 4] = struct.pack("<I", lookup3(bytes(data[start:at])))
    return data


def checksums_hold(data, layout):
    return all(struct.unpack_from("<I", data, at)[0] == lookup3(data[start:at]) for start, _, at in layout.chunks)


def read_rows(data, dataset):
    """The dataset's values, flat, in file order (little-endian numbers)."""
    code = {("i", 8): "q", ("i", 4): "i", ("u", 8): "Q", ("u", 4): "I", ("f", 8): "d", ("f", 4): "f"}
    fmt = code.get((dataset.kind, dataset.itemsize))
    if fmt is None:
        raise H5LayoutError(f"{dataset.path}: no reader for {dataset.kind}{dataset.itemsize}")
    count = dataset.size // dataset.itemsize
    return list(struct.unpack_from(f"<{count}{fmt}", data, dataset.address))
