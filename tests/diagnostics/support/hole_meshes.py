"""Writes the small meshes the hole-filling corpus entries read (tests/diagnostics/29x):
a plate with a square hole, the same with a doubled fin on an edge at the hole, with a
face beside the hole wound the other way, a plate whose one hole is a zero-area
T-junction crack, and a plate folded into a hairpin with a hole round the fold.

    python3 tests/diagnostics/support/hole_meshes.py
"""

import math
from pathlib import Path

HERE = Path(__file__).parent


def write(name, points, faces, note):
    lines = [f"# {note}", "# Written by hole_meshes.py."]
    lines += [f"v {x:.6f} {y:.6f} {z:.6f}" for x, y, z in points]
    lines += ["f " + " ".join(str(i + 1) for i in f) for f in faces]
    (HERE / name).write_text("\n".join(lines) + "\n")


def grid(n, step, skip=()):
    """An n x n grid of step-mm cells, each two counter-clockwise triangles, the cells
    in `skip` left out."""
    points = [(i * step, j * step, 0.0) for j in range(n + 1) for i in range(n + 1)]
    node = lambda i, j: j * (n + 1) + i
    faces = []
    for j in range(n):
        for i in range(n):
            if (i, j) in skip:
                continue
            a, b, c, d = node(i, j), node(i + 1, j), node(i + 1, j + 1), node(i, j + 1)
            faces += [(a, b, c), (a, c, d)]
    return points, faces, node


def main():
    hole = {(2, 2), (3, 2), (2, 3), (3, 3)}
    points, faces, node = grid(6, 10.0, hole)
    write("plate_with_hole.obj", points, faces,
          "A 60 x 60 mm plate of 10 mm cells with a 20 x 20 mm hole at (30, 30).")

    # A doubled fin (two triangles back to back) standing on the edge from (10, 20) to
    # the hole's corner (20, 20): that edge joins four faces.
    fin = list(faces)
    points_fin = list(points) + [(15.0, 20.0, 8.0)]
    top = len(points_fin) - 1
    a, b = node(1, 2), node(2, 2)
    fin += [(a, b, top), (b, a, top)]
    write("hole_fin.obj", points_fin, fin,
          "plate_with_hole.obj with a doubled fin on an edge at the hole's corner (20, 20).")

    # The face beside the hole at (15, 25) wound the other way.
    flipped = [f if k != faces.index((node(1, 2), node(2, 2), node(2, 3)))
               else (f[0], f[2], f[1]) for k, f in enumerate(faces)]
    write("hole_flipped.obj", points, flipped,
          "plate_with_hole.obj with the face beside the hole at (15, 25) wound the other way.")

    # One cell's diagonal split on one side only: a T-junction crack, a free loop of
    # three nodes in a line.
    points_t, faces_t, node_t = grid(3, 10.0, {(1, 1)})
    mid = len(points_t)
    points_t.append((15.0, 15.0, 0.0))
    a, b, c, d = node_t(1, 1), node_t(2, 1), node_t(2, 2), node_t(1, 2)
    faces_t += [(a, b, mid), (mid, b, c), (a, c, d)]
    write("hole_t_junction.obj", points_t, faces_t,
          "A 30 x 30 mm plate whose middle cell is split at (15, 15) on one side of its "
          "diagonal only: a crack of no area.")

    # A 40 mm wide strip, 50 mm along x, folded back over itself at x = 50 (a 160 deg
    # turn), a hole 16 mm across round the fold.
    step, rows = 5.0, 8
    turn = math.radians(160.0)
    along = [k * step for k in range(-10, 11)]  # < 0 first leg, > 0 second
    def place(s, y):
        if s <= 0:
            return (50.0 + s, y, 0.0)
        return (50.0 + s * math.cos(turn), y, s * math.sin(turn))
    pts, fs = [], []
    idx = {}
    for j in range(rows + 1):
        for k, s in enumerate(along):
            idx[(k, j)] = len(pts)
            pts.append(place(s, j * step))
    for j in range(rows):
        for k in range(len(along) - 1):
            s_mid, y_mid = (along[k] + along[k + 1]) / 2, (j + 0.5) * step
            if math.hypot(s_mid, y_mid - 20.0) < 8.0:
                continue
            a, b, c, d = idx[(k, j)], idx[(k + 1, j)], idx[(k + 1, j + 1)], idx[(k, j + 1)]
            fs += [(a, b, c), (a, c, d)]
    write("hole_hairpin.obj", pts, fs,
          "A strip folded back over itself at x = 50 (160 deg), a hole round the fold at (50, 20).")


main()
