"""MeshLab's hole closing on a mesh, timed: the peer of dieface's `fill_holes` in
BENCHMARKS.md (issue 17). Run by the `holes` bench binary:

    python3 bench/reference/meshlab_close_holes.py IN.obj OUT.obj RUNS MAXHOLESIZE [refine]

Loads IN.obj once per run (not timed), times `meshing_close_holes` alone (every hole
of at most MAXHOLESIZE edges: the bench passes one more than the largest hole's, below
the outer edge's, so MeshLab keeps the outer edge as dieface does; MeshLab's own
defaults otherwise, `selfintersection` on), and writes the last run's result to
OUT.obj. With
`refine`, MeshLab also refines the new faces to the mesh's mean edge length
(`refinehole`). Prints the median time in milliseconds and the face counts.
"""

import statistics
import sys
import time

import pymeshlab


def main() -> None:
    source, target, runs = sys.argv[1], sys.argv[2], int(sys.argv[3])
    largest = int(sys.argv[4])
    refine = len(sys.argv) > 5 and sys.argv[5] == "refine"
    times = []
    ms = None
    for _ in range(runs):
        ms = pymeshlab.MeshSet()
        ms.load_new_mesh(source)
        before = ms.current_mesh().face_number()
        options = {"maxholesize": largest}
        if refine:
            options["refinehole"] = True
        start = time.perf_counter()
        ms.meshing_close_holes(**options)
        times.append((time.perf_counter() - start) * 1e3)
    after = ms.current_mesh().face_number()
    ms.save_current_mesh(target, save_vertex_normal=False)
    print(f"{statistics.median(times):.3f} {before} {after}")


if __name__ == "__main__":
    main()
