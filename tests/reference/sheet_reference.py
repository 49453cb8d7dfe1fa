#!/usr/bin/env python3
"""Thickens the sheet examples with OpenCascade and compares the solids with
dieface's (issue 15: "the same part thickened by OpenCascade ... reference volumes and
a sampled distance between the two solids committed as reference data").

Usage (from the crate root):

    pip install -r tests/reference/requirements.txt
    python3 tests/reference/sheet_reference.py            # rewrites tests/data/sheet_reference.json
    python3 tests/reference/sheet_reference.py --stdout   # prints it instead

OpenCascade's parts are built from the examples' numbers, not from dieface's output,
as exact lines and circular arcs sewn into one shell:

* the bracket: the plate (120 x 70 mm, 8 mm corner fillets on the left, a 12 mm bolt
  hole and a 30 x 8 mm slot) and the 30 mm flange square to it along the right edge;
* the hood reinforcement (`examples/hood_reinforcement`, a part laid on a curved skin):
  the skin as the same bicubic B-spline, the plate as the skin trimmed by the outline
  seen from above (each line and arc's points found on the skin by OpenCascade's own
  line-surface intersection, `GeomAPI_IntCS`, and joined by a parameter-space curve),
  the bolt holes, the slot and the rib's foot cut from it, the rib's top on the skin's
  exact offset (`Geom_OffsetSurface`) and its walls ruled between foot and top. Its
  solid is compared without the rear flange: OpenCascade's offset fails on the inside
  of that curved fold (`BRepOffset_MakeOffset` gives an invalid shape there, either
  way round); the flange is checked on its own, each of dieface's vertices on the
  flange's sides against OpenCascade's exact offsets of the ruled surface along the
  skin's normals (`hood_flange`), with the whole part's mid-surface area. That solid
  is thickened half the gauge each way from the mid-surface (one-sided
  `BRepOffset_MakeOffset`, then `BRepAlgoAPI_Fuse`: the shift-then-thicken below
  fails on B-spline faces with `BRepOffset_C0Geometry`);
* the tray: the 160 x 100 mm floor with 15 mm corner radii, a 10 mm drain hole and a
  pad 80 x 40 mm lifted 3 mm on walls drafted 30 deg, and a wall 25 mm long all round
  leaning out 10 deg: planes along the sides and exact cones round the corners, where
  dieface has planar strips on the fillets' chords joined on their mitre lines;
* the reinforcement (`examples/reinforcement`) without its 2 mm tab, its rib and its
  rounded back corners (`trimmed_reinforcement` says why): its holes, the front
  flange and the step-down bend on 3 mm radii, the back flange at 60 deg and the lip
  turned in on it. Its mid-surface is dieface's own (the triangles of `reinforcement/mid`
  made OpenCascade faces, sewn and merged where coplanar), so this part checks the
  thickening alone: OpenCascade's offsets, intersections and junctions against
  dieface's on the same sheets.

* the pan (`examples/pan`): four walls at 80 deg closed at the corners and a level brim
  joined all round the rim, four sheets at each rim corner. Its mid-surface is
  dieface's own too, so OpenCascade's intersection joins decide where the four offset
  sides meet at each rim corner.

Each mid-surface is offset by half the gauge to one
side (`BRepOffsetAPI_MakeOffsetShape`, intersection joins) and thickened by the whole
gauge back across it (`BRepOffset_MakeOffset` with thickening on: the algorithm under
`BRepOffsetAPI_MakeThickSolid`), so the solid's mid-surfaces are the sheets, as
dieface's junction type 1 makes them. (Offsetting half each way and adding the halves
gives invalid shapes in OCCT 7.8; one-sided thickening from the shifted shell does not.)

dieface's solid is read from `dieface build examples/NAME/NAME.die -o X.obj`
(millimetres), the `NAME/solid` object. Recorded per part:

* `occ`: the solid's volume (`BRepGProp.VolumeProperties`, relative accuracy 1e-9),
  the mid-surface's area, the length of its curved edges (the arcs dieface follows by
  chords), and `BRepCheck_Analyzer(solid).IsValid()`;
* `dieface`: the volume of its closed triangle mesh (divergence theorem) and its
  vertex and triangle counts;
* `distance`: the largest distance from a dieface vertex to OpenCascade's solid
  (`BRepExtrema_DistShapeShape`, exact geometry), and from points sampled on
  OpenCascade's faces (the nodes of a 0.002 mm `BRepMesh` tessellation and its
  triangles' centroids) to dieface's mesh (exact point-to-triangle distance);
* `tolerance`: the outline tolerance dieface follows arcs with (0.05 mm).

Floats are rounded to 12 significant digits, so reruns on the same geometry give the
same file. `tests/sheet_reference.rs` checks the committed result against what dieface
computes now.
"""

import atexit
import json
import math
import os
import shutil
import subprocess
import sys
import tempfile
from importlib import metadata

