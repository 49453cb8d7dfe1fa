#!/usr/bin/env python3
"""Fillets by OpenCascade for the rolling-ball round's exact cases (issue 16: "the same
sharp geometry built as a B-rep and filleted by OpenCascade (BRepFilletAPI_MakeFillet
via cadquery-ocp), the sampled distance between OpenCascade's fillet face and dieface's
rounding surface, reference data committed with the script that writes it").

Usage (from the crate root):

    pip install -r tests/reference/requirements.txt
    python3 tests/reference/fillet_reference.py            # rewrites tests/data/fillet_reference.json
    python3 tests/reference/fillet_reference.py --stdout   # prints it instead

The sharp geometry is built from the numbers of `tests/mesh_rounding.rs`, not from
dieface's output, each as a solid whose edge is the concave corner the ball rolls in:

* `fold_90` and `fold_120`: a plate 100 mm long (along x) folded along the x axis: the
  flat 40 mm on y < 0 at z = 0 and the leg 40 mm turned up from it by 90 and 60 deg
  (the legs 90 and 120 deg apart), both 5 mm thick on the side away from the corner:
  the L-section extruded 100 mm. The edge at y = z = 0 is filleted at R 5 mm.
* `boss`: a boss of radius 20 mm standing 30 mm on a disc plate reaching 30 mm round it
  (radius 50 mm, 5 mm thick under z = 0): the circular edge at the boss's foot is
  filleted at R 4 mm.

For each, OpenCascade's fillet face (the face the fillet made: a cylinder for the folds,
a torus for the boss) is sampled on a grid over its (u, v) bounds; the Rust test
(`tests/mesh_rounding.rs`, `the_round_matches_opencascades_fillet`) measures each
sample's distance to dieface's rounding surface of the same edge, made from the
tessellated input. The samples are rounded to 1e-9 mm so the file is the same on every
platform; two runs give byte-identical files.
"""

import json
import math
import sys
from importlib import metadata

from OCP.BRepAdaptor import BRepAdaptor_Curve, BRepAdaptor_Surface
from OCP.BRepAlgoAPI import BRepAlgoAPI_Fuse
from OCP.BRepBuilderAPI import BRepBuilderAPI_MakeFace, BRepBuilderAPI_MakePolygon
from OCP.BRepCheck import BRepCheck_Analyzer
from OCP.BRepFilletAPI import BRepFilletAPI_MakeFillet
from OCP.BRepPrimAPI import BRepPrimAPI_MakeCylinder, BRepPrimAPI_MakePrism
from OCP.BRepTools import BRepTools
from OCP.GeomAbs import GeomAbs_Cylinder, GeomAbs_Torus
from OCP.TopAbs import TopAbs_EDGE, TopAbs_FACE
from OCP.TopExp import TopExp_Explorer
from OCP.TopoDS import TopoDS
from OCP.gp import gp_Ax2, gp_Dir, gp_Pnt, gp_Vec

OUT = "tests/data/fillet_reference.json"

# Samples across the fillet (from one contact line to the other) and along it.
ACROSS, ALONG = 9, 21


def edges(shape):
    """Each edge of `shape` once (the explorer meets an edge once per face it bounds)."""
    seen = []
    explorer = TopExp_Explorer(shape, TopAbs_EDGE)
    while explorer.More():
        edge = TopoDS.Edge(explorer.Current())
        if not any(edge.IsSame(e) for e in seen):
            seen.append(edge)
            yield edge
        explorer.Next()


def faces(shape):
    explorer = TopExp_Explorer(shape, TopAbs_FACE)
    while explorer.More():
        yield TopoDS.Face(explorer.Current())
        explorer.Next()


def edge_ends(edge):
    curve = BRepAdaptor_Curve(edge)
    first, last = curve.FirstParameter(), curve.LastParameter()
    return curve.Value(first), curve.Value(last), curve.Value(0.5 * (first + last))


