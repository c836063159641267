#!/usr/bin/python3
"""The arithmetic of postprocess/refinement_study.py, no runs: the observed order and the
Richardson extrapolation recover p and q0 of synthetic sequences q(h) = q0 + C h^p (constant
and uneven refinement ratios; for a constant ratio p is also ln((q1 - q2)/(q2 - q3)) / ln r);
oscillating, diverging and mesh-independent sequences give no order and say why; the
quantity paths into summary.json resolve, and a wrong one is refused naming what is there.

    /usr/bin/python3 tests/postprocess/refinement_math_test.py
"""
import importlib.util
import math
import os

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
spec = importlib.util.spec_from_file_location("refinement_study",
                                              os.path.join(ROOT, "postprocess", "refinement_study.py"))
rs = importlib.util.module_from_spec(spec)
spec.loader.exec_module(rs)


def close(a, b, tol):
    return abs(a - b) <= tol * max(1.0, abs(b))


def check_power_laws():
    cases = [((0.4, 0.2, 0.1), 2.0, 1.0, 0.3), ((0.4, 0.2, 0.1), 3.0, -2.5, 7.0),
             ((0.011, 0.008, 0.0055), 2.0, 12.0, 8.9), ((1.0, 0.7, 0.3), 1.5, 0.01, -4.0),
             ((0.5, 0.35, 0.25), 4.0, -300.0, 1e-3), ((3.0, 2.9, 1.0), 0.7, 1.0, 2.0)]
    for h, p, c, q0 in cases:
        q = [q0 + c * x**p for x in h]
        res = rs.observed_order(h, q)
        assert res["p"] is not None and close(res["p"], p, 1e-8), (h, p, res)
        assert close(res["q_inf"], q0, 1e-9), (h, p, q0, res)
        assert close(res["error"], abs(c) * h[2] ** p, 1e-7), (h, p, res, abs(c) * h[2] ** p)
        if math.isclose(h[0] / h[1], h[1] / h[2]):  # the closed form of a constant ratio
            direct = math.log((q[0] - q[1]) / (q[1] - q[2])) / math.log(h[0] / h[1])
            assert close(res["p"], direct, 1e-10), (res["p"], direct)
    # A higher-order term only perturbs: p near 2, q_inf much closer to q0 than the finest.
    h = (0.04, 0.02, 0.01)
    q = [1.0 + 0.5 * x**2 + 3.0 * x**3 for x in h]
    res = rs.observed_order(h, q)
    assert 1.9 < res["p"] < 2.3 and abs(res["q_inf"] - 1.0) < 0.1 * abs(q[2] - 1.0), res
    # Whole levels: h_eff from the element counts, h = (V / elements)^(1/3) with any V; the
    # errors of every level, and only the finest three enter the order.
    rows = [dict(order=2, elements=e, time_total_s=1.0) for e in (100, 1000, 8000, 27000)]
    for r in rows:
        r["q"] = 5.0 + 0.2 * (3.0 / r["elements"]) ** (3.0 / 3.0)
    rows[0]["q"] += 1.0  # far from the asymptote, and outside the three finest
    (res,) = rs.analyse(rows, ["q"])
    assert close(res["p"], 3.0, 1e-8) and close(res["q_inf"], 5.0, 1e-10), res
    for r in rows:
        assert close(r["q error"], r["q"] - 5.0, 1e-8), r
    print(f"power laws: {len(cases)} sequences and a study's levels, p and q0 recovered")


def check_no_order():
    h = (0.4, 0.2, 0.1)
    osc = rs.observed_order(h, [1.0 + (-1) ** i * 0.1 * x**2 for i, x in enumerate(h)])
    assert osc["p"] is None and osc["q_inf"] is None and osc["note"].startswith("oscillating"), osc
    grow = rs.observed_order(h, [1.0, 1.1, 1.3])
    assert grow["p"] is None and "do not shrink" in grow["note"], grow
    flat = rs.observed_order(h, [2.0, 2.0 + 1e-12, 2.0])
    assert flat["p"] is None and flat["q_inf"] == 2.0 and close(flat["error"], 2e-9, 1e-6), flat
    same_mesh = rs.observed_order((0.4, 0.4, 0.1), [1.0, 1.1, 1.2])
    assert same_mesh["p"] is None and "not refined" in same_mesh["note"], same_mesh
    assert "not asymptotic" in rs.plausibility(dict(p=9.0, note=""), 1)["note"]
    assert rs.plausibility(dict(p=2.0, note=""), 1)["note"] == ""
    print("no order: oscillating, growing, flat and unrefined sequences named")


def refused(summary, path, *words):
    try:
        rs.resolve(summary, path)
    except rs.QuantityError as e:
        assert all(w in str(e) for w in words), (path, str(e), words)
        return
    raise AssertionError(f"{path} was accepted")


def check_paths():
    assert rs.parse_path("end_of_run.cavities[0].pressure") == ["end_of_run", "cavities", 0, "pressure"]
    assert rs.parse_path("states[-1].tip") == ["states", -1, "tip"]
    assert rs.parse_path("reactions_N.top[1]") == ["reactions_N", "top", 1]
    assert rs.parse_path("states[inflated].x") == ["states", ("inflated",), "x"]
    s = {"dofs": 12, "reactions_N": {"top": [0.5, -1.5, 2.5]},
         "states": [{"name": "rest", "tip": {"d": 1.0}}, {"name": "inflated", "tip": {"d": 2.0}}],
         "end_of_run": {"cavities": [{"name": "a", "pressure": 3.0}, {"name": "b", "pressure": 4.0}]}}
    assert rs.resolve(s, "dofs") == 12.0
    assert rs.resolve(s, "reactions_N.top[1]") == -1.5
    assert rs.resolve(s, "reactions_N.top[-1]") == 2.5
    assert rs.resolve(s, "states[-1].tip.d") == 2.0
    assert rs.resolve(s, "states[rest].tip.d") == 1.0
    assert rs.resolve(s, "end_of_run.cavities[b].pressure") == 4.0
    refused(s, "end_of_run.cavity[0]", "no key 'cavity'", "cavities")
    refused(s, "nope", "no key 'nope'", "dofs", "reactions_N", "states")
    refused(s, "states[5].tip", "out of range", "list of 2")
    refused(s, "end_of_run.cavities[c].pressure", "no item named 'c'", "a, b")
    refused(s, "reactions_N.top", "not a number", "list of 3")
    refused(s, "states[0]", "not a number", "name, tip")
    for bad in ("", ".dofs", "a..b", "a[", "a[1]b", "a b"):
        try:
            rs.parse_path(bad)
        except rs.QuantityError as e:
            assert bad == "" or "position" in str(e), (bad, str(e))
            continue
        raise AssertionError(f"'{bad}' parsed")
    assert rs.default_quantities(s) == ["states[-1].tip.displacement_magnitude_m", "states[-1].tip.inclination_deg",
                                        "end_of_run.cavities[a].volume_ml", "end_of_run.cavities[a].pressure",
                                        "end_of_run.cavities[b].volume_ml", "end_of_run.cavities[b].pressure",
                                        "reactions_N.top[2]"]
    print("paths: resolved, and wrong ones refused naming what is there")


if __name__ == "__main__":
    check_power_laws()
    check_no_order()
    check_paths()