import numpy as np
from OCP.BRep import BRep_Tool
from OCP.BRepBuilderAPI import (
    BRepBuilderAPI_MakeEdge,
    BRepBuilderAPI_MakeFace,
    BRepBuilderAPI_MakeVertex,
    BRepBuilderAPI_MakeWire,
    BRepBuilderAPI_Sewing,
)
from OCP.BRepCheck import BRepCheck_Analyzer
from OCP.BRepExtrema import BRepExtrema_DistShapeShape
from OCP.BRepGProp import BRepGProp
from OCP.BRepMesh import BRepMesh_IncrementalMesh
from OCP.BRepOffset import BRepOffset_MakeOffset, BRepOffset_Skin
from OCP.BRepOffsetAPI import BRepOffsetAPI_MakeOffsetShape
from OCP.BRepPrimAPI import BRepPrimAPI_MakePrism
from OCP.GC import GC_MakeArcOfCircle
from OCP.GeomAbs import GeomAbs_Intersection
from OCP.GProp import GProp_GProps
from OCP.Message import Message_ProgressRange
from OCP.TopAbs import TopAbs_FACE
from OCP.TopExp import TopExp_Explorer
from OCP.TopLoc import TopLoc_Location
from OCP.TopoDS import TopoDS
from OCP.Geom import Geom_ConicalSurface
from OCP.gp import gp_Ax3, gp_Dir, gp_Lin, gp_Pnt, gp_Pnt2d, gp_Vec
from OCP.BRepAlgoAPI import BRepAlgoAPI_Fuse
from OCP.BRepFill import BRepFill
from OCP.BRepLib import BRepLib
from OCP.Geom import Geom_BSplineSurface, Geom_Line, Geom_OffsetSurface
from OCP.Geom2dAPI import Geom2dAPI_Interpolate
from OCP.GeomAPI import GeomAPI_IntCS, GeomAPI_Interpolate
from OCP.GeomFill import GeomFill_BSplineCurves, GeomFill_StretchStyle
from OCP.GeomLProp import GeomLProp_SLProps
from OCP.OCP.collections import Array1_double, Array1_int, Array2_gp_Pnt, HArray1_gp_Pnt, HArray1_gp_Pnt2d
from OCP.ShapeFix import ShapeFix_Face

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
OUT = os.path.join(ROOT, "tests", "data", "sheet_reference.json")

# The bracket's numbers, as examples/bracket/bracket.die gives them.
BRACKET_GAUGE = 1.5
# The reinforcement's plate gauge, as examples/reinforcement gives it.
REINFORCEMENT_GAUGE = 1.2
# The pan's gauge, as examples/pan gives it.
PAN_GAUGE = 0.8
LENGTH, DEPTH, CORNER, FLANGE = 120.0, 70.0, 8.0, 30.0
FOOT_LINE, FOOT_RADIUS = 14.0, 2.0  # the foot's bend line and inside radius, -90 deg
# The tray's, as examples/tray/tray.die gives them.
TRAY_GAUGE = 1.0
TRAY_LENGTH, TRAY_WIDTH, TRAY_WALL, TRAY_DRAFT = 160.0, 100.0, 25.0, math.radians(10.0)
TRAY_CORNER = 15.0
PAD = (50.0, 30.0, 130.0, 70.0)
PAD_HEIGHT, PAD_DRAFT = 3.0, math.radians(30.0)
OUTLINE_TOLERANCE = 0.05


def sig(x, digits=12):
    return float(f"{x:.{digits}g}")


def P(x, y, z=0.0):
    return gp_Pnt(x, y, z)


def seg(a, b):
    return BRepBuilderAPI_MakeEdge(a, b).Edge()


def arc(a, m, b):
    return BRepBuilderAPI_MakeEdge(GC_MakeArcOfCircle(a, m, b).Value()).Edge()


def wire(edges):
    w = BRepBuilderAPI_MakeWire()
    for e in edges:
        w.Add(e)
    return w.Wire()


def polygon(points):
    """A closed wire through `points` (x, y, z) by straight lines."""
    return wire([seg(P(*a), P(*b)) for a, b in zip(points, points[1:] + points[:1])])


def sewn(faces):
    sew = BRepBuilderAPI_Sewing(1e-6)
    for f in faces:
        sew.Add(f)
    sew.Perform()
    return sew.SewedShape()


