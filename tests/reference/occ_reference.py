#!/usr/bin/env python3
"""Generate independent reference values for the dieface NURBS kernel.

Reference implementation: OpenCascade (OCCT) through the `cadquery-ocp`
Python bindings (Geom_BSplineCurve, Geom_BSplineSurface, GeomAPI_Interpolate,
GeomFill_BSplineCurves in Coons style, Geom_SurfaceOfRevolution), plus
`geomdl` (pure-Python, NURBS Book algorithms) for the averaged-knot
interpolation cases.

Usage (from the crate root):

    pip install -r tests/reference/requirements.txt
    python3 tests/reference/occ_reference.py            # rewrites tests/data/occ_reference.json
    python3 tests/reference/occ_reference.py --stdout   # print instead of writing

All inputs are hand written or drawn from `random.Random(<fixed seed>)` and
rounded to 4 decimals, so the output is deterministic.  Every value written
to the JSON file is a Python float printed with repr(), which round-trips
exactly to an IEEE double.

Besides writing the data the script cross-checks OCC against a small
independent evaluator written below (NURBS Book A2.2/A2.3/A4.2/A4.4) and
against the analytic formulas for Coons patches and surfaces of revolution;
it aborts if any of those disagree by more than 1e-10 (relative to the size
of the object).  See tests/reference/README.md for the conventions.
"""

import json
import math
import os
import random
import sys
from importlib import metadata

from OCP.collections import (
    Array1_double,
    Array1_gp_Pnt,
    Array1_int,
    Array2_double,
    Array2_gp_Pnt,
    HArray1_double,
    HArray1_gp_Pnt,
)
from OCP.Geom import Geom_BSplineCurve, Geom_BSplineSurface, Geom_SurfaceOfRevolution
from OCP.GeomAPI import GeomAPI_Interpolate
from OCP.GeomFill import GeomFill_BSplineCurves, GeomFill_FillingStyle
from OCP.gp import gp_Ax1, gp_Dir, gp_Pnt, gp_Vec

from geomdl import fitting

HERE = os.path.dirname(os.path.abspath(__file__))
OUT = os.path.normpath(os.path.join(HERE, "..", "data", "occ_reference.json"))

SQRT2_2 = math.sqrt(2.0) / 2.0
CHECK_TOL = 1e-10

# ---------------------------------------------------------------------------
# small helpers
# ---------------------------------------------------------------------------


def r4(x):
    """Round an input value to 4 decimals (keeps the JSON readable)."""
    v = round(x, 4)
    return 0.0 if v == 0.0 else v  # no negative zeros


def vec(v):
    """gp_Pnt / gp_Vec -> [x, y, z] without negative zeros."""
    return [c + 0.0 for c in (v.X(), v.Y(), v.Z())]


def norm(a):
    return math.sqrt(sum(c * c for c in a))


def sub(a, b):
    return [x - y for x, y in zip(a, b)]


def add(a, b):
    return [x + y for x, y in zip(a, b)]


def scale(s, a):
    return [s * x for x in a]


def dist_rel(a, b, size):
    return norm(sub(a, b)) / max(1.0, size, norm(b))


def compress(flat):
    """Flat knot vector -> (distinct knots, multiplicities)."""
    ks, ms = [], []
    for k in flat:
        if ks and k == ks[-1]:
            ms[-1] += 1
        else:
            ks.append(k)
            ms.append(1)
    return ks, ms


def arr1_real(values):
    a = Array1_double(1, len(values))
    for i, v in enumerate(values):
        a.SetValue(i + 1, float(v))
    return a


def arr1_int(values):
    a = Array1_int(1, len(values))
    for i, v in enumerate(values):
        a.SetValue(i + 1, int(v))
    return a


def arr1_pnt(points):
    a = Array1_gp_Pnt(1, len(points))
    for i, p in enumerate(points):
        a.SetValue(i + 1, gp_Pnt(*p))
    return a


def harr1_pnt(points):
    a = HArray1_gp_Pnt(1, len(points))
    for i, p in enumerate(points):
        a.SetValue(i + 1, gp_Pnt(*p))
    return a


def harr1_real(values):
    a = HArray1_double(1, len(values))
    for i, v in enumerate(values):
        a.SetValue(i + 1, float(v))
    return a


def to_list(arr):
    return [arr.Value(i) for i in range(arr.Lower(), arr.Upper() + 1)]


# ---------------------------------------------------------------------------
# independent evaluator (used only for cross-checking OCC)
# ---------------------------------------------------------------------------


def find_span(n, p, t, U):
    """NURBS Book A2.1; n = number of control points - 1.  Right-side span."""
    if t >= U[n + 1]:
        return n
    if t <= U[p]:
        return p
    lo, hi = p, n + 1
    mid = (lo + hi) // 2
    while t < U[mid] or t >= U[mid + 1]:
        if t < U[mid]:
            hi = mid
        else:
            lo = mid
        mid = (lo + hi) // 2
    return mid


def ders_basis(i, t, p, n, U):
    """NURBS Book A2.3: derivatives 0..n of the p+1 non-zero basis functions."""
    ndu = [[0.0] * (p + 1) for _ in range(p + 1)]
    ndu[0][0] = 1.0
    left = [0.0] * (p + 1)
    right = [0.0] * (p + 1)
    for j in range(1, p + 1):
        left[j] = t - U[i + 1 - j]
        right[j] = U[i + j] - t
        saved = 0.0
        for r in range(j):
            ndu[j][r] = right[r + 1] + left[j - r]
            temp = ndu[r][j - 1] / ndu[j][r]
            ndu[r][j] = saved + right[r + 1] * temp
            saved = left[j - r] * temp
        ndu[j][j] = saved
    ders = [[0.0] * (p + 1) for _ in range(n + 1)]
    for j in range(p + 1):
        ders[0][j] = ndu[j][p]
    a = [[0.0] * (p + 1) for _ in range(2)]
    for r in range(p + 1):
        s1, s2 = 0, 1
        a[0][0] = 1.0
        for k in range(1, n + 1):
            d = 0.0
            rk, pk = r - k, p - k
            if r >= k:
                a[s2][0] = a[s1][0] / ndu[pk + 1][rk]
                d = a[s2][0] * ndu[rk][pk]
            j1 = 1 if rk >= -1 else -rk
            j2 = k - 1 if r - 1 <= pk else p - r
            for j in range(j1, j2 + 1):
                a[s2][j] = (a[s1][j] - a[s1][j - 1]) / ndu[pk + 1][rk + j]
                d += a[s2][j] * ndu[rk + j][pk]
            if r <= pk:
                a[s2][k] = -a[s1][k - 1] / ndu[pk + 1][r]
                d += a[s2][k] * ndu[r][pk]
            ders[k][r] = d
            s1, s2 = s2, s1
    r = p
    for k in range(1, n + 1):
        for j in range(p + 1):
            ders[k][j] *= r
        r *= p - k
    return ders


