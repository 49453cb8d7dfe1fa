#!/usr/bin/env python3
"""Reads dieface's STEP export of both examples with OpenCascade and reports what a
die-machining CAM system would see: shells, validity, free boundaries, area.

Usage (from the crate root):

    pip install -r tests/reference/requirements.txt
    python3 tests/reference/step_reference.py            # rewrites tests/data/step_reference.json
    python3 tests/reference/step_reference.py --stdout   # prints it instead

The script builds each example with `cargo run --release --bin dieface -- build EXAMPLE -o X.step`
(or with the binary given by `--dieface PATH`) into a temporary folder, reads the file
with `STEPControl_Reader`, and per shell (in file order: `die_face`, then `beads`)
records:

* `faces`: the number of faces;
* `valid`: `BRepCheck_Analyzer(shell).IsValid()`;
* `free_closed` / `free_open`: the free boundary wires found by
  `ShapeAnalysis_FreeBounds` (edges used by one face only), each as its length (mm,
  `GProp` linear properties), longest first;
* `area`: `BRepGProp.SurfaceProperties` with a relative accuracy of 1e-9 (mm²).

Floats are rounded to 12 significant digits, so reruns on the same geometry give the
same file. `tests/step.rs` compares the committed result with what dieface computes
now (face counts, area within 1e-6 relative, one closed free wire for the die face as
long as the binder's outer edge).
"""

import json
import os
import subprocess
import sys
import tempfile
from importlib import metadata

from OCP.BRepCheck import BRepCheck_Analyzer
from OCP.BRepGProp import BRepGProp
from OCP.GProp import GProp_GProps
from OCP.IFSelect import IFSelect_RetDone
from OCP.ShapeAnalysis import ShapeAnalysis_FreeBounds
from OCP.STEPControl import STEPControl_Reader
from OCP.TopAbs import TopAbs_FACE, TopAbs_SHELL, TopAbs_WIRE
from OCP.TopExp import TopExp_Explorer

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
EXAMPLES = ["examples/fender/fender.die", "examples/door_outer/door_outer.die"]
OUT = os.path.join(ROOT, "tests", "data", "step_reference.json")


def sig(x, digits=12):
    return float(f"{x:.{digits}g}")


def count(shape, kind):
    n = 0
    exp = TopExp_Explorer(shape, kind)
    while exp.More():
        n += 1
        exp.Next()
    return n


def wire_lengths(compound):
    out = []
    exp = TopExp_Explorer(compound, TopAbs_WIRE)
    while exp.More():
        props = GProp_GProps()
        BRepGProp.LinearProperties_s(exp.Current(), props)
        out.append(sig(props.Mass()))
        exp.Next()
    return sorted(out, reverse=True)


def shell_report(shell):
    props = GProp_GProps()
    BRepGProp.SurfaceProperties_s(shell, props, 1e-9)
    free = ShapeAnalysis_FreeBounds(shell, False, False)
    return {
        "faces": count(shell, TopAbs_FACE),
        "valid": bool(BRepCheck_Analyzer(shell).IsValid()),
        "free_closed": wire_lengths(free.GetClosedWires()),
        "free_open": wire_lengths(free.GetOpenWires()),
        "area": sig(props.Mass()),
    }


def read(path):
    reader = STEPControl_Reader()
    if reader.ReadFile(path) != IFSelect_RetDone:
        raise SystemExit(f"OpenCascade cannot read {path}")
    reader.TransferRoots()
    shape = reader.OneShape()
    shells = []
    exp = TopExp_Explorer(shape, TopAbs_SHELL)
    while exp.More():
        shells.append(shell_report(exp.Current()))
        exp.Next()
    return {
        "shells": shells,
        "valid": bool(BRepCheck_Analyzer(shape).IsValid()),
    }


def build(dieface, example, out):
    cmd = (dieface + ["build", example, "-o", out]) if dieface else (
        ["cargo", "run", "--quiet", "--release", "--bin", "dieface", "--", "build", example, "-o", out]
    )
    subprocess.run(cmd, cwd=ROOT, check=True, stdout=subprocess.DEVNULL)


def main():
    args = sys.argv[1:]
    dieface = None
    if "--dieface" in args:
        dieface = [os.path.abspath(args[args.index("--dieface") + 1])]
    result = {"ocp": metadata.version("cadquery-ocp"), "examples": {}}
    with tempfile.TemporaryDirectory() as tmp:
        for ex in EXAMPLES:
            name = os.path.splitext(os.path.basename(ex))[0]
            path = os.path.join(tmp, name + ".step")
            build(dieface, ex, path)
            result["examples"][name] = read(path)
    text = json.dumps(result, indent=2, sort_keys=True) + "\n"
    if "--stdout" in args:
        sys.stdout.write(text)
    else:
        with open(OUT, "w") as f:
            f.write(text)


if __name__ == "__main__":
    main()