def bracket_mid_surface():
    """The bracket's sheets, sewn into one shell: the plate right of the foot's bend
    zone (with the bolt hole and the slot), the flange, the bend as an exact quarter
    cylinder of the mid-surface's radius (the inside radius plus half the gauge) whose
    zone of the flat plate is centred on the bend line, and the foot: the flat plate
    left of the zone (with its rounded corners), turned down square."""
    r = CORNER
    c = r * (1 - math.sqrt(0.5))
    rho = FOOT_RADIUS + BRACKET_GAUGE / 2
    zone = rho * math.pi / 2
    x1, x0 = FOOT_LINE + zone / 2, FOOT_LINE - zone / 2

    def foot(x, y):
        """Where the flat plate's point (x, y) left of the zone lies on the foot."""
        return P(x1 - rho, y, -rho - (x0 - x))

    outer = wire(
        [
            seg(P(x1, 0), P(LENGTH, 0)),
            seg(P(LENGTH, 0), P(LENGTH, DEPTH)),
            seg(P(LENGTH, DEPTH), P(x1, DEPTH)),
            seg(P(x1, DEPTH), P(x1, 0)),
        ]
    )
    bolt = wire([arc(P(24, 35), P(30, 41), P(36, 35)), arc(P(36, 35), P(30, 29), P(24, 35))])
    slot = wire(
        [
            seg(P(60, 31), P(84, 31)),
            arc(P(84, 31), P(88, 35), P(84, 39)),
            seg(P(84, 39), P(60, 39)),
            arc(P(60, 39), P(56, 35), P(60, 31)),
        ]
    )
    plate = BRepBuilderAPI_MakeFace(outer, True)
    plate.Add(bolt)  # drawn clockwise: a hole as it is
    plate.Add(TopoDS.Wire(slot.Reversed()))  # drawn counter-clockwise: turned round
    flange = BRepBuilderAPI_MakeFace(
        wire(
            [
                seg(P(LENGTH, 0), P(LENGTH, DEPTH)),
                seg(P(LENGTH, DEPTH), P(LENGTH, DEPTH, FLANGE)),
                seg(P(LENGTH, DEPTH, FLANGE), P(LENGTH, 0, FLANGE)),
                seg(P(LENGTH, 0, FLANGE), P(LENGTH, 0)),
            ]
        ),
        True,
    ).Face()
    h = math.sqrt(0.5)
    quarter = arc(P(x1, 0, 0), P(x1 - rho * h, 0, -rho * (1 - h)), P(x1 - rho, 0, -rho))
    bend = TopoDS.Face(BRepPrimAPI_MakePrism(quarter, gp_Vec(0, DEPTH, 0)).Shape())
    foot_face = BRepBuilderAPI_MakeFace(
        wire(
            [
                seg(foot(x0, DEPTH), foot(r, DEPTH)),
                arc(foot(r, DEPTH), foot(c, DEPTH - c), foot(0, DEPTH - r)),
                seg(foot(0, DEPTH - r), foot(0, r)),
                arc(foot(0, r), foot(c, c), foot(r, 0)),
                seg(foot(r, 0), foot(x0, 0)),
                seg(foot(x0, 0), foot(x0, DEPTH)),
            ]
        ),
        True,
    ).Face()
    return sewn([plate.Face(), flange, bend, foot_face])


def tray_mid_surface():
    """The tray's sheets, sewn into one shell: the floor (a rounded rectangle, holed by
    the drain and by the pad's foot), the pad's walls and top, and the wall all round:
    four planes leaning out and, at the corners, exact cones (the fillets' arcs at the
    floor, their radius grown by the lean at the rim)."""
    lean, rise = TRAY_WALL * math.sin(TRAY_DRAFT), TRAY_WALL * math.cos(TRAY_DRAFT)
    lx, wy, r = TRAY_LENGTH, TRAY_WIDTH, TRAY_CORNER

    def corner_arc(cx, cy, a0):
        a1, am = a0 + math.pi / 2, a0 + math.pi / 4
        return arc(
            P(cx + r * math.cos(a0), cy + r * math.sin(a0)),
            P(cx + r * math.cos(am), cy + r * math.sin(am)),
            P(cx + r * math.cos(a1), cy + r * math.sin(a1)),
        )

    # The corners' centres and the angle each arc starts at, counter-clockwise.
    corners = [(lx - r, r, -math.pi / 2), (lx - r, wy - r, 0.0), (r, wy - r, math.pi / 2), (r, r, math.pi)]
    floor_wire = wire(
        [
            seg(P(r, 0), P(lx - r, 0)),
            corner_arc(*corners[0]),
            seg(P(lx, r), P(lx, wy - r)),
            corner_arc(*corners[1]),
            seg(P(lx - r, wy), P(r, wy)),
            corner_arc(*corners[2]),
            seg(P(0, wy - r), P(0, r)),
            corner_arc(*corners[3]),
        ]
    )
    x0, y0, x1, y1 = PAD
    inset = PAD_HEIGHT * math.tan(PAD_DRAFT)
    foot = [(x0, y0, 0), (x1, y0, 0), (x1, y1, 0), (x0, y1, 0)]
    top = [(x0 + inset, y0 + inset, PAD_HEIGHT), (x1 - inset, y0 + inset, PAD_HEIGHT), (x1 - inset, y1 - inset, PAD_HEIGHT), (x0 + inset, y1 - inset, PAD_HEIGHT)]
    drain = wire([arc(P(20, 45), P(25, 50), P(30, 45)), arc(P(30, 45), P(25, 40), P(20, 45))])
    plate = BRepBuilderAPI_MakeFace(floor_wire, True)
    plate.Add(drain)  # drawn clockwise: a hole as it is
    plate.Add(polygon(foot[::-1]))
    faces = [plate.Face(), BRepBuilderAPI_MakeFace(polygon(top), True).Face()]
    for i in range(4):
        j = (i + 1) % 4
        faces.append(BRepBuilderAPI_MakeFace(polygon([foot[i], foot[j], top[j], top[i]]), True).Face())
    # The straight walls, each from its floor edge up and out by the lean.
    for a, b, out in [
        ((r, 0, 0), (lx - r, 0, 0), (0, -1)),
        ((lx, r, 0), (lx, wy - r, 0), (1, 0)),
        ((lx - r, wy, 0), (r, wy, 0), (0, 1)),
        ((0, wy - r, 0), (0, r, 0), (-1, 0)),
    ]:
        up = lambda p: (p[0] + lean * out[0], p[1] + lean * out[1], rise)
        faces.append(BRepBuilderAPI_MakeFace(polygon([a, b, up(b), up(a)]), True).Face())
    # The corners: cones about vertical axes through the fillets' centres, opening by
    # the draft, from the floor's arcs along the wall's slant.
    for cx, cy, a0 in corners:
        cone = Geom_ConicalSurface(gp_Ax3(P(cx, cy), gp_Dir(0, 0, 1), gp_Dir(1, 0, 0)), TRAY_DRAFT, r)
        u0 = a0 % (2 * math.pi)
        faces.append(BRepBuilderAPI_MakeFace(cone, u0, u0 + math.pi / 2, 0.0, TRAY_WALL, 1e-7).Face())
    return sewn(faces)


