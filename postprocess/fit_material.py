#!/usr/bin/python3
"""Fits a silicone's test data to hydrosoft's hyperelastic laws and prints the deck lines.

    /usr/bin/python3 postprocess/fit_material.py UNIAXIAL.csv [--biaxial EQUIBIAXIAL.csv]
        [--law neo_hookean|mooney_rivlin|yeoh|gent|all] [--nu 0.49] [--stress-unit Pa|kPa|MPa]
        [--group body]

Each CSV has two columns, the stretch (current length / initial length) and the nominal
stress (force / initial area), with an optional header line; the stretch may instead be a
strain (column header "strain", stretch = 1 + strain). Points at stretch 1 are kept (they pin
the curve's start).

Each law is fitted in its incompressible form (a silicone's nu is 0.49-0.4999; the deck's nu
sets only the bulk modulus), by least squares on the nominal stress of the tests:
    uniaxial      P = 2 (l - l^-2) (W1 + W2 / l),    I1 = l^2 + 2/l,    I2 = 2 l + l^-2
    equibiaxial   P = 2 (l - l^-5) (W1 + l^2 W2),    I1 = 2 l^2 + l^-4, I2 = l^4 + 2 l^-2
with W1 = dW/dI1, W2 = dW/dI2 of
    neo_hookean   W = mu/2 (I1 - 3)
    mooney_rivlin W = c1 (I1 - 3) + c2 (I2 - 3)
    yeoh          W = C1 x + C2 x^2 + C3 x^3, x = I1 - 3
    gent          W = -mu Jm/2 ln(1 - (I1 - 3)/Jm)
The first three are linear in their coefficients (one linear least-squares solve); gent is
linear in mu for a given Jm, and Jm is found by a golden-section search on the residual.
The deck's laws use the isochoric invariants, equal to these when J = 1 (docs/materials.md).
Printed per law: the coefficients, the fit's relative RMS error, and the materials entry.
"""
import argparse
import math
import sys

import numpy as np

LAWS = ("neo_hookean", "mooney_rivlin", "yeoh", "gent")
UNITS = {"Pa": 1.0, "kPa": 1e3, "MPa": 1e6}


def invariants(stretch, mode):
    l = np.asarray(stretch, dtype=float)
    if mode == "uniaxial":
        return l**2 + 2 / l, 2 * l + l**-2
    return 2 * l**2 + l**-4, l**4 + 2 * l**-2


def factors(stretch, mode):
    """P = a W1 + b W2 for the test `mode`: the nominal stress's factors of W1 and W2."""
    l = np.asarray(stretch, dtype=float)
    if mode == "uniaxial":
        return 2 * (l - l**-2), 2 * (l - l**-2) / l
    return 2 * (l - l**-5), 2 * (l - l**-5) * l**2


def nominal_stress(law, coefficients, stretch, mode="uniaxial"):
    """The incompressible nominal stress of `law` (coefficients as fit() returns them) in a
    uniaxial or equibiaxial test at the given stretches."""
    I1, _ = invariants(stretch, mode)
    a, b = factors(stretch, mode)
    x = I1 - 3
    c = coefficients
    if law == "neo_hookean":
        return a * c["mu"] / 2
    if law == "mooney_rivlin":
        return a * c["c1"] + b * c["c2"]
    if law == "yeoh":
        return a * (c["C1"] + 2 * c["C2"] * x + 3 * c["C3"] * x**2)
    if law == "gent":
        return a * c["mu"] / 2 / (1 - x / c["Jm"])
    raise ValueError(f"unknown law {law}")


def design(law, stretch, mode, Jm=None):
    """The columns of the linear least-squares problem P = A k for the law's coefficients k."""
    I1, _ = invariants(stretch, mode)
    a, b = factors(stretch, mode)
    x = I1 - 3
    if law == "neo_hookean":
        return np.column_stack([a / 2])
    if law == "mooney_rivlin":
        return np.column_stack([a, b])
    if law == "yeoh":
        return np.column_stack([a, 2 * a * x, 3 * a * x**2])
    if law == "gent":
        return np.column_stack([a / 2 / (1 - x / Jm)])
    raise ValueError(f"unknown law {law}")


NAMES = {"neo_hookean": ["mu"], "mooney_rivlin": ["c1", "c2"], "yeoh": ["C1", "C2", "C3"],
         "gent": ["mu"]}


def _solve(law, tests, Jm=None):
    A = np.vstack([design(law, s, mode, Jm) for mode, s, _ in tests])
    P = np.concatenate([p for _, _, p in tests])
    k, *_ = np.linalg.lstsq(A, P, rcond=None)
    return k, float(np.sum((A @ k - P) ** 2))


