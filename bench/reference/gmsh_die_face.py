"""gmsh's quad mesher on the fender's whole die face, read from our STEP, timed: the peer
of the `die_face` bench binary (`quad_mesh_shell` on the sewn die face) in BENCHMARKS.md.

    dieface build examples/fender/fender.die -o fender.step
    python3 bench/reference/gmsh_die_face.py fender.step SIZE OUT.obj \
        [--beads] [--algorithm=N]

Versions: `pip install gmsh==4.15.2` (Python 3.11), numpy.

The STEP is what `dieface build` writes (`src/export/step.rs`): one
`SHELL_BASED_SURFACE_MODEL` of two `OPEN_SHELL`s, `die_face` (product, binder and step
draw faces, sewn: neighbouring faces share one `EDGE_CURVE`) and `beads` (the draw
beads, separate faces lying on the binder). It is imported with gmsh's OpenCASCADE
kernel (`occ.importShapes`, millimetres, no healing or sewing by gmsh). gmsh keeps no
names of faces from it, so the shells are read off the STEP text: each `OPEN_SHELL`'s
name and its `ADVANCED_FACE`s in order; gmsh numbers the surfaces 1, 2, ... in the same
order. That correspondence is checked, not assumed: the die face's surfaces must be one
piece through shared curves and share none with the beads, else the script stops. The
bead surfaces are removed before meshing, unless `--beads` is given: then they are
meshed too and reported apart (`"beads"` in the JSON).

Options as `gmsh_quad.py`: Frontal-Delaunay for quads (`Mesh.Algorithm = 8`), every
surface recombined (`Mesh.RecombineAll = 1`) with the Blossom algorithm
(`Mesh.RecombinationAlgorithm = 1`), the element size fixed (`Mesh.MeshSizeMin =
Mesh.MeshSizeMax = SIZE`, no sizes from curvature) and no subdivision
(`Mesh.SubdivisionAlgorithm = 0`), so triangles Blossom cannot pair stay triangles;
gmsh's defaults otherwise (one thread). `--algorithm=N` sets another `Mesh.Algorithm`
(6: Frontal-Delaunay, then the same Blossom recombination). At 10 mm, Frontal-Delaunay
for quads leaves the two long binder strips (`binder/front`, `binder/top`) nearly
empty inside (gmsh's debug log: interior points "cannot be inserted because it is too
close to another point"), so they get ~180 elements with sides up to 240 mm; the
`longest side` column of the face table (`max_side` in the JSON) shows it. Algorithm 6
meshes them at size.

Timed: `gmsh.model.mesh.generate(2)` alone (`generate_s`; it meshes the curves too),
and the whole script from its first line to the JSON (`script_s`: Python start-up
excluded, `import gmsh`, the STEP import, the quality figures and the OBJ included).
One run per call; run it several times for a median.

Written: OUT.obj, the die face's 2-D elements as gmsh gives them (quads and triangles,
none split or joined, each turned as gmsh orients its surface), in mm, nodes shared
where gmsh shares them. Printed: a JSON line on stdout with the counts (`nodes` used by
the elements, `quads`, `triangles`), the quality (below), the times, and conformity:
`free_edges` (element sides used by one element), `non_manifold_edges` (by more than
two), `boundary_edges` (gmsh's line elements on the curves that bound only one meshed
surface: the shell's own rim), `free_edges_inside` (free sides not on that rim: where
neighbouring faces' meshes do not meet) and `coincident_nodes` (used nodes at the
position of another used node, to 1e-6 mm: a seam gmsh did not share). The mesh is
conforming across the sewn faces when `free_edges_inside`, `non_manifold_edges` and
`coincident_nodes` are all 0. A table of each face's elements and quality goes to
stderr.

Quality mirrors `src/geom/mesh/quad/quality.rs` (`scaled_jacobian` and
`mesh_quality`), so the figures compare with the `die_face` bench's: an element's
scaled Jacobian is the least over its corners of the cross product of the two sides
leaving the corner, dotted with the element's unit normal (a quad's: the cross product
of its diagonals, `(c2 - c0) x (c3 - c1)`; a triangle's: `(c1 - c0) x (c2 - c0)`),
over the product of the two sides' lengths, times 2/sqrt(3) for a triangle, each
corner's value clamped to at most 1; -1 at a corner with a zero-length side or an
element with no normal. `min_sj` / `mean_sj` are over all elements (quads and
triangles, as the bench's `whole:` line), `quad_min_sj` / `quad_mean_sj` over the quads
alone; also the smallest and largest corner angle, the largest aspect ratio (longest
side over shortest), how many elements score 0 or less (`inverted`) and the longest
element side (`max_side`, mm: whether the size was kept). Checked against the bench:
run on the per-face OBJs its `DUMP=dir` writes, these functions give its figures.
"""