# The hood reinforcement's numbers, as examples/hood_reinforcement gives them.
HOOD_GAUGE = 1.2
HOOD_CROWN, HOOD_FALL = 14.0, 0.12
HOOD_CORNER = 12.0
RIB = (25.0, 30.0, 150.0, 50.0)
RIB_HEIGHT, RIB_DRAFT = 2.5, math.radians(30.0)
REAR = ((168.0, 110.0), (12.0, 110.0), 18.0)  # the flange's ends and height


def hood_skin():
    """The hood's skin: the example's bicubic net, clamped uniform knots."""
    poles = Array2_gp_Pnt(1, 5, 1, 5)
    for i in range(5):
        for j in range(5):
            x, y = i * 75.0 - 60.0, j * 60.0 - 50.0
            z = HOOD_FALL * x + HOOD_CROWN * math.sin(math.radians(i * 45)) * math.sin(math.radians(j * 45))
            poles.SetValue(i + 1, j + 1, P(x, y, z))
    knots = Array1_double(1, 3)
    mults = Array1_int(1, 3)
    for k, (t, m) in enumerate([(0.0, 4), (0.5, 1), (1.0, 4)]):
        knots.SetValue(k + 1, t)
        mults.SetValue(k + 1, m)
    return Geom_BSplineSurface(poles, knots, knots, mults, mults, 3, 3)


SKIN = hood_skin()


def uv_under(x, y):
    """The skin's parameters under (x, y) seen from above, by OpenCascade's own
    line-surface intersection."""
    hit = GeomAPI_IntCS(Geom_Line(gp_Lin(P(x, y, -500.0), gp_Dir(0, 0, 1))), SKIN)
    if hit.NbPoints() != 1:
        raise SystemExit(f"the skin is not met once under ({x}, {y})")
    u, v, _ = hit.Parameters(1)
    return u, v


def on_skin(points, surface=SKIN):
    """An edge on `surface` (the skin or an offset of it, whose parameters are the
    skin's) through the skin's parameters under `points`, seen from above."""
    uv = HArray1_gp_Pnt2d(1, len(points))
    for k, (x, y) in enumerate(points):
        uv.SetValue(k + 1, gp_Pnt2d(*uv_under(x, y)))
    curve = Geom2dAPI_Interpolate(uv, False, 1e-12)
    curve.Perform()
    edge = BRepBuilderAPI_MakeEdge(curve.Curve(), surface).Edge()
    BRepLib.BuildCurves3d_s(edge, 1e-9)
    return edge


def line_points(a, b, n=41):
    return [(a[0] + (b[0] - a[0]) * k / (n - 1), a[1] + (b[1] - a[1]) * k / (n - 1)) for k in range(n)]


def arc_points(c, r, a0, a1, n=41):
    return [(c[0] + r * math.cos(a0 + (a1 - a0) * k / (n - 1)), c[1] + r * math.sin(a0 + (a1 - a0) * k / (n - 1))) for k in range(n)]


def rectangle(x0, y0, x1, y1):
    return [line_points((x0, y0), (x1, y0)), line_points((x1, y0), (x1, y1)), line_points((x1, y1), (x0, y1)), line_points((x0, y1), (x0, y0))]


def fixed(face):
    fix = ShapeFix_Face(face)
    fix.Perform()
    return fix.Face()