def fit(law, tests):
    """Least-squares coefficients of `law` for `tests`, a list of (mode, stretch, stress)."""
    if law != "gent":
        k, _ = _solve(law, tests)
        return dict(zip(NAMES[law], (float(v) for v in k)))
    # Jm must exceed every test's I1 - 3; the residual is searched in log(Jm - x_max).
    x_max = max(float(np.max(invariants(s, mode)[0] - 3)) for mode, s, _ in tests)
    floor = max(x_max, 1e-12)

    def residual(t):
        return _solve("gent", tests, x_max + floor * math.exp(t))[1]

    lo, hi = math.log(1e-6), math.log(1e8)
    # A coarse scan first: the residual need not be unimodal over eight decades.
    grid = np.linspace(lo, hi, 141)
    best = int(np.argmin([residual(t) for t in grid]))
    lo, hi = grid[max(best - 1, 0)], grid[min(best + 1, len(grid) - 1)]
    g = (math.sqrt(5) - 1) / 2
    a, b = hi - g * (hi - lo), lo + g * (hi - lo)
    fa, fb = residual(a), residual(b)
    for _ in range(200):
        if fa < fb:
            hi, b, fb = b, a, fa
            a = hi - g * (hi - lo)
            fa = residual(a)
        else:
            lo, a, fa = a, b, fb
            b = lo + g * (hi - lo)
            fb = residual(b)
        if hi - lo < 1e-12:
            break
    Jm = x_max + floor * math.exp(0.5 * (lo + hi))
    k, _ = _solve("gent", tests, Jm)
    return {"mu": float(k[0]), "Jm": Jm}


def relative_rms(law, coefficients, tests):
    errors, scale = [], []
    for mode, s, p in tests:
        errors.append(nominal_stress(law, coefficients, s, mode) - p)
        scale.append(p)
    e, p = np.concatenate(errors), np.concatenate(scale)
    return float(np.sqrt(np.mean(e**2)) / max(np.sqrt(np.mean(p**2)), 1e-300))


def number(value):
    """Four significant digits, as the deck reads them back: 110000, 1.235e+07, -300."""
    return format(float(f"{value:.4g}"), "g")


def deck_entry(law, c, nu, group):
    """The materials entry of docs/decks.md for the fitted coefficients (SI units)."""
    def young(mu):  # E, nu give the small-strain shear modulus mu and the bulk modulus
        return number(2 * mu * (1 + nu))

    head = f"  - {{group: {group}, model: {law}, "
    if law == "neo_hookean":
        return head + f"E: {young(c['mu'])}, nu: {nu}}}"
    if law == "mooney_rivlin":  # E, nu of mu = 2 (c1 + c2), so that kappa matches nu
        return head + (f"E: {young(2 * (c['c1'] + c['c2']))}, nu: {nu}, "
                       f"c1: {number(c['c1'])}, c2: {number(c['c2'])}}}")
    if law == "yeoh":
        return head + (f"C1: {number(c['C1'])}, C2: {number(c['C2'])}, "
                       f"C3: {number(c['C3'])}, nu: {nu}}}")
    return head + f"E: {young(c['mu'])}, nu: {nu}, Jm: {number(c['Jm'])}}}"


def warnings(law, c):
    """What makes a fit unusable in the deck or beyond the data."""
    out = []
    if law in ("neo_hookean", "gent") and c["mu"] <= 0:
        out.append("mu <= 0: the data are not a rubber's")
    if law == "mooney_rivlin" and c["c1"] + c["c2"] <= 0:
        out.append("c1 + c2 <= 0: the deck refuses it")
    if law == "yeoh" and c["C1"] <= 0:
        out.append("C1 <= 0: the deck refuses it (fit fewer terms or more data near stretch 1)")
    return out


def read_csv(path, unit):
    """(stretch, nominal stress in Pa) from a two-column CSV; a header 'strain' means strain."""
    rows, strain = [], False
    with open(path) as f:
        for line_number, line in enumerate(f, 1):
            line = line.strip()
            if not line or line.startswith("#"):
                continue
            cells = [c.strip() for c in line.replace(";", ",").split(",")]
            try:
                rows.append((float(cells[0]), float(cells[1])))
            except (ValueError, IndexError):
                if rows:
                    sys.exit(f"fit_material.py: {path}, line {line_number}: expected two numbers")
                strain = cells[0].lower().startswith("strain")
    if len(rows) < 2:
        sys.exit(f"fit_material.py: {path}: fewer than two data rows")
    data = np.array(rows)
    stretch = data[:, 0] + (1.0 if strain else 0.0)
    if np.any(stretch <= 0):
        sys.exit(f"fit_material.py: {path}: a stretch <= 0 (is the first column a strain? "
                 "name it 'strain' in a header)")
    return stretch, data[:, 1] * UNITS[unit]


def main(argv=None):
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("uniaxial", help="CSV: stretch, nominal stress")
    p.add_argument("--biaxial", help="CSV of an equibiaxial test: stretch, nominal stress")
    p.add_argument("--law", choices=LAWS + ("all",), default="all")
    p.add_argument("--nu", type=float, default=0.49,
                   help="Poisson's ratio for the deck's bulk modulus (default 0.49)")
    p.add_argument("--stress-unit", choices=sorted(UNITS), default="Pa")
    p.add_argument("--group", default="body")
    a = p.parse_args(argv)
    if not -1 < a.nu < 0.5:
        sys.exit("fit_material.py: --nu must be in (-1, 0.5)")
    tests = [("uniaxial",) + read_csv(a.uniaxial, a.stress_unit)]
    if a.biaxial:
        tests.append(("equibiaxial",) + read_csv(a.biaxial, a.stress_unit))
    for law in LAWS if a.law == "all" else (a.law,):
        c = fit(law, tests)
        terms = ", ".join(f"{k} = {number(v)}" + ("" if k == "Jm" else " Pa")
                          for k, v in c.items())
        print(f"# {law}: {terms}; relative RMS error {relative_rms(law, c, tests):.3g}")
        for w in warnings(law, c):
            print(f"#   warning: {w}")
        print(deck_entry(law, c, a.nu, a.group))


if __name__ == "__main__":
    main()
