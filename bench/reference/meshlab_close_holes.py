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

    python3 bench/reference/meshlab_close_holes.py IN.obj OUT.obj serve MAXHOLESIZE

runs the same filter once for each line `run` read from standard input, printing each
run's time in milliseconds on its own line as soon as it is done, and writes the last
run's result to OUT.obj at the end of the input: the bench so times MeshLab and dieface
turn about, run by run, so both meet the machine in the same state.
"""

import statistics
import sys
import time

import pymeshlab


def closed(source: str, options: dict) -> tuple[pymeshlab.MeshSet, float, int]:
    """The mesh at `source` loaded (not timed) and its holes closed: the mesh set,
    the filter's time in milliseconds and the faces before it."""
    ms = pymeshlab.MeshSet()
    ms.load_new_mesh(source)
    before = ms.current_mesh().face_number()
    start = time.perf_counter()
    ms.meshing_close_holes(**options)
    return ms, (time.perf_counter() - start) * 1e3, before


def main() -> None:
    source, target = sys.argv[1], sys.argv[2]
    largest = int(sys.argv[4])
    refine = len(sys.argv) > 5 and sys.argv[5] == "refine"
    options = {"maxholesize": largest}
    if refine:
        options["refinehole"] = True
    ms = None
    if sys.argv[3] == "serve":
        for line in sys.stdin:
            if line.strip() != "run":
                continue
            ms, ms_time, _ = closed(source, options)
            print(f"{ms_time:.3f}", flush=True)
        if ms is not None:
            ms.save_current_mesh(target, save_vertex_normal=False)
        return
    times = []
    before = 0
    for _ in range(int(sys.argv[3])):
        ms, ms_time, before = closed(source, options)
        times.append(ms_time)
    after = ms.current_mesh().face_number()
    ms.save_current_mesh(target, save_vertex_normal=False)
    print(f"{statistics.median(times):.3f} {before} {after}")


if __name__ == "__main__":
    main()
