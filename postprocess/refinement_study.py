#!/usr/bin/python3
"""Refinement study of any deck, with or without an exact solution: runs hydrosoft on a series
of meshes (mesh sizes --h and/or uniform refinements --refine, P1 and/or P2), reads chosen
quantities from each run's summary.json, and from the three finest levels of each element
order estimates the observed order p, the Richardson-extrapolated value q_inf and the error
of every level, |q - q_inf|. Writes refinement.csv, refinement.md and refinement.png (each
quantity's estimated error against run time, log-log, one line per order).

    /usr/bin/python3 postprocess/refinement_study.py input/cylinder_air.yaml \\
        --h 0.011 0.008 0.0055 --order 1 2 --quantity 'states[-1].tip.displacement_m[1]'

Quantity paths into summary.json: keys joined by '.', list items by [i] (negative counts from
the end) or by [name] (the item whose "name" or "group" is name), e.g.
end_of_run.cavities[cavity].pressure, states[inflated].tip.inclination_deg,
reactions_N.top[1]. The path must end at a number. Without --quantity the defaults are
whatever the first run has of: the last state's tip displacement and inclination, each
cavity's end volume and pressure, each reaction group's largest component, the verification
tip deflection.

Mesh size: the ratio between levels is r = (elements_fine / elements_coarse)^(1/3), i.e. the
ratio of h_eff = (V / elements)^(1/3) with the domain volume V cancelled -- what the mesher
made, not what was asked for. --volume V also prints h_eff itself. Levels are ordered by
their element counts. --h-key must name a key that sets the mesh size and nothing else (the
cantilever's mesh.parameters.h is the beam's section: refine it with mesh.parameters.n).

Observed order from three levels with ratios r21 = h1/h2, r32 = h2/h3 (coarse to fine):
(q1 - q2)/(q2 - q3) = r32^p (r21^p - 1)/(r32^p - 1), which is r^p for a constant ratio r;
then q_inf = q3 + (q3 - q2)/(r32^p - 1). Differences of opposite sign (oscillating) or growing
ones (p <= 0) give no order and no extrapolation: the table says which.
"""
import argparse
import csv
import itertools
import json
import math
import os
import re
import subprocess
import sys

TOKEN = re.compile(r"\.?([A-Za-z_][A-Za-z0-9_]*)|\[(-?\d+)\]|\[([^\[\]]+)\]")


class QuantityError(Exception):
    pass


def parse_path(path):
    """'a.b[0].c[name]' -> ['a', 'b', 0, 'c', ('name',)]; a syntax error names the position."""
    tokens, pos = [], 0
    while pos < len(path):
        m = TOKEN.match(path, pos)
        if not m or (pos == 0 and path[0] == ".") or (pos > 0 and m.group(1) and path[pos] != "."):
            raise QuantityError(f"quantity '{path}': cannot read it at position {pos} "
                                f"('{path[pos:]}'); write keys.joined.by.dots, [index] or [name]")
        key, index, name = m.groups()
        tokens.append(key if key is not None else int(index) if index is not None else (name,))
        pos = m.end()
    if not tokens:
        raise QuantityError("empty quantity path")
    return tokens


def resolve(summary, path):
    """The number at path in summary; an error names the failing step and what is there."""
    node, done = summary, ""
    for t in parse_path(path):
        where = done or "summary.json"
        if isinstance(t, str):
            if not isinstance(node, dict) or t not in node:
                have = ", ".join(sorted(node)) if isinstance(node, dict) else type(node).__name__
                raise QuantityError(f"quantity '{path}': {where} has no key '{t}' (it has: {have})")
            node, done = node[t], f"{done}.{t}" if done else t
        elif isinstance(t, int):
            if not isinstance(node, list) or not -len(node) <= t < len(node):
                size = f"a list of {len(node)}" if isinstance(node, list) else type(node).__name__
                raise QuantityError(f"quantity '{path}': {where}[{t}] is out of range ({where} is {size})")
            node, done = node[t], f"{done}[{t}]"
        else:
            names = [i.get("name", i.get("group")) for i in node if isinstance(i, dict)] \
                if isinstance(node, list) else []
            if t[0] not in names:
                raise QuantityError(f"quantity '{path}': {where} has no item named '{t[0]}' "
                                    f"(names: {', '.join(map(str, names)) or 'none'})")
            node, done = node[names.index(t[0])], f"{done}[{t[0]}]"
    if isinstance(node, bool) or not isinstance(node, (int, float)):
        what = f"a list of {len(node)}: pick one with [i]" if isinstance(node, list) else \
            f"an object with keys {', '.join(sorted(node))}" if isinstance(node, dict) else repr(node)
        raise QuantityError(f"quantity '{path}' is not a number: it is {what}")
    return float(node)


