"""A deck's .geo that reaches for other files: meshes/block.geo with `Include`, `Merge`,
`Open` or `MergeWithBoundingBox` lines naming helper files the case writes beside it (random
names, extensions .txt .msh .geo .opt .gz .py .pos .step, none, mixed case; in a subfolder,
through `..`), whose content is a payload: a shell command (`SystemCall`, `System`,
`NonBlockingSystemCall`), a file written (`Printf > file`, `Save`, `CreateDir`), `Exit`,
a chain of further Merges and Includes, a script named .msh, a mesh named .txt, Python, a
gzip of any of these, garbage; and option files `<name>.opt` beside the .geo, beside a
merged file or beside a .msh mesh. With and without mesh.parameters.

Every file a payload would make is named MARKER_...: the judge (classify.py) looks for them
after the run, in the case's folder and in the folder beside it (`@OUTSIDE@`, replaced by
its absolute path when the case is written).
"""
import gzip

EXTENSIONS = [".txt", ".msh", ".geo", ".opt", "", ".TXT", ".Geo", ".MSH", ".gz", ".py", ".pos", ".step", ".geo.opt"]
COMMANDS = ["Merge"] * 4 + ["Include"] * 4 + ["Open", "MergeWithBoundingBox"]
DECK = """mesh:
  file: {file}
{parameters}materials:
  - {{group: body, model: neo_hookean, E: 1.0e6, nu: 0.3, density: 1000}}
boundary:
  - {{group: bottom}}
loads:
  gravity: [0, 0, -9.81]
time: {{type: static, steps: 1}}
solver: {{preset: mumps}}
"""


class GeoCase:
    def __init__(self, rng, block_geo, mesh_text):
        self.rng, self.block_geo, self.mesh_text = rng, block_geo, mesh_text
        self.files = {}  # path in the run folder -> bytes
        self.count = 0
        self.nonblocking = False
        self.notes = []

    def marker(self, what):
        self.count += 1
        where = self.rng.choice(["", "", "sub/", "../outside/", "@OUTSIDE@/"])
        return f"{where}MARKER_{what}_{self.count}"

    def payload(self, depth):
        """The text of a helper file: what it does, as .geo script (or not)."""
        r = self.rng
        kind = r.choice(["system", "system", "printf", "save", "exit", "chain", "chain", "benign",
                         "mesh", "options", "python", "garbage"])
        if depth > 2 and kind == "chain":
            kind = "system"
        self.notes.append(kind)
        if kind == "system":
            command = r.choice(["SystemCall", "System", "NonBlockingSystemCall"])
            self.nonblocking |= command == "NonBlockingSystemCall"
            return f'{command} "touch {self.marker("sys")}";\n'
        if kind == "printf":
            return f'Printf("owned") {r.choice([">", ">>"])} "{self.marker("printf")}";\n'
        if kind == "save":
            return r.choice([f'Save "{self.marker("save")}.msh";\n', f'CreateDir "{self.marker("dir")}";\n'])
        if kind == "exit":
            return r.choice(["Exit;\n", "Abort;\n", "Exit(0);\n"])
        if kind == "chain":
            return self.reference(depth + 1)
        if kind == "benign":
            return r.choice(["// nothing here\n", f"hs_fuzz_{self.count} = 1;\n", ""])
        if kind == "mesh":  # a mesh under any name
            return self.mesh_text
        if kind == "options":
            return r.choice(["General.Terminal = 1;\n", "Mesh.Algorithm = 6;\n",
                             f'General.SessionFileName = "{self.marker("session")}";\n',
                             f'Solver.Executable0 = "touch {self.marker("solver")}";\n'])
        if kind == "python":
            return f'open("{self.marker("python")}", "w").write("owned")\n'
        return "".join(chr(r.randrange(1, 256)) for _ in range(r.randint(1, 200)))

    def helper(self, depth, extension=None):
        """Writes a helper file with a payload; returns the name a .geo refers to it by."""
        r = self.rng
        ext = extension if extension is not None else r.choice(EXTENSIONS)
        zipped = ext == ".gz"
        if zipped:
            ext = r.choice([".txt", ".geo", ".msh", ""]) + ".gz"
        self.count += 1
        path = r.choice(["", "", "", "sub/"]) + r.choice(["helper", "part", "x", "data", "Helper"]) + str(self.count) + ext
        self.files[path] = b""  # named before its payload, which may name more files
        if depth > 1 and r.random() < 0.05:  # a file that merges itself
            text = f'{r.choice(["Merge", "Include"])} "{path.rsplit("/", 1)[-1]}";\n'
            self.notes.append("loop")
        else:
            text = self.payload(depth)
        raw = text.encode("latin-1")
        self.files[path] = gzip.compress(raw, mtime=0) if zipped else raw
        if r.random() < 0.15:  # an options file beside the helper
            self.files[path + ".opt"] = self.payload(depth + 1).encode("latin-1")
        way = r.choice(["", "", "./", "sub/../"]) if "/" not in path else r.choice(["", "./"])
        return way + path

    def reference(self, depth):
        name = self.helper(depth)
        command = self.rng.choice(COMMANDS)
        if self.rng.random() < 0.05:
            return f'{command} StrCat("{name[:2]}", "{name[2:]}");\n'
        return f'{command} "{name}";\n'


