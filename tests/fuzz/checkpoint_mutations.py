"""Mutations of a checkpoint.h5 (src/io/checkpoint_file.cpp: the JSON `state` attribute of
the root group, /node_ids, /fields/<name>): the JSON's values changed to ones out of range
or of another type, its keys deleted, its text cut or reordered, the node rows permuted,
repeated or out of range, a field value NaN, a dataset claiming other rows, bytes flipped
or cut (with and without the header checksums made to match again, so that HDF5 reads what
was changed).

The JSON is edited in place: the new text must fit the old one's length (JSON allows the
spaces that pad it; the informative `deck` path gives room where a value grows). Each
mutation says what the restart must do: 'reject' (refused with one line), 'same' (refused
cleanly, or accepted with the uninterrupted run's final displacements), 'any' (accepted with
a finite result, or refused cleanly).
"""
import json
import struct

from h5_layout import H5Layout, fix_checksums, read_rows

REQUIRED = ["kind", "fingerprint", "nodes", "elements", "order", "coordinate_checksum", "stats", "position"]
ODD_STEPS = [25, -5, 2**62, -(2**62), 10**30, 1e308, 2.5, "7", None, [], {}]
ODD_VALUES = [-1, 0, 2**62, 1e308, -1e308, 1.5, "x", None, True, [], {}, [1, 2]]


class StateText:
    """The `state` attribute: its place in the file and its JSON."""

    def __init__(self, data, layout):
        attribute = next(a for a in layout.attributes if a.owner == "/" and a.name == "state")
        self.at, self.size = attribute.address, attribute.size
        self.state = json.loads(data[self.at : self.at + self.size].decode("utf-8"))

    def fit(self, text):
        """`text` as bytes of exactly the attribute's length (padded), or None if it is longer."""
        raw = text.encode("utf-8", "surrogateescape") if isinstance(text, str) else text
        return raw + b" " * (self.size - len(raw)) if len(raw) <= self.size else None


def _dump(state, shuffle_rng=None):
    if shuffle_rng is not None:
        def shuffled(node):
            if isinstance(node, dict):
                items = list(node.items())
                shuffle_rng.shuffle(items)
                return {k: shuffled(v) for k, v in items}
            return [shuffled(v) for v in node] if isinstance(node, list) else node
        state = shuffled(state)
    return json.dumps(state, separators=(",", ":"), sort_keys=shuffle_rng is None)


def _json_mutation(rng, state, position_step, total_steps):
    """(kind, detail, new state or text, expect)."""
    s = json.loads(json.dumps(state))
    kind = rng.choice(["step", "step", "delete", "delete_inner", "retype", "mesh_counts", "kind_name",
                       "fingerprint", "checksum", "last", "ranks", "stats", "reorder", "deck", "cut_text",
                       "bad_utf8", "load_factor"])
    if kind == "step":
        value = rng.choice(ODD_STEPS + [position_step + 1, position_step - 1, 0])
        s["position"]["step"] = value
        in_range = isinstance(value, int) and not isinstance(value, bool) and 0 <= value < total_steps
        return kind, f"position.step {value!r}", s, "any" if in_range else "reject"
    if kind == "delete":
        key = rng.choice(REQUIRED + ["deck", "ranks"])
        del s[key]
        return kind, f"no {key}", s, "reject" if key in REQUIRED else "any"
    if kind == "delete_inner":
        parent = rng.choice(["position", "stats"])
        key = rng.choice(sorted(s[parent]))
        del s[parent][key]
        return kind, f"no {parent}.{key}", s, "any"
    if kind == "retype":
        parent = rng.choice([None, "position", "stats"])
        node = s if parent is None else s[parent]
        key = rng.choice(sorted(node))
        value = rng.choice(ODD_VALUES)
        node[key] = value
        return kind, f"{(parent + '.') if parent else ''}{key} {value!r}", s, "any"
    if kind == "mesh_counts":
        key = rng.choice(["nodes", "elements", "order"])
        value = rng.choice([s[key] + 1, s[key] - 1, 0, -1, 2**62, 3])
        s[key] = value
        return kind, f"{key} {value}", s, "reject"
    if kind == "kind_name":
        value = rng.choice(["dynamic", "states", "dynamic_states", "control", "", "STATIC", "static "])
        s["kind"] = value
        return kind, f"kind {value!r}", s, "reject"
    if kind == "fingerprint":
        text = s["fingerprint"]
        value = rng.choice([text[:-1] + ("0" if text[-1] != "0" else "1"), "", text.upper(), text + "0"])
        s["fingerprint"] = value
        return kind, f"fingerprint {value!r}", s, "reject"
    if kind == "checksum":
        s["coordinate_checksum"][0] = rng.choice([s["coordinate_checksum"][0] + 1, 0, -1e308])
        return kind, f"coordinate_checksum {s['coordinate_checksum'][0]}", s, "reject"
    if kind == "last":
        s["position"]["last"] = True
        return kind, "position.last true", s, "reject"
    if kind == "ranks":  # where the checkpoint was written: informative only
        value = rng.choice([0, -1, 2, 64, 2**62])
        s["ranks"] = value
        return kind, f"ranks {value}", s, "same"
    if kind == "stats":
        key = rng.choice(sorted(s["stats"]))
        value = rng.choice([-5, 2**62, 1e308, -1e308, 0.5])
        s["stats"][key] = value
        return kind, f"stats.{key} {value!r}", s, "any"
    if kind == "reorder":
        return kind, "keys in another order", _dump(s, rng), "same"
    if kind == "deck":
        value = rng.choice(["", "d", "../../etc/passwd", "\u00e9\u00e9", "x" * 20])
        s["deck"] = value
        return kind, f"deck {value!r}", s, "same"
    if kind == "cut_text":
        text = _dump(s)
        cut = rng.randrange(1, len(text))
        return kind, f"the JSON cut at {cut} of {len(text)}", text[:cut], "reject"
    if kind == "bad_utf8":
        text = _dump(s).encode()
        at = text.index(b'"deck":"') + len(b'"deck":"')
        return kind, "a byte 0xff in deck", text[:at] + b"\xff\xfe" + text[at:], "any"
    value = rng.choice([float("inf"), -0.5, 2.0, 1e308, s["position"].get("load_factor", 0) + 1e-3])
    s["position"]["load_factor"] = value
    if value == float("inf"):
        return "load_factor", "position.load_factor Infinity", _dump(s), "reject"
    return "load_factor", f"position.load_factor {value!r}", s, "any"