def ref_curve_ders(deg, knots, pts, wts, t, nd=2):
    """Rational curve derivatives 0..nd (A3.2 on homogeneous points + A4.2)."""
    n = len(pts) - 1
    w = wts if wts is not None else [1.0] * len(pts)
    span = find_span(n, deg, t, knots)
    nd_eff = min(nd, deg)
    N = ders_basis(span, t, deg, nd_eff, knots)
    A = [[0.0, 0.0, 0.0] for _ in range(nd + 1)]
    W = [0.0] * (nd + 1)
    for k in range(nd_eff + 1):
        for j in range(deg + 1):
            idx = span - deg + j
            c = N[k][j] * w[idx]
            W[k] += c
            for d in range(3):
                A[k][d] += c * pts[idx][d]
    C = []
    for k in range(nd + 1):
        v = list(A[k])
        for i in range(1, k + 1):
            b = math.comb(k, i) * W[i]
            v = [v[d] - b * C[k - i][d] for d in range(3)]
        C.append([x / W[0] for x in v])
    return C


def ref_surface_ders(du_, dv_, ku, kv, pts, wts, u, v):
    """Rational surface derivatives up to order 2 (A3.6 homogeneous + A4.4)."""
    nu, nv = len(pts) - 1, len(pts[0]) - 1
    su = find_span(nu, du_, u, ku)
    sv = find_span(nv, dv_, v, kv)
    Nu = ders_basis(su, u, du_, min(2, du_), ku)
    Nv = ders_basis(sv, v, dv_, min(2, dv_), kv)
    while len(Nu) < 3:
        Nu.append([0.0] * (du_ + 1))
    while len(Nv) < 3:
        Nv.append([0.0] * (dv_ + 1))
    A = [[[0.0] * 3 for _ in range(3)] for _ in range(3)]
    W = [[0.0] * 3 for _ in range(3)]
    for k in range(3):
        for l in range(3 - k):
            for i in range(du_ + 1):
                for j in range(dv_ + 1):
                    ii, jj = su - du_ + i, sv - dv_ + j
                    wij = wts[ii][jj] if wts is not None else 1.0
                    c = Nu[k][i] * Nv[l][j] * wij
                    W[k][l] += c
                    for d in range(3):
                        A[k][l][d] += c * pts[ii][jj][d]
    S = [[None] * 3 for _ in range(3)]
    for k in range(3):
        for l in range(3 - k):
            v_ = list(A[k][l])
            for j in range(1, l + 1):
                b = math.comb(l, j) * W[0][j]
                v_ = [v_[d] - b * S[k][l - j][d] for d in range(3)]
            for i in range(1, k + 1):
                b = math.comb(k, i) * W[i][0]
                v_ = [v_[d] - b * S[k - i][l][d] for d in range(3)]
                v2 = [0.0, 0.0, 0.0]
                for j in range(1, l + 1):
                    b2 = math.comb(l, j) * W[i][j]
                    v2 = [v2[d] + b2 * S[k - i][l - j][d] for d in range(3)]
                v_ = [v_[d] - math.comb(k, i) * v2[d] for d in range(3)]
            S[k][l] = [x / W[0][0] for x in v_]
    return S


# ---------------------------------------------------------------------------
# OCC object construction
# ---------------------------------------------------------------------------


def make_occ_curve(c):
    ks, ms = compress(c["knots"])
    poles = arr1_pnt(c["points"])
    if c["weights"] is None:
        crv = Geom_BSplineCurve(poles, arr1_real(ks), arr1_int(ms), c["degree"], False)
    else:
        crv = Geom_BSplineCurve(
            poles, arr1_real(c["weights"]), arr1_real(ks), arr1_int(ms), c["degree"], False
        )
    assert crv.Degree() == c["degree"]
    assert to_list(crv.KnotSequence()) == c["knots"], "OCC changed the knot vector"
    assert crv.NbPoles() == len(c["points"])
    return crv


def make_occ_surface(s):
    ku, mu = compress(s["knots_u"])
    kv, mv = compress(s["knots_v"])
    nu, nv = len(s["points"]), len(s["points"][0])
    poles = Array2_gp_Pnt(1, nu, 1, nv)
    for i in range(nu):
        for j in range(nv):
            poles.SetValue(i + 1, j + 1, gp_Pnt(*s["points"][i][j]))
    args = [arr1_real(ku), arr1_real(kv), arr1_int(mu), arr1_int(mv), s["degree_u"], s["degree_v"]]
    if s["weights"] is None:
        srf = Geom_BSplineSurface(poles, *args)
    else:
        w = Array2_double(1, nu, 1, nv)
        for i in range(nu):
            for j in range(nv):
                w.SetValue(i + 1, j + 1, float(s["weights"][i][j]))
        srf = Geom_BSplineSurface(poles, w, *args)
    assert srf.UDegree() == s["degree_u"] and srf.VDegree() == s["degree_v"]
    assert srf.NbUPoles() == nu and srf.NbVPoles() == nv
    assert to_list(srf.UKnotSequence()) == s["knots_u"]
    assert to_list(srf.VKnotSequence()) == s["knots_v"]
    return srf


def occ_curve_d2(crv, t):
    p, v1, v2 = gp_Pnt(), gp_Vec(), gp_Vec()
    crv.D2(t, p, v1, v2)
    return vec(p), vec(v1), vec(v2)


def occ_surface_d2(srf, u, v):
    p, du, dv, duu, dvv, duv = gp_Pnt(), gp_Vec(), gp_Vec(), gp_Vec(), gp_Vec(), gp_Vec()
    # OCP signature: D2(U, V, P, D1U, D1V, D2U, D2V, D2UV)
    srf.D2(u, v, p, du, dv, duu, dvv, duv)
    return vec(p), vec(du), vec(dv), vec(duu), vec(duv), vec(dvv)


def bbox_size(points):
    return max(norm(p) for p in points)


# ---------------------------------------------------------------------------
# sampling parameters
# ---------------------------------------------------------------------------

# fixed fractions of the domain (irregular on purpose, no knot hits)
FRACTIONS = [0.0371, 0.1139, 0.2017, 0.2953, 0.3719, 0.4603, 0.5381, 0.6127,
             0.6871, 0.7733, 0.8459, 0.9281, 0.9713]


def curve_params(degree, knots, count=15):
    """Sample parameters: both ends, interior knots where the 2nd derivative
    is continuous (multiplicity <= degree - 2), points just beside knots where
    it is not, and irregular interior fractions up to `count` values."""
    a, b = knots[0], knots[-1]
    ks, ms = compress(knots)
    ts = {a, b}
    eps = 1e-7 * (b - a)
    for k, m in zip(ks[1:-1], ms[1:-1]):
        if m <= degree - 2:
            ts.add(k)
        else:  # derivatives jump here: sample on both sides instead
            ts.add(k - eps)
            ts.add(k + eps)
    for f in FRACTIONS:
        if len(ts) >= count:
            break
        t = a + f * (b - a)
        if all(abs(t - k) > 1e-6 * (b - a) for k in ks):
            ts.add(t)
    return sorted(ts)


def surface_params(degree, knots, count):
    return curve_params(degree, knots, count)