def hood_mid_surface(with_flange=False):
    """The hood reinforcement's sheets, sewn into one shell: the skin trimmed by the
    rounded outline and holed by the bolt holes, the slot and the rib's foot; the rib's
    top on the skin offset by its height over the foot inset by the height times the
    draft's tangent, its walls ruled between; with `with_flange`, the rear flange
    ruled between the skin under its edge and the points 18 mm along the normals."""
    r = HOOD_CORNER
    outline = [
        line_points((r, 0), (180 - r, 0)), arc_points((180 - r, r), r, -math.pi / 2, 0),
        line_points((180, r), (180, 110 - r)), arc_points((180 - r, 110 - r), r, 0, math.pi / 2),
        line_points((180 - r, 110), (r, 110)), arc_points((r, 110 - r), r, math.pi / 2, math.pi),
        line_points((0, 110 - r), (0, r)), arc_points((r, r), r, math.pi, 1.5 * math.pi),
    ]
    circle = lambda cx, cy, rr: [arc_points((cx, cy), rr, 0, math.pi), arc_points((cx, cy), rr, math.pi, 2 * math.pi)]
    slot = [
        line_points((120, 70.5), (140, 70.5)), arc_points((140, 75), 4.5, -math.pi / 2, math.pi / 2),
        line_points((140, 79.5), (120, 79.5)), arc_points((120, 75), 4.5, math.pi / 2, 1.5 * math.pi),
    ]
    plate = BRepBuilderAPI_MakeFace(SKIN, wire([on_skin(p) for p in outline]), True)
    for hole in [circle(40, 80, 4.25), circle(80, 80, 4.25), slot, rectangle(*RIB)]:
        plate.Add(TopoDS.Wire(wire([on_skin(p) for p in hole]).Reversed()))
    faces = [fixed(plate.Face())]
    inset = RIB_HEIGHT * math.tan(RIB_DRAFT)
    x0, y0, x1, y1 = RIB
    top_surface = Geom_OffsetSurface(SKIN, RIB_HEIGHT)
    foot = [on_skin(p) for p in rectangle(*RIB)]
    top = [on_skin(p, top_surface) for p in rectangle(x0 + inset, y0 + inset, x1 - inset, y1 - inset)]
    faces.append(fixed(BRepBuilderAPI_MakeFace(top_surface, wire(top), True).Face()))
    faces += [BRepFill.Face_s(a, b) for a, b in zip(foot, top)]
    if with_flange:
        faces.append(BRepBuilderAPI_MakeFace(rear_flange(), 1e-7).Face())
    return sewn(faces)


def rear_flange(below=0.0):
    """The rear flange's mid-surface: ruled between the skin under its edge and the
    points its height along the skin's normals (turned up) there; with `below`, run
    on that far below the skin (where the outside of the fold's mitre lies)."""
    a, b, height = REAR
    points = line_points(a, b, 61)
    foot, top = HArray1_gp_Pnt(1, len(points)), HArray1_gp_Pnt(1, len(points))
    for k, (x, y) in enumerate(points):
        props = GeomLProp_SLProps(SKIN, *uv_under(x, y), 1, 1e-9)
        n = props.Normal()
        if n.Z() < 0:
            n.Reverse()
        p = props.Value()
        foot.SetValue(k + 1, P(p.X() - below * n.X(), p.Y() - below * n.Y(), p.Z() - below * n.Z()))
        top.SetValue(k + 1, P(p.X() + height * n.X(), p.Y() + height * n.Y(), p.Z() + height * n.Z()))
    curves = []
    for row in (foot, top):
        fit = GeomAPI_Interpolate(row, False, 1e-12)
        fit.Perform()
        curves.append(fit.Curve())
    return GeomFill_BSplineCurves(curves[0], curves[1], GeomFill_StretchStyle).Surface()


def thicken_both_ways(name, shell, gauge):
    """The solid half the gauge each side of the shell: two one-sided thickenings
    fused."""
    halves = []
    for side in (shell, shell.Reversed()):
        thick = BRepOffset_MakeOffset()
        thick.Initialize(side, gauge / 2, 1e-7, BRepOffset_Skin, False, False, GeomAbs_Intersection, True)
        thick.MakeOffsetShape(Message_ProgressRange())
        if not thick.IsDone():
            raise SystemExit(f"OpenCascade could not thicken the {name}: error {thick.Error()}")
        halves.append(thick.Shape())
    return BRepAlgoAPI_Fuse(*halves).Shape()


def curved_length(shape):
    """The length of the shape's edges that are not straight lines (its arcs)."""
    from OCP.BRepAdaptor import BRepAdaptor_Curve
    from OCP.GeomAbs import GeomAbs_Line
    from OCP.TopAbs import TopAbs_EDGE

    # The explorer meets an edge once per face it bounds; every arc bounds the plate
    # only (the edges sheets share are straight), so each counts once.
    total = 0.0
    exp = TopExp_Explorer(shape, TopAbs_EDGE)
    while exp.More():
        edge = TopoDS.Edge(exp.Current())
        exp.Next()
        if BRepAdaptor_Curve(edge).GetType() != GeomAbs_Line:
            g = GProp_GProps()
            BRepGProp.LinearProperties_s(edge, g)
            total += g.Mass()
    return total


