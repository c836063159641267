"""The YAML the decks of input/ are written in, read and written without PyYAML, so that the
harness runs on a machine with /usr/bin/python3's standard library alone: block maps and
lists, flow maps and lists, plain scalars, comments. Scalars stay the text they are (the
harness needs the tree's shape, not the values' types); an empty value is None.

fuzz.py checks, where PyYAML is installed, that this reads every deck to the same shape.
"""
import re


def _code(line):
    if line.lstrip().startswith("#"):
        return ""
    at = line.find(" #")
    return (line if at < 0 else line[:at]).rstrip()


def _flow(text):
    """A flow value: [a, b], {k: v}, nested, or a plain scalar."""
    tokens = re.findall(r"[\[\]{},]|[^\[\]{},]+", text)
    tokens = [t.strip() for t in tokens if t.strip()]
    pos = 0

    def value():
        nonlocal pos
        t = tokens[pos]
        pos += 1
        if t == "[":
            items = []
            while tokens[pos] != "]":
                items.append(value())
                if tokens[pos] == ",":
                    pos += 1
            pos += 1
            return items
        if t == "{":
            node = {}
            while tokens[pos] != "}":
                key, _, rest = tokens[pos].partition(":")
                pos += 1
                if rest.strip():
                    node[key.strip()] = rest.strip()
                elif tokens[pos] in (",", "}"):
                    node[key.strip()] = None
                else:
                    node[key.strip()] = value()
                if tokens[pos] == ",":
                    pos += 1
            pos += 1
            return node
        if t.endswith(":") and pos < len(tokens) and tokens[pos] in ("[", "{"):
            raise ValueError("a key inside a flow list")
        return t

    node = value()
    if pos != len(tokens):
        raise ValueError(f"trailing text in {text!r}")
    return node


def _key_value(content):
    m = re.match(r"([^\s:\[\]{},][^:]*?)\s*:(?:\s+(.*))?$", content)
    return (m.group(1), (m.group(2) or "").strip()) if m else None


def load(text):
    lines = []
    for line in text.split("\n"):
        code = _code(line)
        if code.strip():
            lines.append((len(code) - len(code.lstrip(" ")), code.strip()))
    pos = 0

    def block(indent):
        nonlocal pos
        first_indent, content = lines[pos]
        if content == "-" or content.startswith("- "):
            items = []
            while pos < len(lines) and lines[pos][0] == first_indent and (
                    lines[pos][1] == "-" or lines[pos][1].startswith("- ")):
                rest = lines[pos][1][1:].strip()
                if not rest:
                    pos += 1
                    items.append(block(first_indent + 1))
                elif _key_value(rest) and not rest.startswith(("[", "{")):
                    # "- key: value" opens a map whose keys line up with "key".
                    lines[pos] = (first_indent + 2, rest)
                    items.append(mapping(first_indent + 2))
                else:
                    items.append(_flow(rest))
                    pos += 1
            return items
        return mapping(first_indent)

    def mapping(indent):
        nonlocal pos
        node = {}
        while pos < len(lines) and lines[pos][0] == indent:
            kv = _key_value(lines[pos][1])
            if kv is None:
                raise ValueError(f"not a key: {lines[pos][1]!r}")
            key, rest = kv
            pos += 1
            if rest:
                node[key] = _flow(rest)
            elif pos < len(lines) and (lines[pos][0] > indent or (
                    lines[pos][0] == indent and lines[pos][1].startswith("- "))):
                node[key] = block(indent)
            else:
                node[key] = None
        return node

    if not lines:
        return None
    tree = block(0)
    if pos != len(lines):
        raise ValueError(f"unexpected indentation at {lines[pos][1]!r}")
    return tree


def _scalar(node):
    return "null" if node is None else str(node)


def dump(node, indent=0):
    """Block YAML of a tree of dicts, lists and scalars (plain, as read)."""
    pad = " " * indent
    if isinstance(node, dict):
        if not node:
            return pad + "{}\n"
        out = ""
        for k, v in node.items():
            if isinstance(v, (dict, list)) and v:
                out += f"{pad}{_scalar(k)}:\n" + dump(v, indent + 2)
            else:
                out += f"{pad}{_scalar(k)}: {dump(v).strip()}\n"
        return out
    if isinstance(node, list):
        if not node:
            return pad + "[]\n"
        out = ""
        for v in node:
            if isinstance(v, (dict, list)) and v:
                body = dump(v, indent + 2)
                out += f"{pad}- " + body[indent + 2 :]
            else:
                out += f"{pad}- {dump(v).strip()}\n"
        return out
    if isinstance(node, tuple):
        return dump(list(node), indent)
    return pad + _scalar(node) + "\n"


def shape(node):
    """The tree with every scalar replaced by '' (what must agree with PyYAML's)."""
    if isinstance(node, dict):
        return {str(k): shape(v) for k, v in node.items()}
    if isinstance(node, list):
        return [shape(v) for v in node]
    return ""