# ---------------------------------------------------------------------------
# curve definitions
# ---------------------------------------------------------------------------


def clamped(degree, interior, a=0.0, b=1.0):
    return [a] * (degree + 1) + list(interior) + [b] * (degree + 1)


def uniform_clamped(degree, ncp, a=0.0, b=1.0):
    nspans = ncp - degree
    interior = [a + (b - a) * i / nspans for i in range(1, nspans)]
    return clamped(degree, [r4(x) for x in interior], a, b)


def rand_points(rng, n, dims=3, spread=10.0):
    pts = []
    for i in range(n):
        x = i * spread / max(1, n - 1) + rng.uniform(-0.3, 0.3)
        y = rng.uniform(-3.0, 3.0)
        z = rng.uniform(-2.0, 2.0) if dims == 3 else 0.0
        pts.append([r4(x), r4(y), r4(z)])
    return pts


def rand_weights(rng, n):
    return [r4(rng.uniform(0.5, 2.0)) for _ in range(n)]


def curve_defs():
    rng = random.Random(20240611)
    C = []

    def add_curve(name, degree, knots, points, weights=None):
        assert len(knots) == len(points) + degree + 1, name
        C.append({"name": name, "degree": degree, "knots": [float(k) for k in knots],
                  "points": [[float(x) for x in p] for p in points],
                  "weights": None if weights is None else [float(w) for w in weights]})

    # --- degree 1
    add_curve("deg1_polyline_2d_uniform", 1, uniform_clamped(1, 5),
              [[0, 0, 0], [1, 2, 0], [3, 2.5, 0], [4, 0.5, 0], [6, 1, 0]])
    add_curve("deg1_nonuniform_3d_domain_2_7.5", 1, clamped(1, [2.5, 4.0, 4.25, 6.0], 2.0, 7.5),
              rand_points(rng, 6))
    add_curve("deg1_rational", 1, clamped(1, [0.3, 0.7]),
              rand_points(rng, 4), [1.0, 2.0, 0.5, 1.5])
    # --- degree 2
    add_curve("deg2_uniform", 2, uniform_clamped(2, 6), rand_points(rng, 6))
    circle = [[1, 0, 0], [1, 1, 0], [0, 1, 0], [-1, 1, 0], [-1, 0, 0],
              [-1, -1, 0], [0, -1, 0], [1, -1, 0], [1, 0, 0]]
    add_curve("deg2_full_circle_9pt", 2, clamped(2, [0.25, 0.25, 0.5, 0.5, 0.75, 0.75]),
              circle, [1.0, SQRT2_2, 1.0, SQRT2_2, 1.0, SQRT2_2, 1.0, SQRT2_2, 1.0])
    # full circle of radius 2 centred (1,-1,3), 3 arcs of 120 degrees (weights 1/2), domain [2, 7.5]
    r, cx, cy, cz = 2.0, 1.0, -1.0, 3.0
    tri = []
    for k in range(7):
        ang = k * math.pi / 3.0
        rad = r if k % 2 == 0 else 2.0 * r  # corner points of circumscribed triangle at 2r
        tri.append([cx + rad * math.cos(ang), cy + rad * math.sin(ang), cz])
    tri[-1] = list(tri[0])
    add_curve("deg2_full_circle_7pt_domain_2_7.5", 2,
              clamped(2, [2.0 + 5.5 / 3.0] * 2 + [2.0 + 11.0 / 3.0] * 2, 2.0, 7.5),
              tri, [1.0, 0.5, 1.0, 0.5, 1.0, 0.5, 1.0])
    add_curve("deg2_rational_random_double_knot", 2, clamped(2, [0.2, 0.45, 0.45, 0.8]),
              rand_points(rng, 7), rand_weights(rng, 7))
    add_curve("deg2_hyperbolic_arc_domain_10_110", 2, clamped(2, [], 10.0, 110.0),
              [[0, 0, 0], [5, 5, 1], [10, 0, 2]], [1.0, 3.0, 1.0])
    # --- degree 3
    add_curve("deg3_bezier", 3, clamped(3, []),
              [[0, 0, 0], [1, 3, 1], [4, 3, -1], [5, 0, 0.5]])
    add_curve("deg3_uniform", 3, uniform_clamped(3, 8), rand_points(rng, 8))
    add_curve("deg3_nonuniform_2d", 3, clamped(3, [0.05, 0.15, 0.5, 0.55, 0.9]),
              rand_points(rng, 9, dims=2))
    add_curve("deg3_double_knot_C1", 3, clamped(3, [0.3, 0.6, 0.6, 0.8]), rand_points(rng, 8))
    add_curve("deg3_triple_knot_C0_kink", 3, clamped(3, [0.25, 0.5, 0.5, 0.5, 0.75]),
              rand_points(rng, 9))
    add_curve("deg3_rational_domain_m1_3", 3, clamped(3, [-0.5, 0.25, 1.0, 2.2], -1.0, 3.0),
              rand_points(rng, 8), rand_weights(rng, 8))
    add_curve("deg3_rational_12pts_repeated", 3,
              clamped(3, [0.1, 0.2, 0.3, 0.3, 0.45, 0.6, 0.7, 0.7, 0.7]),
              rand_points(rng, 13), rand_weights(rng, 13))
    # --- degree 4
    add_curve("deg4_nonuniform", 4, clamped(4, [0.1, 0.35, 0.4, 0.85]), rand_points(rng, 9))
    add_curve("deg4_rational_double_knot", 4, clamped(4, [0.3, 0.5, 0.5, 0.7]),
              rand_points(rng, 9), rand_weights(rng, 9))
    add_curve("deg4_quadruple_knot_C0", 4, clamped(4, [0.4, 0.6, 0.6, 0.6, 0.6], 0.0, 2.0),
              rand_points(rng, 10))
    add_curve("deg4_rational_bezier", 4, clamped(4, [], -2.0, -0.5),
              rand_points(rng, 5), rand_weights(rng, 5))
    # --- degree 5
    add_curve("deg5_bezier", 5, clamped(5, []), rand_points(rng, 6))
    add_curve("deg5_nonuniform", 5, clamped(5, [0.2, 0.3, 0.65, 0.9]), rand_points(rng, 10))
    add_curve("deg5_rational_domain_2_7.5", 5, clamped(5, [3.0, 4.1, 5.5, 6.0], 2.0, 7.5),
              rand_points(rng, 10), rand_weights(rng, 10))
    add_curve("deg5_triple_knot_C2", 5, clamped(5, [0.3, 0.55, 0.55, 0.55, 0.8]),
              rand_points(rng, 11), rand_weights(rng, 11))
    add_curve("deg5_quintuple_knot_C0", 5, clamped(5, [0.25, 0.5, 0.5, 0.5, 0.5, 0.5]),
              rand_points(rng, 12))
    return C