def area(shape):
    g = GProp_GProps()
    BRepGProp.SurfaceProperties_s(shape, g, 1e-9)
    return g.Mass()


def volume(shape):
    g = GProp_GProps()
    BRepGProp.VolumeProperties_s(shape, g, 1e-9)
    return g.Mass()


def thicken(name, shell, gauge):
    """The solid: the shell moved half the gauge to one side, thickened across."""
    shifted = BRepOffsetAPI_MakeOffsetShape()
    shifted.PerformByJoin(shell, -gauge / 2, 1e-7, BRepOffset_Skin, False, False, GeomAbs_Intersection, False)
    thick = BRepOffset_MakeOffset()
    thick.Initialize(shifted.Shape(), gauge, 1e-7, BRepOffset_Skin, False, False, GeomAbs_Intersection, True)
    thick.MakeOffsetShape(Message_ProgressRange())
    if not thick.IsDone():
        raise SystemExit(f"OpenCascade could not thicken the {name}: error {thick.Error()}")
    return thick.Shape()


def occ_samples(solid, deflection=0.002):
    """Points on the solid's faces: the tessellation's nodes and triangle centroids."""
    BRepMesh_IncrementalMesh(solid, deflection, False, 0.1, True)
    points = []
    exp = TopExp_Explorer(solid, TopAbs_FACE)
    while exp.More():
        face = TopoDS.Face(exp.Current())
        loc = TopLoc_Location()
        tri = BRep_Tool.Triangulation_s(face, loc)
        trsf = loc.Transformation()
        nodes = [tri.Node(i).Transformed(trsf) for i in range(1, tri.NbNodes() + 1)]
        xyz = np.array([[p.X(), p.Y(), p.Z()] for p in nodes])
        points.append(xyz)
        for i in range(1, tri.NbTriangles() + 1):
            a, b, c = tri.Triangle(i).Get()
            points.append(((xyz[a - 1] + xyz[b - 1] + xyz[c - 1]) / 3.0)[None, :])
        exp.Next()
    return np.vstack(points)


def read_obj_object(path, name):
    """The vertices and triangles of object `name` in an OBJ file (whose indices are
    1-based and global to the file), renumbered to the object's own vertices."""
    vertices, triangles, inside = [], [], False
    with open(path) as f:
        for line in f:
            if line.startswith("v "):
                vertices.append([float(x) for x in line.split()[1:4]])
            elif line.startswith("o "):
                inside = line.split()[1] == name
            elif line.startswith("f ") and inside:
                triangles.append([int(x.split("/")[0]) - 1 for x in line.split()[1:4]])
    triangles = np.array(triangles)
    used = np.unique(triangles)
    renumber = np.full(len(vertices), -1)
    renumber[used] = np.arange(len(used))
    return np.array(vertices)[used], renumber[triangles]


def point_triangle_distances(points, a, b, c):
    """Each point's distance to the nearest of the triangles (a, b, c), exactly
    (Ericson, Real-Time Collision Detection, 5.1.5), vectorised over triangles."""
    ab, ac = b - a, c - a
    best = np.full(len(points), np.inf)
    for k, p in enumerate(points):
        ap, bp, cp = p - a, p - b, p - c
        d1, d2 = np.einsum("ij,ij->i", ab, ap), np.einsum("ij,ij->i", ac, ap)
        d3, d4 = np.einsum("ij,ij->i", ab, bp), np.einsum("ij,ij->i", ac, bp)
        d5, d6 = np.einsum("ij,ij->i", ab, cp), np.einsum("ij,ij->i", ac, cp)
        va, vb, vc = d3 * d6 - d5 * d4, d5 * d2 - d1 * d6, d1 * d4 - d3 * d2
        with np.errstate(divide="ignore", invalid="ignore"):
            denom = 1.0 / (va + vb + vc)
            v, w = vb * denom, vc * denom
            q = a + ab * v[:, None] + ac * w[:, None]
            # Vertex regions.
            q = np.where(((d1 <= 0) & (d2 <= 0))[:, None], a, q)
            q = np.where(((d3 >= 0) & (d4 <= d3))[:, None], b, q)
            q = np.where(((d6 >= 0) & (d5 <= d6))[:, None], c, q)
            # Edge regions.
            t = d1 / (d1 - d3)
            m = (vc <= 0) & (d1 >= 0) & (d3 <= 0)
            q = np.where(m[:, None], a + ab * t[:, None], q)
            t = d2 / (d2 - d6)
            m = (vb <= 0) & (d2 >= 0) & (d6 <= 0)
            q = np.where(m[:, None], a + ac * t[:, None], q)
            t = (d4 - d3) / ((d4 - d3) + (d5 - d6))
            m = (va <= 0) & ((d4 - d3) >= 0) & ((d5 - d6) >= 0)
            q = np.where(m[:, None], b + (c - b) * t[:, None], q)
        best[k] = np.min(np.linalg.norm(q - p, axis=1))
    return best