import time

SCRIPT_START = time.perf_counter()

import json  # noqa: E402
import re  # noqa: E402
import sys  # noqa: E402

import gmsh  # noqa: E402
import numpy as np  # noqa: E402


def step_shells(path):
    """The STEP's `OPEN_SHELL`s in the order written: (name, [face names in order])."""
    with open(path, errors="replace") as f:
        text = f.read()
    face_names = {
        int(i): name
        for i, name in re.findall(r"#(\d+)=ADVANCED_FACE\('((?:[^']|'')*)'", text)
    }
    shells = []
    for name, refs in re.findall(r"#\d+=OPEN_SHELL\('((?:[^']|'')*)',\(([^)]*)\)\)", text):
        faces = [
            face_names[int(r.strip().lstrip("#"))] for r in refs.split(",") if r.strip()
        ]
        shells.append((name, faces))
    return shells


def curves_of(surface):
    """The tags of the curves bounding a surface."""
    return {abs(t) for _, t in gmsh.model.getBoundary([(2, surface)], oriented=False)}


def pieces(surfaces):
    """The surfaces grouped into pieces joined through shared curves."""
    curves = {s: curves_of(s) for s in surfaces}
    left, out = set(surfaces), []
    while left:
        todo = [left.pop()]
        piece = set(todo)
        while todo:
            s = todo.pop()
            for t in list(left):
                if curves[s] & curves[t]:
                    left.discard(t)
                    piece.add(t)
                    todo.append(t)
        out.append(piece)
    return out


def import_die_face(path, keep_beads):
    """Imports the STEP; returns {surface tag: face name} of the die face and of the
    beads (the beads removed from the model unless keep_beads)."""
    shells = step_shells(path)
    gmsh.model.occ.importShapes(path, highestDimOnly=False)
    gmsh.model.occ.synchronize()
    tags = sorted(t for _, t in gmsh.model.getEntities(2))
    named = [(shell, face) for shell, faces in shells for face in faces]
    if len(named) != len(tags):
        raise SystemExit(
            f"the STEP has {len(named)} faces in its shells "
            f"but gmsh made {len(tags)} surfaces"
        )
    by_shell = {}
    for tag, (shell, face) in zip(tags, named):
        by_shell.setdefault(shell, {})[tag] = face
    if "die_face" not in by_shell:
        raise SystemExit(f"no `die_face` shell in the STEP (shells: {list(by_shell)})")
    die, beads = by_shell["die_face"], by_shell.get("beads", {})
    die_curves = set().union(*(curves_of(s) for s in die))
    if len(pieces(list(die))) != 1 or any(curves_of(s) & die_curves for s in beads):
        raise SystemExit(
            "gmsh's surfaces do not follow the STEP's shells in order: the die face's "
            "are not one piece, or share curves with the beads'"
        )
    if beads and not keep_beads:
        gmsh.model.occ.remove([(2, s) for s in beads], recursive=True)
        gmsh.model.occ.synchronize()
    for tag, face in {**die, **(beads if keep_beads else {})}.items():
        gmsh.model.setEntityName(2, tag, face)
    return die, beads


def set_options(size, algorithm=8):
    """The meshing options of the module notes."""
    gmsh.option.setNumber("General.Terminal", 0)
    gmsh.option.setString("Geometry.OCCTargetUnit", "MM")
    gmsh.option.setNumber("Mesh.Algorithm", algorithm)
    gmsh.option.setNumber("Mesh.RecombineAll", 1)
    gmsh.option.setNumber("Mesh.RecombinationAlgorithm", 1)
    gmsh.option.setNumber("Mesh.SubdivisionAlgorithm", 0)
    gmsh.option.setNumber("Mesh.MeshSizeMin", size)
    gmsh.option.setNumber("Mesh.MeshSizeMax", size)
    gmsh.option.setNumber("Mesh.MeshSizeFromCurvature", 0)