def sample_curve(c):
    crv = make_occ_curve(c)
    size = bbox_size(c["points"])
    samples = []
    for t in curve_params(c["degree"], c["knots"]):
        p, d1, d2 = occ_curve_d2(crv, t)
        ref = ref_curve_ders(c["degree"], c["knots"], c["points"], c["weights"], t)
        for a, b in ((p, ref[0]), (d1, ref[1]), (d2, ref[2])):
            err = dist_rel(a, b, size)
            assert err < CHECK_TOL, (c["name"], t, a, b, err)
        samples.append({"t": t, "p": p, "d1": d1, "d2": d2})
    out = dict(c)
    out["samples"] = samples
    return out


# ---------------------------------------------------------------------------
# surface definitions
# ---------------------------------------------------------------------------


def grid_points(rng, nu, nv, lx=10.0, ly=8.0, bump=2.0):
    pts = []
    for i in range(nu):
        row = []
        for j in range(nv):
            x = lx * i / (nu - 1) + rng.uniform(-0.25, 0.25)
            y = ly * j / (nv - 1) + rng.uniform(-0.25, 0.25)
            z = rng.uniform(-bump, bump)
            row.append([r4(x), r4(y), r4(z)])
        pts.append(row)
    return pts


def grid_weights(rng, nu, nv):
    return [[r4(rng.uniform(0.5, 2.0)) for _ in range(nv)] for _ in range(nu)]


def surface_defs():
    rng = random.Random(977)
    S = []

    def add_surface(name, du, dv, ku, kv, pts, wts=None):
        assert len(ku) == len(pts) + du + 1, name
        assert len(kv) == len(pts[0]) + dv + 1, name
        S.append({"name": name, "degree_u": du, "degree_v": dv,
                  "knots_u": [float(k) for k in ku], "knots_v": [float(k) for k in kv],
                  "points": [[[float(x) for x in p] for p in row] for row in pts],
                  "weights": None if wts is None else [[float(w) for w in row] for row in wts]})

    add_surface("deg1x1_bilinear", 1, 1, clamped(1, []), clamped(1, []),
                [[[0, 0, 0], [0, 1, 0.5]], [[2, 0, 1], [2.5, 1.5, -0.5]]])
    add_surface("deg1x2_nonuniform", 1, 2, clamped(1, [0.4, 0.7]), clamped(2, [0.3]),
                grid_points(rng, 4, 4))
    # quarter cylinder, radius 3, axis z, height 5: u = circular arc (rational quadratic), v = line
    cyl_pts, cyl_w = [], []
    for (x, y), w in zip([(3, 0), (3, 3), (0, 3)], [1.0, SQRT2_2, 1.0]):
        cyl_pts.append([[x, y, 0.0], [x, y, 5.0]])
        cyl_w.append([w, w])
    add_surface("deg2x1_rational_quarter_cylinder", 2, 1, clamped(2, []), clamped(1, []),
                cyl_pts, cyl_w)
    # sphere octant radius 2: u = longitude arc 0..90 deg, v = latitude 0..90 deg
    arc = [((1.0, 0.0), 1.0), ((1.0, 1.0), SQRT2_2), ((0.0, 1.0), 1.0)]
    sph_pts, sph_w = [], []
    for (cu, su), wu in arc:
        row, wrow = [], []
        for (cv, sv), wv in arc:
            row.append([2.0 * cu * cv, 2.0 * su * cv, 2.0 * sv])
            wrow.append(wu * wv)
        sph_pts.append(row)
        sph_w.append(wrow)
    add_surface("deg2x2_rational_sphere_octant", 2, 2, clamped(2, []), clamped(2, []),
                sph_pts, sph_w)
    add_surface("deg2x2_rational_random_domain_2_7.5", 2, 2,
                clamped(2, [3.0, 5.0], 2.0, 7.5), clamped(2, [0.5], 0.0, 1.0),
                grid_points(rng, 5, 4), grid_weights(rng, 5, 4))
    add_surface("deg3x3_uniform", 3, 3, uniform_clamped(3, 6), uniform_clamped(3, 5),
                grid_points(rng, 6, 5))
    add_surface("deg3x3_rational_domains", 3, 3,
                clamped(3, [3.5, 5.0, 6.0], 2.0, 7.5), clamped(3, [-0.2, 0.4], -1.0, 1.0),
                grid_points(rng, 7, 6), grid_weights(rng, 7, 6))
    add_surface("deg3x2_repeated_knots", 3, 2,
                clamped(3, [0.3, 0.5, 0.5, 0.8]), clamped(2, [0.4, 0.4, 0.7]),
                grid_points(rng, 8, 6))
    add_surface("deg4x3_nonuniform", 4, 3, clamped(4, [0.15, 0.6]), clamped(3, [0.35, 0.5, 0.9]),
                grid_points(rng, 7, 7))
    add_surface("deg5x5_bezier", 5, 5, clamped(5, []), clamped(5, []), grid_points(rng, 6, 6))
    add_surface("deg5x2_rational", 5, 2, clamped(5, [0.4, 0.7]), clamped(2, [0.25, 0.6, 0.6]),
                grid_points(rng, 8, 6), grid_weights(rng, 8, 6))
    add_surface("deg2x4_rational", 2, 4, clamped(2, [0.5, 0.5], 0.0, 3.0), clamped(4, [0.45]),
                grid_points(rng, 5, 6), grid_weights(rng, 5, 6))
    add_surface("deg1x5_ruled", 1, 5, clamped(1, [0.6]), clamped(5, [0.5]),
                grid_points(rng, 3, 7))
    add_surface("deg4x4_rational_repeated", 4, 4,
                clamped(4, [0.3, 0.6, 0.6]), clamped(4, [0.5, 0.5, 0.5, 0.5]),
                grid_points(rng, 8, 9), grid_weights(rng, 8, 9))
    add_surface("deg3x5_domains", 3, 5, clamped(3, [12.0, 15.0], 10.0, 20.0),
                clamped(5, [0.7], 0.5, 1.25), grid_points(rng, 6, 7))
    add_surface("deg5x1_rational", 5, 1, clamped(5, [0.5]), clamped(1, [0.5]),
                grid_points(rng, 7, 3), grid_weights(rng, 7, 3))
    return S


def sample_surface(s):
    srf = make_occ_surface(s)
    size = max(bbox_size(row) for row in s["points"])
    us = surface_params(s["degree_u"], s["knots_u"], 6)
    vs = surface_params(s["degree_v"], s["knots_v"], 6)
    samples = []
    for u in us:
        for v in vs:
            p, du, dv, duu, duv, dvv = occ_surface_d2(srf, u, v)
            R = ref_surface_ders(s["degree_u"], s["degree_v"], s["knots_u"], s["knots_v"],
                                 s["points"], s["weights"], u, v)
            for a, b in ((p, R[0][0]), (du, R[1][0]), (dv, R[0][1]), (duu, R[2][0]),
                         (duv, R[1][1]), (dvv, R[0][2])):
                err = dist_rel(a, b, size)
                assert err < CHECK_TOL, (s["name"], u, v, a, b, err)
            samples.append({"u": u, "v": v, "p": p, "du": du, "dv": dv,
                            "duu": duu, "duv": duv, "dvv": dvv})
    out = dict(s)
    out["samples"] = samples
    return out