def mesh_volume(vertices, triangles):
    a, b, c = (vertices[triangles[:, i]] for i in range(3))
    return float(np.einsum("ij,ij->i", a, np.cross(b, c)).sum() / 6.0)


# How dieface is run: built by cargo unless `--dieface PATH` names a binary.
dieface = ["cargo", "run", "--quiet", "--release", "--bin", "dieface", "--"]


def dieface_obj(dieface, example, edit=None):
    """dieface's OBJ of `examples/NAME/NAME.die` (its text changed by `edit` first),
    as the path of a file in a temporary folder the caller removes."""
    tmp = tempfile.mkdtemp()
    atexit.register(shutil.rmtree, tmp, True)
    source = os.path.join(ROOT, "examples", example, f"{example}.die")
    if edit is not None:
        with open(source) as f:
            text = edit(f.read())
        source = os.path.join(tmp, f"{example}.die")
        with open(source, "w") as f:
            f.write(text)
    out = os.path.join(tmp, f"{example}.obj")
    subprocess.run(dieface + ["build", source, "-o", out], cwd=ROOT, check=True, capture_output=True)
    return out


def obj_group_vertices(path, group):
    """The vertices of the triangles of OBJ group `group` (a `g` line's name)."""
    vertices, used, inside = [], set(), False
    with open(path) as f:
        for line in f:
            if line.startswith("v "):
                vertices.append([float(x) for x in line.split()[1:4]])
            elif line.startswith("g ") or line.startswith("o "):
                inside = line.split()[1] == group
            elif line.startswith("f ") and inside:
                used.update(int(x.split("/")[0]) - 1 for x in line.split()[1:4])
    return np.array(vertices)[sorted(used)]


def without_rear_flange(text):
    """The hood reinforcement's script without its rear flange."""
    kept = [line for line in text.splitlines() if not line.strip().startswith("flange rear")]
    if len(kept) != len(text.splitlines()) - 1:
        raise SystemExit("the hood reinforcement has no one `flange rear` line")
    return "\n".join(kept) + "\n"


def trimmed_reinforcement(text):
    """The reinforcement's script without its 2 mm tab (OpenCascade thickens a shell at
    one gauge), its rib and its rounded back corners (OpenCascade's offset fails on the
    rib's drafted walls round its round ends, and on the step-down bend beside the
    rounded corners, with `BRepOffset_NotConnectedShell`)."""
    drop = ("flange tab", "lift rib", "fillet corner")
    kept = [line for line in text.splitlines() if not line.strip().startswith(drop)]
    if len(kept) != len(text.splitlines()) - 4:
        raise SystemExit("the reinforcement has not one tab, one rib and two fillets")
    return "\n".join(kept) + "\n"


def dieface_mid_surface(example, sheet, edit):
    """dieface's mid-surface of the example (its script changed by `edit`), its
    triangles made OpenCascade faces, sewn into one shell and merged where coplanar
    (`ShapeUpgrade_UnifySameDomain`). OpenCascade then thickens dieface's own sheets:
    the offsets, the edges where they meet and the junctions are its, not dieface's."""
    from OCP.BRepBuilderAPI import BRepBuilderAPI_MakeFace
    from OCP.ShapeUpgrade import ShapeUpgrade_UnifySameDomain

    mid, triangles = read_obj_object(dieface_obj(dieface, example, edit), f"{sheet}/mid")
    faces = [BRepBuilderAPI_MakeFace(polygon([tuple(mid[i]) for i in t]), True).Face() for t in triangles]
    sew = BRepBuilderAPI_Sewing(1e-4)
    for f in faces:
        sew.Add(f)
    sew.Perform()
    unify = ShapeUpgrade_UnifySameDomain(sew.SewedShape(), True, True, False)
    unify.Build()
    return unify.Shape()