def make_geo_case(rng, block_geo, mesh_text):
    """One case: (kind, detail, files, deck text, mesh file name, mode, nonblocking), mode
    'check' (hydrosoft --check), 'run' (a real run) or 'mesh' (hydrosoft mesh DECK OUT.h5)."""
    case = GeoCase(rng, block_geo, mesh_text)
    kind = rng.choice(["reference", "reference", "reference", "opt_beside_geo", "opt_beside_merged",
                       "msh_opt", "script_named", "direct"])
    main = "body.geo"
    lines = block_geo.split("\n")
    if kind == "msh_opt":  # a .msh mesh with an options file beside it
        main = rng.choice(["body.msh", "mesh.msh", "Body.MSH"])
        case.files[main] = mesh_text.encode()
        case.files[main + ".opt"] = case.payload(1).encode("latin-1")
        if rng.random() < 0.3:
            case.files[main.rsplit(".", 1)[0] + ".opt"] = case.payload(1).encode("latin-1")
    else:
        references = [case.reference(1) for _ in range(rng.randint(1 if kind != "direct" else 0, 3))]
        if kind == "direct":
            references.append(case.payload(3))
        if kind == "opt_beside_merged":
            name = case.helper(1, rng.choice([".txt", ".msh", ".geo", ""]))
            case.files[name.replace("sub/../", "").replace("./", "") + ".opt"] = case.payload(2).encode("latin-1")
            references.append(f'Merge "{name}";\n')
        for text in references:
            at = rng.choice([0, len(lines) // 2, len(lines) - 1])
            lines.insert(at, text.rstrip("\n"))
        if kind == "script_named":
            main = rng.choice(["body.msh", "body.txt", "body.GEO", "body", "body.geo.txt", "body.Geo"])
        case.files[main] = "\n".join(lines).encode("latin-1")
        if kind == "opt_beside_geo" or rng.random() < 0.1:
            case.files[main + ".opt"] = case.payload(2).encode("latin-1")
            if rng.random() < 0.3:
                case.files[main.rsplit(".", 1)[0] + ".opt"] = case.payload(2).encode("latin-1")
    parameters = "  parameters: {h: 0.5}\n" if rng.random() < 0.6 and kind != "msh_opt" else ""
    deck = DECK.format(file=main, parameters=parameters)
    mode = rng.choice(["check"] * 7 + ["run"] * 2 + ["mesh"] * 2)
    detail = f"{main}: " + ",".join(case.notes) + "; files " + " ".join(sorted(case.files))
    return kind, detail[:300], case.files, deck, main, mode, case.nonblocking