# ---------------------------------------------------------------------------
# interpolation
# ---------------------------------------------------------------------------


def params_chord(points, centripetal=False, normalise=True):
    d = [0.0]
    for a, b in zip(points, points[1:]):
        l = norm(sub(b, a))
        d.append(d[-1] + (math.sqrt(l) if centripetal else l))
    if not normalise:
        return d
    tot = d[-1]
    out = [x / tot for x in d]
    out[-1] = 1.0
    return out


def curve_object_from_occ(crv):
    weights = None
    if crv.IsRational():
        weights = [crv.Weight(i) for i in range(1, crv.NbPoles() + 1)]
    return {"degree": crv.Degree(), "knots": to_list(crv.KnotSequence()),
            "points": [vec(crv.Pole(i)) for i in range(1, crv.NbPoles() + 1)],
            "weights": weights}


def sample_curve_object(name, co, params):
    """Sample a curve-object (OCC evaluation, checked against the reference evaluator)."""
    crv = make_occ_curve(dict(co, name=name))
    size = bbox_size(co["points"])
    samples = []
    for t in params:
        p, d1, d2 = occ_curve_d2(crv, t)
        ref = ref_curve_ders(co["degree"], co["knots"], co["points"], co["weights"], t)
        for a, b in zip((p, d1, d2), ref):
            assert dist_rel(a, b, size) < CHECK_TOL, (name, t, a, b)
        samples.append({"t": t, "p": p, "d1": d1, "d2": d2})
    return samples


def occ_interpolate(points, params, t0=None, t1=None, scale_tangents=False):
    it = GeomAPI_Interpolate(harr1_pnt(points), harr1_real(params), False, 1e-9)
    if t0 is not None:
        it.Load(gp_Vec(*t0), gp_Vec(*t1), scale_tangents)
    it.Perform()
    assert it.IsDone()
    return it.Curve()


def lagrange_derivative(ts, pts, x):
    """Derivative at x of the Lagrange polynomial through (ts[i], pts[i])."""
    out = [0.0, 0.0, 0.0]
    for i, ti in enumerate(ts):
        li = 0.0
        for m, tm in enumerate(ts):
            if m == i:
                continue
            term = 1.0 / (ti - tm)
            for l, tl in enumerate(ts):
                if l != i and l != m:
                    term *= (x - tl) / (ti - tl)
            li += term
        out = add(out, scale(li, pts[i]))
    return out


def interpolation_defs():
    rng = random.Random(31337)
    cases = []
    pts6 = [[0.0, 0.0, 0.0], [1.0, 2.0, 0.5], [3.0, 3.0, 1.0], [5.0, 1.5, 0.0],
            [6.5, 2.5, -1.0], [8.0, 0.0, 0.0]]
    pts8 = rand_points(rng, 8)
    pts9_2d = [[0.0, 0.0, 0.0], [0.5, 1.8, 0.0], [1.0, 2.0, 0.0], [4.0, 2.2, 0.0],
               [4.5, 0.0, 0.0], [5.0, -2.0, 0.0], [7.5, -2.5, 0.0], [8.0, 0.0, 0.0],
               [10.0, 1.0, 0.0]]
    pts4 = [[0.0, 0.0, 0.0], [2.0, 1.0, 1.0], [4.0, -1.0, 2.0], [6.0, 0.5, 0.0]]
    cases.append(("chord_6pts_no_tangents", pts6, params_chord(pts6), None, None))
    cases.append(("chord_6pts_tangents", pts6, params_chord(pts6), [4.0, 10.0, 2.0], [6.0, -8.0, 0.0]))
    cases.append(("centripetal_8pts_no_tangents", pts8, params_chord(pts8, True), None, None))
    cases.append(("centripetal_8pts_tangents", pts8, params_chord(pts8, True),
                  [10.0, 3.0, -2.0], [5.0, 0.0, 4.0]))
    cases.append(("chord_unnormalised_9pts_2d_tangents", pts9_2d,
                  params_chord(pts9_2d, normalise=False), [0.3, 1.0, 0.0], [0.8, 0.6, 0.0]))
    cases.append(("centripetal_9pts_2d_no_tangents", pts9_2d, params_chord(pts9_2d, True),
                  None, None))
    cases.append(("chord_4pts_no_tangents", pts4, params_chord(pts4), None, None))
    cases.append(("chord_4pts_tangents", pts4, params_chord(pts4), [1.0, 5.0, 0.0], [3.0, 3.0, -6.0]))

    out = []
    for name, pts, params, t0, t1 in cases:
        crv = occ_interpolate(pts, params, t0, t1)
        co = curve_object_from_occ(crv)
        assert co["weights"] is None and co["degree"] == 3
        # interpolation conditions
        size = bbox_size(pts)
        for q, t in zip(pts, params):
            p, _, _ = occ_curve_d2(crv, t)
            assert dist_rel(p, q, size) < 1e-9, (name, t)
        if t0 is not None:
            # Load(..., Scale=False): the tangents are used as first derivatives unchanged
            _, d, _ = occ_curve_d2(crv, params[0])
            assert dist_rel(d, t0, norm(t0)) < 1e-9, (name, d, t0)
            _, d, _ = occ_curve_d2(crv, params[-1])
            assert dist_rel(d, t1, norm(t1)) < 1e-9, (name, d, t1)
            end_conditions = "given end tangents used unscaled as first derivatives (Load(..., Scale=False))"
        else:
            # OCC builds the missing end derivatives itself: derivative of the cubic
            # Lagrange polynomial through the first / last four (point, parameter) pairs
            _, d, _ = occ_curve_d2(crv, params[0])
            lag = lagrange_derivative(params[:4], pts[:4], params[0])
            assert dist_rel(d, lag, norm(lag)) < 1e-9, (name, d, lag)
            _, d, _ = occ_curve_d2(crv, params[-1])
            lag = lagrange_derivative(params[-4:], pts[-4:], params[-1])
            assert dist_rel(d, lag, norm(lag)) < 1e-9, (name, d, lag)
            end_conditions = ("end first derivatives = derivative of the cubic Lagrange polynomial "
                              "through the first / last 4 points at their parameters (OCC BuildTangents)")
        ts = sorted(set(params) | set(curve_params(3, co["knots"], 15)))
        out.append({"name": name, "points": pts, "parameters": params,
                    "start_tangent": t0, "end_tangent": t1, "degree": 3,
                    "end_conditions": end_conditions,
                    "knots": co["knots"], "control_points": co["points"],
                    "samples": sample_curve_object(name, co, ts)})
    return out


