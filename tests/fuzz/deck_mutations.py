"""Mutations of a deck's YAML text: keys deleted, misspelled and duplicated, values of the
wrong type or range, a second document, truncation, bytes a deck never holds.

Most mutations work on the text, so that a deck keeps its comments, flow maps and line
numbers and the validator's "(line N)" can be checked; a few rebuild the tree (a map where a
list was, and the reverse) through mini_yaml.py (no PyYAML needed). Every choice is drawn from
the `rng` given, so that a seed gives the same cases on every machine.
"""
import re

import mini_yaml

# Values that a deck key may be given by mistake or by an attacker.
ODD_VALUES = [
    "-1", "0", "-0.0", ".nan", ".inf", "-.inf", "1e308", "-1e308", "1e-308", "5e-324",
    "1e999", "2147483648", "-2147483649", "9223372036854775808", "1.5", "0x10", "1_000",
    '"1.0"', "''", '""', "null", "~", "true", "no", "[]", "{}", "[1, 2]", "{a: 1}",
    "[.nan, .nan, .nan]", "[1e308, 1e308, 1e308]", "[0, 0]", "[0, 0, 0, 0]",
    "text", "'" + "x" * 5000 + "'", "'" + "a/" * 3000 + "'", "!!binary aGVsbG8=",
    "!custom 1", "*undefined_anchor", "&a 1", '"\\u0000"', '"\\xff\\xfe"',
]

# Replacements for a number found anywhere in the text (a list item, a flow map's value).
ODD_NUMBERS = [
    "-1", "0", "-0", ".nan", ".inf", "-.inf", "1e308", "-1e308", "1e-308", "5e-324",
    "1e999", "-1e999", "2147483648", "1e30", "-1e30", "1e-30", "text", "''", "[]", "{}",
]

KEY_RE = re.compile(r"(?:(?<=^)|(?<=[\s{,]))([A-Za-z_][A-Za-z0-9_]*)\s*:(?=\s|$)")
NUMBER_RE = re.compile(r"(?<![\w.])[-+]?(?:\d+\.?\d*|\.\d+)(?:[eE][-+]?\d+)?(?![\w.])")


def code_part(line):
    """The line without its comment (decks quote no '#')."""
    if line.lstrip().startswith("#"):
        return ""
    at = line.find(" #")
    return line if at < 0 else line[:at]


def _closing(text, start):
    """Index after the bracket that closes text[start], or -1 if it does not on this line."""
    depth = 0
    for i in range(start, len(text)):
        if text[i] in "[{":
            depth += 1
        elif text[i] in "]}":
            depth -= 1
            if depth == 0:
                return i + 1
    return -1


class KeyAt:
    """One `key: value` of the text: its line, the spans of its key and its value."""

    def __init__(self, line, key_start, key_end, value_start, value_end, in_flow):
        self.line, self.key_start, self.key_end = line, key_start, key_end
        self.value_start, self.value_end, self.in_flow = value_start, value_end, in_flow


def find_keys(lines):
    keys = []
    for n, line in enumerate(lines):
        code = code_part(line)
        for m in KEY_RE.finditer(code):
            in_flow = code[: m.start()].count("{") > code[: m.start()].count("}")
            v = m.end()
            while v < len(code) and code[v] == " ":
                v += 1
            if v < len(code) and code[v] in "[{":
                end = _closing(code, v)
                if end < 0:
                    continue
            elif in_flow:
                end = v
                while end < len(code) and code[end] not in ",}]":
                    end += 1
            else:
                end = len(code.rstrip())
            keys.append(KeyAt(n, m.start(1), m.end(1), v, max(v, end), in_flow))
    return keys


def _children_end(lines, n):
    """The line after the block of lines indented deeper than line n (its children)."""
    indent = len(lines[n]) - len(lines[n].lstrip(" -"))
    k = n + 1
    while k < len(lines):
        s = lines[k]
        if s.strip() and not s.lstrip().startswith("#") and len(s) - len(s.lstrip(" -")) <= indent:
            break
        k += 1
    return k