def surface_elements(surface):
    """A surface's 2-D elements as lists of node tags, as gmsh orders them."""
    out = []
    types, _, conn = gmsh.model.mesh.getElements(2, surface)
    for kind, ids in zip(types, conn):
        if kind == 2:
            k = 3
        elif kind == 3:
            k = 4
        else:
            raise SystemExit(f"gmsh gave an element of type {kind}, not a triangle or quad")
        out.extend([int(t) for t in ids[i : i + k]] for i in range(0, len(ids), k))
    return out


def all_nodes():
    """Every mesh node: tag to position (mm)."""
    tags, coords, _ = gmsh.model.mesh.getNodes()
    coords = np.asarray(coords).reshape(-1, 3)
    return {int(t): coords[i] for i, t in enumerate(tags)}


def scaled_jacobians(c):
    """The scaled Jacobians of m elements of k corners each, c (m x k x 3), mirroring
    `quality.rs`'s `scaled_jacobian` (see the module notes)."""
    m, k, _ = c.shape
    if k == 4:
        n = np.cross(c[:, 2] - c[:, 0], c[:, 3] - c[:, 1])
    else:
        n = np.cross(c[:, 1] - c[:, 0], c[:, 2] - c[:, 0])
    length = np.linalg.norm(n, axis=1)
    n = np.divide(n, length[:, None], out=np.zeros_like(n), where=length[:, None] > 0)
    scale = 2.0 / np.sqrt(3.0) if k == 3 else 1.0
    least = np.full(m, np.inf)
    for i in range(k):
        a = c[:, (i + 1) % k] - c[:, i]
        b = c[:, (i + k - 1) % k] - c[:, i]
        ll = np.linalg.norm(a, axis=1) * np.linalg.norm(b, axis=1)
        bad = (ll <= sys.float_info.min) | (length == 0)
        sine = np.einsum("ij,ij->i", np.cross(a, b), n) / np.where(bad, 1.0, ll)
        sine = np.where(bad, -1.0, sine)
        least = np.minimum(least, np.minimum(sine * scale, 1.0))
    return least


def quality(elements, nodes):
    """`mesh_quality` of quality.rs over the elements, plus the quads' own SJ."""
    sj, quad_sj = [], np.zeros(0)
    min_angle, max_angle, max_aspect, max_side = 180.0, 0.0, 1.0, 0.0
    for k in (3, 4):
        group = [f for f in elements if len(f) == k]
        if not group:
            continue
        c = np.array([[nodes[t] for t in f] for f in group])
        j = scaled_jacobians(c)
        sj.append(j)
        if k == 4:
            quad_sj = j
        shortest, longest = np.full(len(c), np.inf), np.zeros(len(c))
        for i in range(k):
            a = c[:, (i + 1) % k] - c[:, i]
            b = c[:, (i + k - 1) % k] - c[:, i]
            la, lb = np.linalg.norm(a, axis=1), np.linalg.norm(b, axis=1)
            dot = np.einsum("ij,ij->i", a, b)
            cos = np.where(la * lb > 0, dot / np.where(la * lb > 0, la * lb, 1.0), 1.0)
            angle = np.degrees(np.arccos(np.clip(cos, -1.0, 1.0)))
            min_angle = min(min_angle, float(angle.min()))
            max_angle = max(max_angle, float(angle.max()))
            shortest, longest = np.minimum(shortest, la), np.maximum(longest, la)
        aspect = longest / np.maximum(shortest, sys.float_info.min)
        max_aspect = max(max_aspect, float(aspect.max()))
        max_side = max(max_side, float(longest.max()))
    sj = np.concatenate(sj) if sj else np.zeros(0)
    return {
        "quads": len(quad_sj),
        "triangles": len(sj) - len(quad_sj),
        "min_sj": float(sj.min()) if len(sj) else 0.0,
        "mean_sj": float(sj.mean()) if len(sj) else 0.0,
        "quad_min_sj": float(quad_sj.min()) if len(quad_sj) else 0.0,
        "quad_mean_sj": float(quad_sj.mean()) if len(quad_sj) else 0.0,
        "min_angle": min_angle,
        "max_angle": max_angle,
        "max_aspect": max_aspect,
        "max_side": max_side,
        "inverted": int((sj <= 0.0).sum()),
    }