def interpolation_averaged_defs():
    rng = random.Random(4242)
    cases = [("geomdl_deg2_7pts", 2, rand_points(rng, 7)),
             ("geomdl_deg3_9pts", 3, rand_points(rng, 9)),
             ("geomdl_deg4_10pts", 4, rand_points(rng, 10))]
    out = []
    for name, deg, pts in cases:
        crv = fitting.interpolate_curve([tuple(p) for p in pts], deg)
        params = fitting.compute_params_curve([tuple(p) for p in pts], False)
        params = [float(x) for x in params]
        assert params[0] == 0.0 and params[-1] == 1.0
        co = {"degree": deg, "knots": [float(k) for k in crv.knotvector],
              "points": [[float(x) for x in p] for p in crv.ctrlpts], "weights": None}
        size = bbox_size(pts)
        for q, t in zip(pts, params):
            p = ref_curve_ders(deg, co["knots"], co["points"], None, t, 0)[0]
            assert dist_rel(p, q, size) < 1e-9, (name, t)
        ts = sorted(set(params) | set(curve_params(deg, co["knots"], 15)))
        out.append({"name": name, "points": pts, "parameters": params,
                    "start_tangent": None, "end_tangent": None, "degree": deg,
                    "knots": co["knots"], "control_points": co["points"],
                    "samples": sample_curve_object(name, co, ts)})
    return out


def check_scale_true_behaviour():
    """Document what Load(..., Scale=True) does; nothing is stored, we always use
    Scale=False.  OCC keeps each tangent's direction and rescales it so that its
    L1 norm (|x|+|y|+|z|) equals that of the derivative of the quadratic Lagrange
    polynomial through the FIRST three points -- for the final tangent too
    (evaluated at the last parameter), as long as only the two end tangents are
    given (ScaleTangents in GeomAPI_Interpolate.cxx).  Returns the two ratios."""
    pts = [[0.0, 0.0, 0.0], [1.0, 2.0, 0.5], [3.0, 3.0, 1.0], [5.0, 1.5, 0.0],
           [6.5, 2.5, -1.0], [8.0, 0.0, 0.0]]
    params = params_chord(pts)
    t0, t1 = [4.0, 10.0, 2.0], [6.0, -8.0, 0.0]
    crv = occ_interpolate(pts, params, t0, t1, scale_tangents=True)
    l1 = lambda v: sum(abs(x) for x in v)
    ratios = []
    for t, tan in ((params[0], t0), (params[-1], t1)):
        _, d, _ = occ_curve_d2(crv, t)
        ratio = l1(lagrange_derivative(params[:3], pts[:3], t)) / l1(tan)
        assert dist_rel(d, scale(ratio, tan), norm(d)) < 1e-12, (d, tan, ratio)
        ratios.append(ratio)
    return ratios


# ---------------------------------------------------------------------------
# Coons patches
# ---------------------------------------------------------------------------


def eval_curve_normalised(crv, co, s):
    a, b = co["knots"][0], co["knots"][-1]
    p = gp_Pnt()
    crv.D0(a + s * (b - a), p)
    return vec(p)


def classical_coons(cb, ct, cl, cr, u, v):
    """S = (1-v) B(u) + v T(u) + (1-u) L(v) + u R(v) - bilinear(corners)."""
    B, T, L, R = cb(u), ct(u), cl(v), cr(v)
    P00, P10, P01, P11 = cb(0.0), cb(1.0), ct(0.0), ct(1.0)
    out = []
    for d in range(3):
        out.append((1 - v) * B[d] + v * T[d] + (1 - u) * L[d] + u * R[d]
                   - ((1 - u) * (1 - v) * P00[d] + u * (1 - v) * P10[d]
                      + (1 - u) * v * P01[d] + u * v * P11[d]))
    return out


def hermite_coons(cb, ct, cl, cr, u, v):
    """Same as classical_coons with the cubic blends F(t) = 1 - 3t^2 + 2t^3,
    G(t) = 3t^2 - 2t^3 instead of (1 - t, t) -- what GeomFill_Coons uses."""
    F = lambda t: 1.0 - 3.0 * t * t + 2.0 * t ** 3
    G = lambda t: 3.0 * t * t - 2.0 * t ** 3
    B, T, L, R = cb(u), ct(u), cl(v), cr(v)
    P00, P10, P01, P11 = cb(0.0), cb(1.0), ct(0.0), ct(1.0)
    return [F(v) * B[d] + G(v) * T[d] + F(u) * L[d] + G(u) * R[d]
            - (F(u) * F(v) * P00[d] + G(u) * F(v) * P10[d] + F(u) * G(v) * P01[d]
               + G(u) * G(v) * P11[d]) for d in range(3)]


def coons_defs():
    """Each case: bottom(u) from P00 to P10, top(u) from P01 to P11,
    left(v) from P00 to P01, right(v) from P10 to P11; all on [0, 1]."""
    cases = []
    # case 1: planar-ish square with bulging sides, degrees 2/3 vs 3/2
    P00, P10, P01, P11 = [0.0, 0.0, 0.0], [10.0, 0.0, 0.0], [0.0, 8.0, 0.0], [10.0, 8.0, 1.0]
    cases.append(("coons_square_deg2_3", {
        "bottom": {"degree": 2, "knots": clamped(2, []),
                   "points": [P00, [5.0, -2.0, 1.0], P10], "weights": None},
        "top": {"degree": 3, "knots": clamped(3, [0.4]),
                "points": [P01, [2.0, 9.0, 0.5], [5.0, 10.0, 2.0], [8.0, 9.0, 1.0], P11], "weights": None},
        "left": {"degree": 3, "knots": clamped(3, []),
                 "points": [P00, [-1.0, 3.0, 1.0], [-1.0, 5.0, -1.0], P01], "weights": None},
        "right": {"degree": 2, "knots": clamped(2, [0.3, 0.7]),
                  "points": [P10, [11.0, 2.0, 0.0], [10.5, 5.0, 2.0], [11.5, 7.0, 1.0], P11], "weights": None},
    }))
    # case 2: twisted, non-uniform knots and repeated knot, degrees 1..4
    Q00, Q10, Q01, Q11 = [0.0, 0.0, 0.0], [6.0, 1.0, 2.0], [-1.0, 5.0, 1.0], [5.0, 6.0, -2.0]
    cases.append(("coons_twisted_deg1_4", {
        "bottom": {"degree": 1, "knots": clamped(1, [0.35]),
                   "points": [Q00, [3.0, -1.0, 1.5], Q10], "weights": None},
        "top": {"degree": 4, "knots": clamped(4, [0.25, 0.6, 0.6]),
                "points": [Q01, [0.0, 6.0, 0.0], [1.5, 7.0, 1.0], [2.5, 5.5, -1.0],
                           [3.5, 6.5, -0.5], [4.2, 6.0, -1.0], [4.5, 7.0, -1.5], [5.0, 6.0, -2.0]], "weights": None},
        "left": {"degree": 3, "knots": clamped(3, [0.2, 0.7]),
                 "points": [Q00, [-1.0, 1.0, 0.5], [0.5, 2.5, 2.0], [-2.0, 4.0, 1.5], [-1.5, 4.5, 0.5], Q01],
                 "weights": None},
        "right": {"degree": 2, "knots": clamped(2, [0.5, 0.5]),
                  "points": [Q10, [7.0, 2.0, 1.0], [6.5, 3.5, 0.0], [5.0, 5.0, -1.0], Q11], "weights": None},
    }))
    # case 3: saddle, degree 5 opposite degree 2, cubic sides with several knots
    R00, R10, R01, R11 = [0.0, 0.0, 1.0], [4.0, 0.0, -1.0], [0.0, 4.0, -1.0], [4.0, 4.0, 1.0]
    cases.append(("coons_saddle_deg5_2_3", {
        "bottom": {"degree": 5, "knots": clamped(5, []),
                   "points": [R00, [0.8, -0.5, 0.8], [1.6, 0.3, 0.2], [2.4, -0.3, -0.2],
                              [3.2, 0.5, -0.8], R10], "weights": None},
        "top": {"degree": 2, "knots": clamped(2, [0.6]),
                "points": [R01, [1.5, 4.8, -0.5], [3.0, 4.4, 0.5], R11], "weights": None},
        "left": {"degree": 3, "knots": clamped(3, [0.3, 0.5, 0.8]),
                 "points": [R00, [-0.5, 0.6, 1.0], [0.3, 1.5, 0.5], [-0.4, 2.5, 0.0],
                            [0.4, 3.4, -0.5], [-0.3, 3.8, -0.8], R01], "weights": None},
        "right": {"degree": 3, "knots": clamped(3, [0.5]),
                  "points": [R10, [4.6, 1.0, -0.5], [3.6, 2.0, 0.0], [4.5, 3.0, 0.5], R11],
                  "weights": None},
    }))
    # case 4: Bezier boundaries only (degrees 3/2 and 3/1).  Here OCC's result is
    # exactly the cubic-Hermite-blended Coons patch (checked), still not the classical one.
    S00, S10, S01, S11 = [0.0, 0.0, 0.0], [3.0, 0.0, 0.0], [0.0, 3.0, 0.0], [3.0, 3.0, 1.0]
    cases.append(("coons_bezier_deg3_2_3_1", {
        "bottom": {"degree": 3, "knots": clamped(3, []),
                   "points": [S00, [1.0, -1.0, 1.0], [2.0, 1.0, 0.0], S10], "weights": None},
        "top": {"degree": 2, "knots": clamped(2, []),
                "points": [S01, [1.5, 4.0, 1.0], S11], "weights": None},
        "left": {"degree": 3, "knots": clamped(3, []),
                 "points": [S00, [-1.0, 1.0, 1.0], [0.5, 2.0, 0.0], S01], "weights": None},
        "right": {"degree": 1, "knots": clamped(1, []),
                  "points": [S10, S11], "weights": None},
    }))
    for _, b in cases:
        for c in b.values():
            c["knots"] = [float(k) for k in c["knots"]]
            c["points"] = [[float(x) for x in p] for p in c["points"]]
    return cases