# Each part: its mid-surface, gauge and thickening, the example and sheet it is
# compared with (its script edited first where OpenCascade cannot make the whole
# part), and how far dieface's vertices may lie off the exact solid: on a bend's
# radius, dieface's facets are chords within 0.01 mm of the arc (BEND_TOLERANCE in
# src/sheet/part/strips.rs); round the tray's corners its wall's strips are chords of
# the fillets within the outline tolerance; on the hood's skin, dieface's vertices lie
# on the offsets exactly but for the rib's curved mitres (within the skin's curvature
# times the gauge squared, LAID_TOLERANCE bounds it).
PARTS = {
    "bracket": dict(build=bracket_mid_surface, gauge=BRACKET_GAUGE, sag=0.01, thicken=thicken, example="bracket", sheet="bracket", edit=None),
    "tray": dict(build=tray_mid_surface, gauge=TRAY_GAUGE, sag=OUTLINE_TOLERANCE, thicken=thicken, example="tray", sheet="tray", edit=None),
    "reinforcement": dict(build=lambda: dieface_mid_surface("reinforcement", "reinforcement", trimmed_reinforcement), gauge=REINFORCEMENT_GAUGE, sag=1e-6, thicken=thicken, example="reinforcement", sheet="reinforcement", edit=trimmed_reinforcement),
    "pan": dict(build=lambda: dieface_mid_surface("pan", "pan", None), gauge=PAN_GAUGE, sag=1e-6, thicken=thicken, example="pan", sheet="pan", edit=None),
    "hood_reinforcement": dict(build=hood_mid_surface, gauge=HOOD_GAUGE, sag=0.01, thicken=thicken_both_ways, example="hood_reinforcement", sheet="reinforcement", edit=without_rear_flange),
}


def compare(dieface, name):
    """One part's record: OpenCascade's solid, dieface's, and the distances between."""
    part = PARTS[name]
    shell = part["build"]()
    solid = part["thicken"](name, shell, part["gauge"])
    obj = dieface_obj(dieface, part["example"], part["edit"])
    vertices, triangles = read_obj_object(obj, f"{part['sheet']}/solid")
    # dieface's vertices to OpenCascade's exact solid.
    to_occ = 0.0
    for x, y, z in vertices:
        vertex = BRepBuilderAPI_MakeVertex(P(x, y, z)).Vertex()
        dist = BRepExtrema_DistShapeShape(vertex, solid)
        to_occ = max(to_occ, dist.Value())
    # OpenCascade's faces to dieface's triangles.
    samples = occ_samples(solid)
    a, b, c = (vertices[triangles[:, i]] for i in range(3))
    to_dieface = float(point_triangle_distances(samples, a, b, c).max())
    return {
        "example": f"examples/{part['example']}/{part['example']}.die",
        "edited": part["edit"].__doc__ if part["edit"] else None,
        "gauge": part["gauge"],
        "sag": part["sag"],
        "occ": {
            "volume": sig(volume(solid)),
            "mid_area": sig(area(shell)),
            "curved_length": sig(curved_length(shell)),
            "valid": BRepCheck_Analyzer(solid).IsValid(),
        },
        "dieface": {
            "volume": sig(mesh_volume(vertices, triangles)),
            "vertices": len(vertices),
            "triangles": len(triangles),
        },
        "distance": {
            "dieface_to_occ": sig(to_occ, 6),
            "occ_to_dieface": sig(to_dieface, 6),
            "occ_samples": len(samples),
        },
    }


def hood_flange(dieface):
    """The whole hood reinforcement, flange and all: OpenCascade's mid-surface area and
    dieface's, and how far each of dieface's vertices on the flange's sides lies off
    OpenCascade's exact offsets of the flange half the gauge each way."""
    from OCP.GeomAPI import GeomAPI_ProjectPointOnSurf

    obj = dieface_obj(dieface, "hood_reinforcement")
    # The flange run on below the skin: the outside of the fold's mitre lies there.
    flange = rear_flange(below=2.0)
    offsets = [Geom_OffsetSurface(flange, HOOD_GAUGE / 2), Geom_OffsetSurface(flange, -HOOD_GAUGE / 2)]
    worst, count = 0.0, 0
    for side in ("inside", "outside"):
        for x, y, z in obj_group_vertices(obj, f"reinforcement/solid/rear.{side}"):
            d = min(GeomAPI_ProjectPointOnSurf(P(x, y, z), s).LowerDistance() for s in offsets)
            worst, count = max(worst, d), count + 1
    mid, triangles = read_obj_object(obj, "reinforcement/mid")
    a, b, c = (mid[triangles[:, i]] for i in range(3))
    mid_area = float(0.5 * np.linalg.norm(np.cross(b - a, c - a), axis=1).sum())
    return {
        "example": "examples/hood_reinforcement/hood_reinforcement.die",
        "occ_mid_area": sig(area(hood_mid_surface(with_flange=True))),
        "dieface_mid_area": sig(mid_area),
        "flange_vertices": count,
        "flange_sides_to_occ_offsets": sig(worst, 6),
    }


def main():
    global dieface
    if "--dieface" in sys.argv:
        dieface = [sys.argv[sys.argv.index("--dieface") + 1]]
    result = {
        "ocp": metadata.version("cadquery-ocp"),
        "tolerance": OUTLINE_TOLERANCE,
        "parts": {name: compare(dieface, name) for name in PARTS},
        "hood_flange": hood_flange(dieface),
    }
    text = json.dumps(result, indent=2) + "\n"
    if "--stdout" in sys.argv:
        sys.stdout.write(text)
    else:
        with open(OUT, "w") as f:
            f.write(text)
        print(f"wrote {OUT}")


if __name__ == "__main__":
    main()
