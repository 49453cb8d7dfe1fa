"""gmsh's quad mesher on a plane region, timed: the peer of dieface's
`quad_mesh_region` in BENCHMARKS.md (issue 18). Run by the `quad` bench binary:

    python3 bench/reference/gmsh_quad.py REGION.json OUT.obj [RUNS]

Versions: `pip install gmsh==4.15.2` (Python 3.11).

REGION.json holds the region as the bench writes it: `{"size": mm, "outer": [[x, y],
...], "holes": [[[x, y], ...], ...]}`, every loop a closed polygon in mm, the first
point not repeated at the end, either way round.

The geometry is built with gmsh's built-in `geo` kernel. Every loop (repeated points
dropped) is split at its corners (where it turns by 30 deg or more between neighbouring
segments, as dieface's `QuadOptions::at_size` takes them) and each run between two
corners becomes one curve: a spline through its points, or a straight line when it has
two. A segment more than 4 times as long as both its neighbours (the straight side of a
rounded rectangle or a slot between its arcs' points) is a line of its own too: a spline
through it and the arcs' closely spaced points would bulge off the side by up to 10 mm
(seen on the door inner's window opening). A loop with fewer than 3 such breaks (a
circle) is cut into 4 runs of about equal point counts (3 when it has fewer than 8
points), any corner it has kept. So gmsh is not made to keep every polyline point as a
mesh node: it spaces its own nodes along each curve, as dieface resamples the boundary
too.

Options: Frontal-Delaunay for quads (`Mesh.Algorithm = 8`), every surface recombined
(`Mesh.RecombineAll = 1`) with the Blossom algorithm (`Mesh.RecombinationAlgorithm =
1`), the element size fixed (`Mesh.MeshSizeMin = Mesh.MeshSizeMax = size`, no sizes
from curvature) and no subdivision (`Mesh.SubdivisionAlgorithm = 0`), so triangles
Blossom cannot pair are left as triangles; gmsh's defaults otherwise (one thread).

Each run starts from a fresh model and times the geometry build and `generate(2)`; the
median of RUNS (5 unless given) is printed as JSON on stdout (`{"ms": ..., "quads":
..., "triangles": ..., "nodes": ...}`). The last run's mesh is written to OUT.obj: 2-D
(z = 0), the faces as gmsh gives them (its quads and triangles, none split or joined),
all turned counter-clockwise if gmsh's surface faces the other way (the whole mesh at
once, never face by face, so an element gmsh folds still shows as inverted).
"""

import json
import math
import statistics
import sys
import time

import gmsh

# Where a loop turns by at least this much (deg), its point is a corner.
CORNER_TURN = 30.0

# A segment more than this many times as long as both its neighbours is a straight side
# of its own (a line), not part of a spline.
LONG_SIDE = 4.0


def signed_area(points):
    """The signed area of a closed polygon (positive counter-clockwise)."""
    n = len(points)
    return 0.5 * sum(
        points[i][0] * points[(i + 1) % n][1] - points[(i + 1) % n][0] * points[i][1]
        for i in range(n)
    )


def corners(points):
    """The indices of the loop's points where it turns by CORNER_TURN or more."""
    n = len(points)
    found = []
    for i in range(n):
        p, q, r = points[i - 1], points[i], points[(i + 1) % n]
        a = (q[0] - p[0], q[1] - p[1])
        b = (r[0] - q[0], r[1] - q[1])
        cross, dot = a[0] * b[1] - a[1] * b[0], a[0] * b[0] + a[1] * b[1]
        turn = math.degrees(abs(math.atan2(cross, dot)))
        if turn >= CORNER_TURN:
            found.append(i)
    return found


def long_sides(points):
    """The indices of the points that start or end a long straight side: a segment
    more than LONG_SIDE times as long as both its neighbours."""
    n = len(points)
    length = [math.dist(points[i], points[(i + 1) % n]) for i in range(n)]
    found = set()
    for i in range(n):
        if length[i] > LONG_SIDE * max(length[i - 1], length[(i + 1) % n]):
            found |= {i, (i + 1) % n}
    return found


def breaks(points):
    """Where the loop is cut into runs: its corners and the ends of its long sides, and
    more cuts where it has fewer than three (evenly by point count: 4 runs, or 3 on a
    loop of fewer than 8 points)."""
    n = len(points)
    found = sorted(set(corners(points)) | long_sides(points))
    if len(found) >= 3:
        return found
    pieces = 4 if n >= 8 else 3
    start = found[0] if found else 0
    cuts = {(start + round(k * n / pieces)) % n for k in range(pieces)}
    return sorted(cuts | set(found))