def coons_build(name, b):
    occ = {k: make_occ_curve(dict(v, name=name + "_" + k)) for k, v in b.items()}
    cb = lambda s: eval_curve_normalised(occ["bottom"], b["bottom"], s)
    ct = lambda s: eval_curve_normalised(occ["top"], b["top"], s)
    cl = lambda s: eval_curve_normalised(occ["left"], b["left"], s)
    cr = lambda s: eval_curve_normalised(occ["right"], b["right"], s)
    # GeomFill_BSplineCurves wants a closed loop C1 -> C2 -> C3 -> C4 (it reverses
    # curves itself if needed); we pass bottom, right, top, left and find out
    # from the result which boundary became which iso-line.
    fill = GeomFill_BSplineCurves(occ["bottom"], occ["right"], occ["top"], occ["left"],
                                  GeomFill_FillingStyle.GeomFill_CoonsStyle)
    srf = fill.Surface()
    return srf, (cb, ct, cl, cr)


def coons_orientation(srf, fns):
    """Return a function (u, v) -> (U, V) mapping our convention to OCC's
    parameters, found by matching corners and boundaries."""
    cb, ct, cl, cr = fns
    u0, u1, v0, v1 = srf.Bounds()
    size = max(norm(cb(0.0)), norm(cb(1.0)), norm(ct(0.0)), norm(ct(1.0)), 1.0)
    candidates = []
    for swap in (False, True):
        for fu in (False, True):
            for fv in (False, True):
                def m(u, v, swap=swap, fu=fu, fv=fv):
                    a, b = (v, u) if swap else (u, v)
                    a = 1 - a if fu else a
                    b = 1 - b if fv else b
                    return u0 + a * (u1 - u0), v0 + b * (v1 - v0)
                candidates.append(((swap, fu, fv), m))
    for key, m in candidates:
        ok = True
        for s in (0.0, 0.137, 0.5, 0.81, 1.0):
            for (u, v), q in (((s, 0.0), cb(s)), ((s, 1.0), ct(s)), ((0.0, s), cl(s)),
                              ((1.0, s), cr(s))):
                p = gp_Pnt()
                srf.D0(*m(u, v), p)
                if dist_rel(vec(p), q, size) > 1e-9:
                    ok = False
        if ok:
            return key, m, (u0, u1, v0, v1)
    raise AssertionError("no orientation of the OCC Coons patch matches the boundaries")


COONS_UV = [0.0, 0.1, 0.25, 0.37, 0.5, 0.63, 0.8, 0.93, 1.0]


def coons_section(report):
    out = []
    for name, b in coons_defs():
        srf, fns = coons_build(name, b)
        key, m, bounds = coons_orientation(srf, fns)
        maxdev = 0.0
        maxdev_hermite = 0.0
        samples = []
        size = max(bbox_size(c["points"]) for c in b.values())
        for u in COONS_UV:
            for v in COONS_UV:
                classical = classical_coons(*fns, u, v)
                p = gp_Pnt()
                srf.D0(*m(u, v), p)
                maxdev = max(maxdev, dist_rel(vec(p), classical, size))
                maxdev_hermite = max(maxdev_hermite,
                                     dist_rel(vec(p), hermite_coons(*fns, u, v), size))
                samples.append({"u": u, "v": v, "p": classical, "p_occ": vec(p)})
        equal = maxdev < 1e-9
        # orientation: we pass (bottom, right, top, left); OCC's U runs along bottom
        assert key == (False, False, False) and bounds == (0.0, 1.0, 0.0, 1.0), (name, key, bounds)
        if all(len(c["knots"]) == 2 * (c["degree"] + 1) for c in b.values()):
            assert maxdev_hermite < 1e-12, (name, maxdev_hermite)
        report.append((name, "max rel dev OCC vs classical", maxdev,
                       "vs cubic-hermite", maxdev_hermite, srf.UDegree(), srf.VDegree()))
        out.append({"name": name,
                    "source": ("p: occ_geomfill_coons (equals classical formula)" if equal else
                               "p: classical bilinearly blended Coons formula evaluated with the OCC "
                               "boundary curves; p_occ: GeomFill_BSplineCurves(CoonsStyle) result, "
                               "which is NOT the classical formula"),
                    "boundaries": {k: b[k] for k in ("bottom", "top", "left", "right")},
                    "samples": samples})
    return out


# ---------------------------------------------------------------------------
# surfaces of revolution
# ---------------------------------------------------------------------------