def default_quantities(summary):
    """The quantities a summary offers that a refinement study usually wants."""
    q = []
    states = summary.get("states") or []
    if states and "tip" in states[-1]:
        q += ["states[-1].tip.displacement_magnitude_m", "states[-1].tip.inclination_deg"]
    for c in (summary.get("end_of_run") or {}).get("cavities", []):
        q += [f"end_of_run.cavities[{c['name']}].volume_ml", f"end_of_run.cavities[{c['name']}].pressure"]
    for group, force in (summary.get("reactions_N") or {}).items():
        q.append(f"reactions_N.{group}[{max(range(3), key=lambda i: abs(force[i]))}]")
    if "tip_deflection" in (summary.get("verification") or {}):
        q.append("verification.tip_deflection")
    return q


def observed_order(h, q, noise=1e-9):
    """Order, extrapolated value and error estimate from three levels, coarse to fine.

    h: the three mesh sizes (any common scale), q: the values; differences below noise times
    the values are the solver's tolerance, not the mesh. Returns dict(p, q_inf, error, note):
    p and q_inf are None where the sequence gives none, and note says why."""
    (h1, h2, h3), (q1, q2, q3) = h, q
    r21, r32 = h1 / h2, h2 / h3
    if r21 <= 1 + 1e-9 or r32 <= 1 + 1e-9:
        return dict(p=None, q_inf=None, error=None, note="levels not refined (same or coarser mesh)")
    e21, e32 = q1 - q2, q2 - q3
    scale = max(abs(q1), abs(q2), abs(q3), 1e-300)
    if abs(e21) <= noise * scale and abs(e32) <= noise * scale:
        return dict(p=None, q_inf=q3, error=noise * scale,
                    note=f"the same on the finest three levels (to {noise:g} relative)")
    if abs(e32) <= noise * scale:
        return dict(p=None, q_inf=q3, error=noise * scale,
                    note=f"the finest two levels agree (to {noise:g} relative)")
    rho = e21 / e32
    if rho <= 0:
        return dict(p=None, q_inf=None, error=None,
                    note=f"oscillating: no order; the finest three spread over {max(q) - min(q):.3g}")

    def g(p):  # (q1 - q2)/(q2 - q3) for an error C h^p; increases with p from ln r21 / ln r32
        return r32**p * (r21**p - 1) / (r32**p - 1)

    if rho <= math.log(r21) / math.log(r32):
        return dict(p=None, q_inf=None, error=None,
                    note="differences do not shrink (p <= 0): not converging at these sizes")
    lo, hi = 1e-12, 1.0
    while g(hi) < rho:
        hi *= 2
        if hi > 64:
            return dict(p=None, q_inf=q3, error=abs(e32),
                        note="differences shrink faster than any order up to 64")
    for _ in range(200):
        mid = 0.5 * (lo + hi)
        lo, hi = (mid, hi) if g(mid) < rho else (lo, mid)
    p = 0.5 * (lo + hi)
    q_inf = q3 - e32 / (r32**p - 1)
    return dict(p=p, q_inf=q_inf, error=abs(q3 - q_inf), note="")


def plausibility(res, order):
    """A note where p is far from what an element of this order gives (1 to 2(k + 1))."""
    if res["p"] is not None and not 0.5 <= res["p"] <= 2 * (order + 1):
        res["note"] = f"p outside 0.5 to {2 * (order + 1)}: probably not asymptotic yet, q_inf uncertain"
    return res