def add_loop(points, size):
    """Adds one loop to the geo model, cut at its breaks into splines; returns its
    curve loop's tag."""
    n = len(points)
    tags = [gmsh.model.geo.addPoint(x, y, 0.0, size) for x, y in points]
    cuts = breaks(points)
    curves = []
    for k, first in enumerate(cuts):
        last = cuts[(k + 1) % len(cuts)]
        count = (last - first) % n or n
        run = [tags[(first + i) % n] for i in range(count + 1)]
        if len(run) == 2:
            curves.append(gmsh.model.geo.addLine(run[0], run[1]))
        else:
            curves.append(gmsh.model.geo.addSpline(run))
    return gmsh.model.geo.addCurveLoop(curves)


def distinct(points, size):
    """The loop without repeated points (a point within a millionth of the size of the
    one before it, or of the first when it is the last)."""
    out = []
    for p in points:
        if not out or math.dist(p, out[-1]) > 1e-6 * size:
            out.append(p)
    if len(out) > 1 and math.dist(out[0], out[-1]) <= 1e-6 * size:
        out.pop()
    return out


def build(region):
    """Builds the region as one plane surface: the outer loop counter-clockwise, the
    holes clockwise, repeated points dropped."""
    size = region["size"]
    outer = distinct(region["outer"], size)
    if signed_area(outer) < 0:
        outer = outer[::-1]
    loops = [add_loop(outer, size)]
    for hole in region["holes"]:
        hole = distinct(hole, size)
        if signed_area(hole) > 0:
            hole = hole[::-1]
        loops.append(add_loop(hole, size))
    gmsh.model.geo.addPlaneSurface(loops)
    gmsh.model.geo.synchronize()


def set_options(size):
    """The meshing options of the module notes."""
    gmsh.option.setNumber("General.Terminal", 0)
    gmsh.option.setNumber("Mesh.Algorithm", 8)
    gmsh.option.setNumber("Mesh.RecombineAll", 1)
    gmsh.option.setNumber("Mesh.RecombinationAlgorithm", 1)
    gmsh.option.setNumber("Mesh.SubdivisionAlgorithm", 0)
    gmsh.option.setNumber("Mesh.MeshSizeMin", size)
    gmsh.option.setNumber("Mesh.MeshSizeMax", size)
    gmsh.option.setNumber("Mesh.MeshSizeFromCurvature", 0)


def faces():
    """The 2-D mesh's nodes (tag to (x, y)) and faces (lists of node tags, as gmsh
    orders them)."""
    tags, coords, _ = gmsh.model.mesh.getNodes()
    nodes = {int(t): (coords[3 * i], coords[3 * i + 1]) for i, t in enumerate(tags)}
    out = []
    types, _, conn = gmsh.model.mesh.getElements(dim=2)
    for kind, ids in zip(types, conn):
        if kind == 2:
            k = 3
        elif kind == 3:
            k = 4
        else:
            raise SystemExit(f"gmsh gave an element of type {kind}, not a triangle or quad")
        out.extend([int(t) for t in ids[i : i + k]] for i in range(0, len(ids), k))
    return nodes, out


def write_obj(path, nodes, elements):
    """Writes the mesh as OBJ at z = 0, faces counter-clockwise: all turned if their
    total signed area is negative (the surface faced down)."""
    def area(face):
        return signed_area([nodes[t] for t in face])

    if sum(area(f) for f in elements) < 0:
        elements = [f[::-1] for f in elements]
    used = sorted({t for f in elements for t in f})
    index = {t: i + 1 for i, t in enumerate(used)}
    lines = [f"v {nodes[t][0]:.12f} {nodes[t][1]:.12f} 0\n" for t in used]
    lines += ["f " + " ".join(str(index[t]) for t in f) + "\n" for f in elements]
    with open(path, "w") as out:
        out.writelines(lines)


def main() -> None:
    source, target = sys.argv[1], sys.argv[2]
    runs = int(sys.argv[3]) if len(sys.argv) > 3 else 5
    with open(source) as f:
        region = json.load(f)
    gmsh.initialize(readConfigFiles=False)
    set_options(region["size"])
    times = []
    for _ in range(runs):
        gmsh.clear()
        gmsh.model.add("region")
        start = time.perf_counter()
        build(region)
        gmsh.model.mesh.generate(2)
        times.append((time.perf_counter() - start) * 1e3)
    nodes, elements = faces()
    gmsh.finalize()
    write_obj(target, nodes, elements)
    quads = sum(1 for f in elements if len(f) == 4)
    print(
        json.dumps(
            {
                "ms": statistics.median(times),
                "quads": quads,
                "triangles": len(elements) - quads,
                "nodes": len({t for f in elements for t in f}),
            }
        )
    )


if __name__ == "__main__":
    main()