def rotate(p, axis_point, axis_dir, ang):
    """Rodrigues rotation of p about the axis (right-hand rule, counter-clockwise
    when looking against axis_dir)."""
    k = scale(1.0 / norm(axis_dir), axis_dir)
    x = sub(p, axis_point)
    c, s = math.cos(ang), math.sin(ang)
    kx = [k[1] * x[2] - k[2] * x[1], k[2] * x[0] - k[0] * x[2], k[0] * x[1] - k[1] * x[0]]
    kd = sum(a * b for a, b in zip(k, x))
    r = [x[i] * c + kx[i] * s + k[i] * kd * (1 - c) for i in range(3)]
    return add(r, axis_point)


def revolution_section():
    cases = []
    # non-rational cubic profile in the xz-plane, revolved about the z axis, full turn
    cases.append(("rev_cubic_profile_z_axis_full", {
        "degree": 3, "knots": [float(k) for k in clamped(3, [0.4, 0.7])],
        "points": [[1.0, 0.0, 0.0], [2.0, 0.0, 0.5], [2.5, 0.0, 1.5], [1.5, 0.0, 2.5],
                   [1.0, 0.0, 3.0], [1.2, 0.0, 4.0]], "weights": None},
        [0.0, 0.0, 0.0], [0.0, 0.0, 1.0], 2.0 * math.pi))
    # rational quadratic profile (quarter circle + line), tilted axis, partial angle 100 deg
    cases.append(("rev_rational_profile_tilted_axis_partial", {
        "degree": 2, "knots": [float(k) for k in clamped(2, [1.0, 1.0], 0.0, 2.0)],
        "points": [[3.0, 0.0, 0.0], [3.0, 1.0, 0.0], [2.0, 1.0, 0.0], [1.0, 1.0, 0.5],
                   [0.5, 2.0, 1.0]], "weights": [1.0, SQRT2_2, 1.0, 1.3, 1.0]},
        [0.5, -0.5, 0.0], [1.0, 2.0, 2.0], math.radians(100.0)))
    # random rational quartic profile, x axis, 270 deg
    rng = random.Random(7)
    prof = [[r4(i * 1.5), r4(rng.uniform(1.0, 3.0)), r4(rng.uniform(-1.0, 1.0))] for i in range(6)]
    cases.append(("rev_rational_quartic_x_axis_270deg", {
        "degree": 4, "knots": [float(k) for k in clamped(4, [1.8], 1.0, 3.0)],
        "points": prof, "weights": rand_weights(rng, 6)},
        [0.0, 0.0, 0.0], [1.0, 0.0, 0.0], 1.5 * math.pi))
    out = []
    for name, prof, ap, ad, ang in cases:
        crv = make_occ_curve(dict(prof, name=name))
        rev = Geom_SurfaceOfRevolution(crv, gp_Ax1(gp_Pnt(*ap), gp_Dir(*ad)))
        u0, u1, v0, v1 = rev.Bounds()
        assert u0 == 0.0 and abs(u1 - 2.0 * math.pi) < 1e-15
        assert (v0, v1) == (prof["knots"][0], prof["knots"][-1])
        size = bbox_size(prof["points"])
        us = [ang * f for f in (0.0, 0.1, 0.3, 0.45, 0.6, 0.85, 1.0)]
        vs = curve_params(prof["degree"], prof["knots"], 7)
        samples = []
        for u in us:
            for v in vs:
                p, du, dv = gp_Pnt(), gp_Vec(), gp_Vec()
                rev.D1(u, v, p, du, dv)
                # check: S(u, v) = Rot(axis, u) C(v)
                cp, cd, _ = occ_curve_d2(crv, v)
                assert dist_rel(vec(p), rotate(cp, ap, ad, u), size) < CHECK_TOL
                k = scale(1.0 / norm(ad), ad)
                r = sub(vec(p), ap)
                dcross = [k[1] * r[2] - k[2] * r[1], k[2] * r[0] - k[0] * r[2], k[0] * r[1] - k[1] * r[0]]
                assert dist_rel(vec(du), dcross, size) < CHECK_TOL
                assert dist_rel(vec(dv), sub(rotate(add(cd, ap), ap, ad, u), ap), size) < CHECK_TOL
                samples.append({"u": u, "v": v, "p": vec(p), "du": vec(du), "dv": vec(dv)})
        out.append({"name": name, "profile": prof, "axis_point": ap, "axis_dir": ad,
                    "angle_rad": ang, "samples": samples})
    return out


# ---------------------------------------------------------------------------
# output
# ---------------------------------------------------------------------------


def is_scalar(x):
    return x is None or isinstance(x, (int, float, str, bool))


def is_inline(x):
    if is_scalar(x):
        return True
    if isinstance(x, list):
        return all(is_scalar(e) for e in x)
    if isinstance(x, dict):
        return all(is_scalar(e) or (isinstance(e, list) and all(is_scalar(f) for f in e))
                   for e in x.values())
    return False


def emit(x, ind=0):
    if is_inline(x):
        return json.dumps(x, separators=(", ", ": "), allow_nan=False)
    pad = "  " * (ind + 1)
    if isinstance(x, list):
        return "[\n" + ",\n".join(pad + emit(e, ind + 1) for e in x) + "\n" + "  " * ind + "]"
    return ("{\n" + ",\n".join(pad + json.dumps(k) + ": " + emit(v, ind + 1) for k, v in x.items())
            + "\n" + "  " * ind + "}")


def main():
    verbose = "--verbose" in sys.argv
    generator = ("tests/reference/occ_reference.py; cadquery-ocp %s (OpenCascade %s); geomdl %s"
                 % (metadata.version("cadquery-ocp"), ".".join(metadata.version("cadquery-ocp").split(".")[:3]),
                    metadata.version("geomdl")))
    coons_report = []
    scale_ratios = check_scale_true_behaviour()
    data = {
        "generator": generator,
        "curves": [sample_curve(c) for c in curve_defs()],
        "surfaces": [sample_surface(s) for s in surface_defs()],
        "interpolations": interpolation_defs(),
        "interpolations_averaged": interpolation_averaged_defs(),
        "coons": coons_section(coons_report),
        "revolutions": revolution_section(),
    }
    text = emit(data) + "\n"
    if verbose:
        for r in coons_report:
            print("coons", r, file=sys.stderr)
        print("Load(Scale=True) scale ratios at ends:", scale_ratios, file=sys.stderr)
        for k in ("curves", "surfaces", "interpolations", "interpolations_averaged", "coons", "revolutions"):
            print(k, len(data[k]), sum(len(e["samples"]) for e in data[k]), file=sys.stderr)
    if "--stdout" in sys.argv:
        sys.stdout.write(text)
    else:
        os.makedirs(os.path.dirname(OUT), exist_ok=True)
        with open(OUT, "w", encoding="utf-8", newline="\n") as f:
            f.write(text)
        print("wrote %s (%d bytes)" % (OUT, len(text.encode("utf-8"))))


if __name__ == "__main__":
    main()