def _fit_state(st, new):
    """Bytes of the new state that fit the attribute, shortening `deck` if need be, or None."""
    if isinstance(new, (str, bytes)):
        return st.fit(new)
    raw = st.fit(_dump(new))
    if raw is None and "deck" in new:
        new = dict(new, deck="")
        raw = st.fit(_dump(new))
    return raw


def mutate_checkpoint(rng, data, total_steps):
    """One mutation of the bytes of a checkpoint of a run of `total_steps` steps: (kind, detail,
    new bytes, expect)."""
    layout = H5Layout(data)
    st = StateText(data, layout)
    out = bytearray(data)
    family = rng.choice(["json"] * 5 + ["rows"] * 2 + ["bytes"] * 2)
    if family == "json":
        for _ in range(20):  # a mutation whose text does not fit is drawn again
            kind, detail, new, expect = _json_mutation(rng, st.state, st.state["position"].get("step", 0), total_steps)
            raw = _fit_state(st, new)
            if raw is not None:
                out[st.at : st.at + st.size] = raw
                return "json_" + kind, detail, bytes(fix_checksums(out, layout)), expect
        return "json_none", "nothing fitted", data, "same"
    sets = layout.datasets
    ids = sets["/node_ids"]
    fields = sorted(p for p in sets if p.startswith("/fields/"))
    n = ids.shape[0]
    if family == "rows":
        kind = rng.choice(["permute", "permute", "repeat_id", "id_out", "nan", "claimed_rows", "rename_field"])
        if kind == "permute":  # the rows in another order, each field's with its id: the same state
            order = list(range(n))
            rng.shuffle(order)
            for dataset, width in [(ids, 1)] + [(sets[f], 3) for f in fields]:
                fmt = "q" if dataset is ids else "d"
                values = read_rows(data, dataset)
                for new_row, old_row in enumerate(order):
                    for c in range(width):
                        struct.pack_into("<" + fmt, out, dataset.address + 8 * (new_row * width + c),
                                         values[old_row * width + c])
            return "rows_permute", f"{n} rows shuffled", bytes(out), "same"
        if kind == "repeat_id":
            a, b = rng.sample(range(n), 2)
            struct.pack_into("<q", out, ids.address + 8 * b, read_rows(data, ids)[a])
            return "rows_repeat_id", f"/node_ids[{b}] = /node_ids[{a}]", bytes(out), "reject"
        if kind == "id_out":
            row = rng.randrange(n)
            value = rng.choice([-1, n, n + 7, 2**62, -(2**63)])
            struct.pack_into("<q", out, ids.address + 8 * row, value)
            return "rows_id_out", f"/node_ids[{row}] = {value}", bytes(out), "reject"
        if kind == "nan":
            field = sets[rng.choice(fields)]
            at = rng.randrange(3 * n)
            value = rng.choice([float("nan"), float("inf"), -1e308])
            struct.pack_into("<d", out, field.address + 8 * at, value)
            # Refusing is right; a restart that goes on must still end with finite results (a
            # value of a held node, or of the predictor's previous state, may not matter).
            return "rows_nan", f"{field.path}[{at // 3}][{at % 3}] = {value}", bytes(out), "any"
        if kind == "claimed_rows":
            dataset = rng.choice([ids] + [sets[f] for f in fields])
            value = rng.choice([0, 1, n - 1, n + 1, 2**40, 2**64 - 1])
            out[dataset.shape_at : dataset.shape_at + layout.L] = value.to_bytes(layout.L, "little")
            return "rows_claimed", f"{dataset.path}: {n} rows -> {value}", bytes(fix_checksums(out, layout)), "any"
        name = rng.choice(fields).rsplit("/", 1)[1].encode()  # rename_field: a field gone
        at = bytes(out).find(name, 0, ids.address)
        out[at] = ord("X") if out[at] != ord("X") else ord("Y")
        return "rows_rename_field", f"{name.decode()} renamed", bytes(fix_checksums(out, layout)), "reject"
    kind = rng.choice(["flip", "flip_fixed", "truncate"])
    if kind == "truncate":
        cut = rng.randrange(len(data))
        return "bytes_truncate", f"{cut} of {len(data)} bytes", data[:cut], "any"
    spots = []
    for _ in range(rng.randint(1, 6)):
        at = rng.randrange(len(out))
        out[at] ^= 1 << rng.randrange(8)
        spots.append(str(at))
    if kind == "flip_fixed":  # HDF5 then reads the flipped metadata as the file's own
        fix_checksums(out, layout)
    return "bytes_" + kind, "bytes " + ", ".join(spots), bytes(out), "any"