def run_level(args, order, h, refine):
    name = f"p{order}" + (f"_h{h:g}" if h is not None else "") + (f"_r{refine}" if refine is not None else "")
    folder = os.path.join(args.out, name)
    cmd = []
    if args.np > 1:
        cmd = ["mpirun", "--oversubscribe", "-np", str(args.np)]
        if os.geteuid() == 0:
            cmd.append("--allow-run-as-root")
    cmd += [args.binary, args.deck, "-q", "--set", f"mesh.order={order}", "--set", f"output.folder={folder}"]
    if refine is not None:  # only when asked: a deck whose mesh is not a .geo takes no refine
        cmd += ["--set", f"mesh.refine={refine}"]
    if h is not None:
        cmd += ["--set", f"{args.h_key}={h}"]
    for s in args.set:
        cmd += ["--set", s]
    env = dict(os.environ, OPENBLAS_NUM_THREADS="1")
    result = subprocess.run(cmd, capture_output=True, text=True, env=env)
    if result.returncode != 0:
        sys.exit(f"refinement_study: {args.deck} P{order} {name} failed:\n{result.stderr[-3000:]}")
    with open(os.path.join(folder, "summary.json")) as f:
        return json.load(f)


def analyse(rows, quantities, noise=1e-9):
    """Per order and quantity: the three finest levels' order, q_inf and each level's error."""
    results = []
    for order in sorted({r["order"] for r in rows}):
        levels = [r for r in rows if r["order"] == order]
        sizes = [r["elements"] ** (-1.0 / 3.0) for r in levels]
        for name in quantities:
            values = [r[name] for r in levels]
            if len(levels) < 3:
                res = dict(p=None, q_inf=None, error=None, note="fewer than three levels")
            else:
                res = plausibility(observed_order(sizes[-3:], values[-3:], noise), order)
            for r in levels:
                r[f"{name} error"] = abs(r[name] - res["q_inf"]) if res["q_inf"] is not None else None
            results.append(dict(order=order, quantity=name, finest=values[-1],
                                time_s=levels[-1]["time_total_s"], **res))
    return results


def fmt(x, spec=".6g"):
    return "-" if x is None else format(x, spec)


def write_markdown(path, deck, rows, quantities, results, volume):
    lines = [f"# Refinement study: {deck}", ""]
    for order in sorted({r["order"] for r in rows}):
        levels = [r for r in rows if r["order"] == order]
        head = ["h", "refine", "elements", "dofs"] + (["h_eff"] if volume else []) + ["run time s"]
        lines += [f"P{order}:", "", "| " + " | ".join(head + quantities) + " |",
                  "|" + "---|" * (len(head) + len(quantities))]
        for r in levels:
            cells = [fmt(r["h"], "g"), fmt(r["refine"], "d"), f"{r['elements']:,}", f"{r['dofs']:,}"]
            cells += [f"{(volume / r['elements']) ** (1 / 3):.4g}"] if volume else []
            cells += [f"{r['time_total_s']:.2f}"] + [fmt(r[q]) for q in quantities]
            lines.append("| " + " | ".join(cells) + " |")
        lines.append("")
    lines += ["Observed order p, extrapolated value q_inf and the finest level's error estimate "
              "|q - q_inf| (three finest levels):", "",
              "| element | quantity | finest | p | q_inf | error estimate | run time s | note |",
              "|---|---|---|---|---|---|---|---|"]
    for res in results:
        lines.append(f"| P{res['order']} | `{res['quantity']}` | {fmt(res['finest'])} | "
                     f"{fmt(res['p'], '.2f')} | {fmt(res['q_inf'])} | {fmt(res['error'], '.2e')} | "
                     f"{res['time_s']:.2f} | {res['note']} |")
    with open(path, "w") as f:
        f.write("\n".join(lines) + "\n")


def plot(path, deck, rows, quantities, results):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    n = len(quantities)
    cols = min(n, 3)
    fig, axes = plt.subplots((n + cols - 1) // cols, cols, figsize=(4.6 * cols, 3.8 * ((n + cols - 1) // cols)),
                             squeeze=False)
    for ax, name in zip(axes.flat, quantities):
        for order, marker in zip(sorted({r["order"] for r in rows}), "osd^"):
            pts = [(r["time_total_s"], r[f"{name} error"]) for r in rows
                   if r["order"] == order and r[f"{name} error"]]
            res = next(x for x in results if x["order"] == order and x["quantity"] == name)
            label = f"P{order}, p = {res['p']:.2f}" if res["p"] is not None else \
                f"P{order}: {res['note'].split(':')[0] or 'no order'}"
            if pts:
                ax.loglog(*zip(*pts), marker + "-", label=label)
            else:
                ax.plot([], [], marker, label=label)
        ax.set_title(name, fontsize=9)
        ax.set_xlabel(f"run time, s ({rows[0]['ranks']} rank(s), whole run)")
        ax.set_ylabel("estimated error |q - q_inf|")
        ax.grid(True, which="both", alpha=0.3)
        ax.legend(fontsize=8)
    for ax in list(axes.flat)[n:]:
        ax.set_visible(False)
    fig.suptitle(os.path.basename(deck))
    fig.tight_layout()
    fig.savefig(path, dpi=110)