def _misspell(rng, word):
    i = rng.randrange(len(word))
    edits = [
        word[:i] + word[i + 1 :] if len(word) > 1 else word + "x",
        word[:i] + word[i] + word[i:],
        word[:i] + word[i + 1 : i + 2] + word[i : i + 1] + word[i + 2 :],
        word.upper(),
        word + "s",
        word.replace("_", "-") if "_" in word else word + "_",
        word[:i] + "\u00e9" + word[i + 1 :],
    ]
    out = rng.choice(edits)
    return out if out != word else word + "x"


def _delete_key(lines, k):
    line = lines[k.line]
    if k.in_flow or not line[: k.key_start].strip() in ("", "-"):
        after = line[k.value_end :]
        before = line[: k.key_start]
        if after.lstrip().startswith(","):
            after = after.lstrip()[1:]
        elif before.rstrip().endswith(","):
            before = before.rstrip()[:-1]
        lines[k.line] = before + after
        return
    end = _children_end(lines, k.line) if k.value_start == k.value_end else k.line + 1
    if line[: k.key_start].strip() == "-" and end < len(lines):
        nxt = lines[end]
        dash = line.index("-")
        if len(nxt) - len(nxt.lstrip()) == dash + 2:  # the item's next key takes the dash
            lines[end] = " " * dash + "- " + nxt.lstrip()
    del lines[k.line : end]


def _set_value(lines, k, value):
    line = lines[k.line]
    if k.value_start == k.value_end and not k.in_flow:  # a block section: drop its children
        del lines[k.line + 1 : _children_end(lines, k.line)]
        lines[k.line] = line[: k.key_end] + ": " + value
        return
    lines[k.line] = line[: k.value_start] + value + line[k.value_end :]


def _duplicate_key(lines, k):
    line = lines[k.line]
    if k.in_flow:
        pair = line[k.key_start : k.value_end]
        lines[k.line] = line[: k.value_end] + ", " + pair + line[k.value_end :]
        return
    end = _children_end(lines, k.line) if k.value_start == k.value_end else k.line + 1
    copy = lines[k.line : end]
    if copy[0][: k.key_start].strip() == "-":
        copy[0] = copy[0].replace("-", " ", 1)
    lines[end:end] = copy


def _restructure(rng, text):
    """A map becomes a list or a scalar, a list a map, through the parsed tree."""
    tree = mini_yaml.load(text)
    places = []

    def walk(node, parent, key):
        if parent is not None:
            places.append((parent, key, node))
        if isinstance(node, dict):
            for k, v in node.items():
                walk(v, node, k)
        elif isinstance(node, list):
            for i, v in enumerate(node):
                walk(v, node, i)

    walk(tree, None, None)
    parent, key, node = rng.choice(places)
    if isinstance(node, dict):
        parent[key] = rng.choice([list(node.values()), list(node.items()), "map", 1, None])
    elif isinstance(node, list):
        parent[key] = rng.choice([{str(i): v for i, v in enumerate(node)}, node * 100, [node], 3])
    else:
        parent[key] = rng.choice([{"value": node}, [node], [node] * 3, {str(node): node}])
    return mini_yaml.dump(tree)