def conformity(elements, nodes, surfaces):
    """Free and non-manifold element sides, the shell's rim and coincident nodes (see
    the module notes)."""
    uses = {}
    for f in elements:
        for i in range(len(f)):
            e = tuple(sorted((f[i], f[(i + 1) % len(f)])))
            uses[e] = uses.get(e, 0) + 1
    free = {e for e, n in uses.items() if n == 1}
    non_manifold = sum(1 for n in uses.values() if n > 2)
    count = {}
    for s in surfaces:
        for c in curves_of(s):
            count[c] = count.get(c, 0) + 1
    rim = set()
    for c, n in count.items():
        if n == 1:
            for kind, _, conn in zip(*gmsh.model.mesh.getElements(1, c)):
                if kind != 1:
                    raise SystemExit(f"gmsh gave a line element of type {kind}")
                rim |= {
                    tuple(sorted((int(a), int(b)))) for a, b in zip(conn[::2], conn[1::2])
                }
    used = sorted({t for f in elements for t in f})
    keys = {tuple(np.round(nodes[t] * 1e6).astype(np.int64)) for t in used}
    return {
        "free_edges": len(free),
        "non_manifold_edges": non_manifold,
        "boundary_edges": len(rim),
        "free_edges_inside": len(free - rim),
        "coincident_nodes": len(used) - len(keys),
    }


def write_obj(path, nodes, elements):
    """Writes the elements as OBJ (mm), nodes shared by tag."""
    used = sorted({t for f in elements for t in f})
    index = {t: i + 1 for i, t in enumerate(used)}
    lines = [f"v {nodes[t][0]:.9f} {nodes[t][1]:.9f} {nodes[t][2]:.9f}\n" for t in used]
    lines += ["f " + " ".join(str(index[t]) for t in f) + "\n" for f in elements]
    with open(path, "w") as out:
        out.writelines(lines)


def report(name_of, nodes, per_face):
    """The counts, quality and conformity of some faces' meshes."""
    elements = [f for s in name_of for f in per_face[s]]
    out = {"nodes": len({t for f in elements for t in f})}
    out.update(quality(elements, nodes))
    out.update(conformity(elements, nodes, list(name_of)))
    return out, elements


def main() -> None:
    args = [a for a in sys.argv[1:] if not a.startswith("--")]
    flags = [a for a in sys.argv[1:] if a.startswith("--")]
    keep_beads = "--beads" in flags
    algorithm = 8
    for flag in flags:
        if flag.startswith("--algorithm="):
            algorithm = int(flag.split("=", 1)[1])
        elif flag != "--beads":
            raise SystemExit(f"unknown option {flag}\n{__doc__}")
    if len(args) != 3:
        raise SystemExit(__doc__)
    source, size, target = args[0], float(args[1]), args[2]
    gmsh.initialize(readConfigFiles=False)
    set_options(size, algorithm)
    gmsh.model.add("die_face")
    start = time.perf_counter()
    die, beads = import_die_face(source, keep_beads)
    import_s = time.perf_counter() - start
    start = time.perf_counter()
    gmsh.model.mesh.generate(2)
    generate_s = time.perf_counter() - start
    nodes = all_nodes()
    meshed = {**die, **(beads if keep_beads else {})}
    per_face = {s: surface_elements(s) for s in meshed}
    whole, elements = report(die, nodes, per_face)
    print("| face | quads | triangles | min SJ | mean SJ | longest side |", file=sys.stderr)
    print("|---|---:|---:|---:|---:|---:|", file=sys.stderr)
    for s, name in meshed.items():
        q = quality(per_face[s], nodes)
        print(
            f"| {name} | {q['quads']} | {q['triangles']} | {q['min_sj']:.3f} "
            f"| {q['mean_sj']:.3f} | {q['max_side']:.1f} mm |",
            file=sys.stderr,
        )
    result = {"size": size, "algorithm": algorithm, **whole}
    result.update(import_s=import_s, generate_s=generate_s)
    if keep_beads and beads:
        result["beads"], _ = report(beads, nodes, per_face)
    write_obj(target, nodes, elements)
    gmsh.finalize()
    result["script_s"] = time.perf_counter() - SCRIPT_START
    print(json.dumps(result))


if __name__ == "__main__":
    main()