def main():
    p = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("deck")
    p.add_argument("--h", type=float, nargs="+",
                   help="mesh sizes, coarse first (default: the deck's); the values of --h-key")
    p.add_argument("--h-key", default="mesh.parameters.h",
                   help="the deck key --h sets (e.g. mesh.parameters.n, elements across a section)")
    p.add_argument("--refine", type=int, nargs="+", help="uniform refinements, mesh.refine (default: the deck's)")
    p.add_argument("--order", type=int, nargs="+", default=[1, 2], choices=[1, 2])
    p.add_argument("--quantity", nargs="+", help="paths into summary.json (default: see above)")
    p.add_argument("--set", action="append", default=[], help="another deck override, key=value")
    p.add_argument("--binary", default="build/bin/hydrosoft")
    p.add_argument("--np", type=int, default=1, help="MPI ranks (more than 1: through mpirun)")
    p.add_argument("--volume", type=float, help="the domain's volume, to print h_eff")
    p.add_argument("--noise", type=float, default=1e-9,
                   help="relative differences below this are solver tolerance, not the mesh")
    p.add_argument("--out", default="out/refinement")
    args = p.parse_args()
    for what, path in (("deck", args.deck), ("binary", args.binary)):
        if not os.path.isfile(path):
            sys.exit(f"refinement_study: {what} '{path}' not found")
    try:
        for q in args.quantity or []:
            parse_path(q)
    except QuantityError as e:
        sys.exit(f"refinement_study: {e}")
    if len(set(args.order)) != len(args.order):
        sys.exit("refinement_study: --order lists an order twice")
    if any(h <= 0 for h in args.h or []) or any(k < 0 for k in args.refine or []):
        sys.exit("refinement_study: --h must be > 0 and --refine >= 0")
    os.makedirs(args.out, exist_ok=True)

    # Run in the order given (the first run, which checks the quantities, best the cheapest);
    # the analysis orders the levels by their element counts.
    levels = list(itertools.product(args.h or [None], args.refine or [None]))
    rows, quantities = [], args.quantity
    for order in args.order:
        for h, refine in levels:
            s = run_level(args, order, h, refine)
            if quantities is None:
                quantities = default_quantities(s)
                if not quantities:
                    sys.exit("refinement_study: the summary has none of the default quantities; name "
                             f"them with --quantity (summary.json's keys: {', '.join(sorted(s))})")
            try:
                values = {q: resolve(s, q) for q in quantities}
            except QuantityError as e:
                sys.exit(f"refinement_study: {e}")
            rows.append(dict(order=order, h=h, refine=refine, elements=s["elements"], dofs=s["dofs"],
                             ranks=s["ranks"], time_total_s=s["time_s"]["total"], **values))
            print(f"P{order} h={fmt(h, 'g')} refine={fmt(refine, 'd')} dofs={s['dofs']:>8} "
                  f"t={s['time_s']['total']:.2f}s " + " ".join(f"{v:.6g}" for v in values.values()),
                  flush=True)

    rows.sort(key=lambda r: (args.order.index(r["order"]), r["elements"]))
    results = analyse(rows, quantities, args.noise)
    csv_path = os.path.join(args.out, "refinement.csv")
    with open(csv_path, "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=list(rows[0].keys()))
        w.writeheader()
        w.writerows(rows)
    md = os.path.join(args.out, "refinement.md")
    write_markdown(md, args.deck, rows, quantities, results, args.volume)
    png = os.path.join(args.out, "refinement.png")
    plot(png, args.deck, rows, quantities, results)
    for res in results:
        print(f"P{res['order']} {res['quantity']}: p = {fmt(res['p'], '.2f')}, q_inf = {fmt(res['q_inf'])}, "
              f"error estimate {fmt(res['error'], '.2e')} {res['note']}")
    print(f"wrote {csv_path}, {md} and {png}")


if __name__ == "__main__":
    main()