def mutate_deck(rng, text):
    """One mutation of a deck's text: (kind, detail, new text)."""
    lines = text.split("\n")
    keys = find_keys(lines)
    kinds = ["delete_key"] * 3 + ["misspell_key"] * 3 + ["odd_value"] * 6 + ["odd_number"] * 5
    kinds += ["duplicate_key"] * 2 + ["second_document", "truncate", "restructure"] * 1
    kinds += ["line_edit", "deep_nesting", "alias_bomb", "bad_bytes"]
    kind = rng.choice(kinds)
    k = rng.choice(keys)
    name = lines[k.line][k.key_start : k.key_end]
    detail = ""
    if kind == "delete_key":
        detail = f"line {k.line + 1}: {name}"
        _delete_key(lines, k)
    elif kind == "misspell_key":
        new = _misspell(rng, name)
        detail = f"line {k.line + 1}: {name} -> {new}"
        line = lines[k.line]
        lines[k.line] = line[: k.key_start] + new + line[k.key_end :]
    elif kind == "odd_value":
        value = rng.choice(ODD_VALUES)
        detail = f"line {k.line + 1}: {name}: {value[:40]}"
        _set_value(lines, k, value)
    elif kind == "duplicate_key":
        detail = f"line {k.line + 1}: {name}"
        _duplicate_key(lines, k)
    elif kind == "odd_number":
        spots = [(n, m) for n, l in enumerate(lines) for m in NUMBER_RE.finditer(code_part(l))]
        n, m = rng.choice(spots)
        value = rng.choice(ODD_NUMBERS)
        detail = f"line {n + 1}: {m.group(0)} -> {value}"
        lines[n] = lines[n][: m.start()] + value + lines[n][m.end() :]
    elif kind == "second_document":
        tail = rng.choice(["", "a: 1", text, "---", "..."])
        at = rng.randrange(len(lines) + 1)
        detail = f"'---' at line {at + 1}"
        lines[at:at] = ["---"] + ([tail] if tail else [])
    elif kind == "truncate":
        cut = rng.randrange(len(text))
        return kind, f"{cut} of {len(text)} bytes", text[:cut]
    elif kind == "restructure":
        return kind, "", _restructure(rng, text)
    elif kind == "line_edit":
        n = rng.randrange(len(lines))
        edit = rng.choice(["delete", "duplicate", "indent", "dedent", "tab", "long"])
        detail = f"line {n + 1}: {edit}"
        if edit == "delete":
            del lines[n]
        elif edit == "duplicate":
            lines.insert(n, lines[n])
        elif edit == "indent":
            lines[n] = "   " + lines[n]
        elif edit == "dedent":
            lines[n] = lines[n][min(2, len(lines[n]) - len(lines[n].lstrip())) :]
        elif edit == "tab":
            lines[n] = "\t" + lines[n]
        else:
            lines.insert(n, "z" * 200000 + ": 1")
    elif kind == "deep_nesting":
        depth = rng.choice([100, 1000, 100000])
        detail = f"line {k.line + 1}: {name}: depth {depth}"
        _set_value(lines, k, "[" * depth + "]" * depth)
    elif kind == "alias_bomb":  # 10^9 leaves if expanded; yaml-cpp shares the aliased nodes
        detail = f"line {k.line + 1}: {name}"
        bomb = ["&a0 [" + ", ".join(["1"] * 10) + "]"]
        bomb += [f"&a{i} [" + ", ".join([f"*a{i - 1}"] * 10) + "]" for i in range(1, 9)]
        _set_value(lines, k, "[" + ", ".join(bomb) + "]")
    elif kind == "bad_bytes":
        n = rng.randrange(len(lines))
        junk = rng.choice(["\x00", "\xff\xfe", "\ufeff", "\x1b[2J", "\u202e", "\r"])
        detail = f"line {n + 1}: {junk.encode('unicode_escape').decode()}"
        at = rng.randrange(len(lines[n]) + 1)
        lines[n] = lines[n][:at] + junk + lines[n][at:]
    return kind, detail, "\n".join(lines)


def override_mutation(rng, text):
    """A --set key=value of the command line: a key of the deck (maybe misspelled), an odd value."""
    tree = mini_yaml.load(text)
    paths = []

    def walk(node, path):
        if path:
            paths.append(path)
        if isinstance(node, dict):
            for k, v in node.items():
                walk(v, f"{path}.{k}" if path else str(k))
        elif isinstance(node, list):
            for i, v in enumerate(node):
                walk(v, f"{path}[{i}]")

    walk(tree, "")
    path = rng.choice(paths)
    shape = rng.choice(["value", "value", "misspell", "index", "malformed"])
    if shape == "misspell":
        path = _misspell(rng, path)
    elif shape == "index":
        path = re.sub(r"\[\d+\]", lambda m: "[" + rng.choice(["99", "4294967296", "-1"]) + "]", path)
        if "[" not in path:
            path += "[7]"
    elif shape == "malformed":
        path = rng.choice([path + ".", "." + path, path + "[", path + "[]", path.replace(".", "..")])
    value = rng.choice(ODD_VALUES + ODD_NUMBERS)
    return f"{path}={value}"