def fillet(solid, pick, radius, surface_type):
    """The solid with its edge `pick(edge)` chooses filleted at `radius`; the fillet
    face's samples (a grid over its (u, v) bounds) and what was made."""
    maker = BRepFilletAPI_MakeFillet(solid)
    # The edge, whole or in pieces (a circle may come in two, split at its seam).
    chosen = [e for e in edges(solid) if pick(e)]
    assert chosen, "no edge to fillet"
    for e in chosen:
        maker.Add(radius, e)
    maker.Build()
    assert maker.IsDone(), "OpenCascade's fillet failed"
    result = maker.Shape()
    assert BRepCheck_Analyzer(result).IsValid(), "OpenCascade's filleted solid is invalid"
    made = [f for f in faces(result) if BRepAdaptor_Surface(f).GetType() == surface_type]
    assert made, "no fillet face"
    # Each fillet face sampled on a grid over its (u, v) bounds (the grid covers the
    # fillet across and along whichever way its parameters run).
    samples = []
    for face in made:
        surface = BRepAdaptor_Surface(face)
        u0, u1, v0, v1 = BRepTools.UVBounds_s(face)
        for i in range(ALONG):
            for j in range(ACROSS):
                a = u0 + (u1 - u0) * i / (ALONG - 1)
                b = v0 + (v1 - v0) * j / (ACROSS - 1)
                p = surface.Value(a, b)
                samples.append([round(p.X(), 9), round(p.Y(), 9), round(p.Z(), 9)])
    return samples, len(chosen), len(made)


def fold(turn_deg, radius=5.0, length=100.0, leg=40.0, thick=5.0):
    turn = math.radians(turn_deg)
    up = (math.cos(turn), math.sin(turn))  # the leg's direction in (y, z)
    away = (math.sin(turn), -math.cos(turn))  # its normal, away from the corner
    # The outer corner: the flat's underside z = -thick meets the leg's outer line.
    s = (-thick - thick * away[1]) / up[1]
    outer = (thick * away[0] + s * up[0], -thick)
    section = [
        (-leg, 0.0),
        (0.0, 0.0),
        (leg * up[0], leg * up[1]),
        (leg * up[0] + thick * away[0], leg * up[1] + thick * away[1]),
        outer,
        (-leg, -thick),
    ]
    polygon = BRepBuilderAPI_MakePolygon()
    for y, z in section:
        polygon.Add(gp_Pnt(0.0, y, z))
    polygon.Close()
    face = BRepBuilderAPI_MakeFace(polygon.Wire()).Face()
    solid = BRepPrimAPI_MakePrism(face, gp_Vec(length, 0.0, 0.0)).Shape()

    def corner(edge):
        a, b, mid = edge_ends(edge)
        return all(abs(p.Y()) < 1e-9 and abs(p.Z()) < 1e-9 for p in (a, b, mid))

    samples, edges_filleted, fillet_faces = fillet(solid, corner, radius, GeomAbs_Cylinder)
    return {
        "turn_deg": turn_deg,
        "radius": radius,
        "edges": edges_filleted,
        "faces": fillet_faces,
        "samples": samples,
    }


def boss(a=20.0, height=30.0, reach=30.0, radius=4.0, thick=5.0):
    axis = gp_Ax2(gp_Pnt(0.0, 0.0, -thick), gp_Dir(0.0, 0.0, 1.0))
    plate = BRepPrimAPI_MakeCylinder(axis, a + reach, thick).Shape()
    column = BRepPrimAPI_MakeCylinder(axis, a, thick + height).Shape()
    fuse = BRepAlgoAPI_Fuse(plate, column)
    fuse.SimplifyResult()
    solid = fuse.Shape()

    def foot(edge):
        p, q, mid = edge_ends(edge)
        return all(
            abs(r.Z()) < 1e-9 and abs(math.hypot(r.X(), r.Y()) - a) < 1e-9 for r in (p, q, mid)
        )

    samples, edges_filleted, fillet_faces = fillet(solid, foot, radius, GeomAbs_Torus)
    return {
        "boss_radius": a,
        "radius": radius,
        "edges": edges_filleted,
        "faces": fillet_faces,
        "samples": samples,
    }


def main():
    result = {
        "ocp": metadata.version("cadquery-ocp"),
        "cases": {
            "fold_90": fold(90.0),
            "fold_120": fold(60.0),
            "boss": boss(),
        },
    }
    text = json.dumps(result, indent=1) + "\n"
    if "--stdout" in sys.argv:
        sys.stdout.write(text)
    else:
        with open(OUT, "w") as f:
            f.write(text)
        print(f"wrote {OUT}")


if __name__ == "__main__":
    main()
