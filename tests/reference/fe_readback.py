#!/usr/bin/env python3
"""Reads dieface's FE decks back with independent readers and prints what they found.

Usage: python3 tests/reference/fe_readback.py DECK.k DECK.bdf

`tests/fe_decks.rs` writes both decks of one model and compares this script's JSON
(stdout) with the model it wrote:

* the LS-DYNA deck (`.k`) read by `lsdyna_mesh_reader` (nodes, shell elements with their
  part ids);
* the Nastran deck (`.bdf`) read by pyNastran (`read_bdf`: nodes, elements, PSHELL,
  MAT1; with `SOL 101` and `CEND` put ahead of the file's text, as the analysis setup
  would, since pyNastran reads a `BEGIN BULK` only after executive and case control)
  and by meshio (nodes, cells, the cells' property ids);
* what neither reader exposes, parsed by this script from the `.k` in LS-DYNA's fixed
  columns, and said so under `parsed_by_this_script`: `lsdyna_mesh_reader` reads only
  nodes and elements, so `*PART`, `*SECTION_SHELL`, `*MAT_RIGID`, `*SET_NODE_LIST`,
  `*DEFINE_CURVE` and `*CONTACT_DRAWBEAD` are read here; and the Nastran draw bead
  comments (Nastran has no draw bead card; no reader keeps them).

A missing module exits with status 3 and a message naming it (scripts/test installs
tests/reference/fe-requirements.txt); a reader's failure is an exception (status 1).
"""

import importlib
import io
import json
import sys

MISSING_MODULE = 3


def need(name):
    """The module `name`, or exit with status 3 saying how to install it."""
    try:
        return importlib.import_module(name)
    except ImportError as error:
        print(
            f"fe_readback.py: the Python module {name!r} is missing ({error}); "
            "run scripts/test, which installs tests/reference/fe-requirements.txt",
            file=sys.stderr,
        )
        sys.exit(MISSING_MODULE)


def version(module):
    return getattr(module, "__version__", "unknown")


# ---------------------------------------------------------------------------------
# LS-DYNA


def read_lsdyna(path):
    """Nodes and shells as lsdyna_mesh_reader reads them."""
    reader = need("lsdyna_mesh_reader")
    np = need("numpy")
    deck = reader.Deck(path)
    nodes = {}
    for section in deck.node_sections:
        for nid, xyz in zip(section.nid.tolist(), section.coordinates.tolist()):
            nodes[str(nid)] = xyz
    elements = {}
    for section in deck.element_shell_sections:
        offsets = section.node_id_offsets
        split = np.split(section.node_ids, offsets[1:-1])
        for eid, pid, conn in zip(section.eid.tolist(), section.pid.tolist(), split):
            elements[str(eid)] = {"part": pid, "nodes": conn.tolist()}
    element_counts = {"quad": 0, "triangle": 0, "other": 0}
    part_counts = {}
    for e in elements.values():
        conn = e["nodes"]
        # LS-DYNA takes a triangle as a quad whose fourth node repeats its third.
        if len(conn) == 3 or (len(conn) == 4 and conn[2] == conn[3]):
            kind = "triangle"
        elif len(conn) == 4:
            kind = "quad"
        else:
            kind = "other"
        element_counts[kind] += 1
        key = str(e["part"])
        part_counts[key] = part_counts.get(key, 0) + 1
    return {
        "reader": f"lsdyna_mesh_reader {version(reader)}",
        "node_count": len(nodes),
        "nodes": nodes,
        "element_counts": element_counts,
        "part_element_counts": part_counts,
        "elements": elements,
        "parsed_by_this_script": parse_keywords(path),
    }


def keyword_blocks(path):
    """(keyword, data lines) for each keyword of the deck, comment lines left out."""
    blocks = []
    with open(path, encoding="ascii") as f:
        for raw in f:
            line = raw.rstrip("\n")
            if line.startswith("*"):
                blocks.append((line.strip().upper(), []))
            elif line.startswith("$") or not blocks:
                continue
            else:
                blocks[-1][1].append(line)
    return blocks


def fields(line, width):
    """A card's fixed-width fields, stripped."""
    return [line[i : i + width].strip() for i in range(0, len(line), width)]


def ints(line, width=10):
    return [int(f) for f in fields(line, width) if f]


def floats(line, width=10):
    return [float(f) for f in fields(line, width) if f]


def parse_keywords(path):
    """What lsdyna_mesh_reader does not read, from LS-DYNA's fixed columns."""
    parts, sections, materials = {}, {}, {}
    node_sets, curves, drawbeads = {}, {}, []
    for keyword, lines in keyword_blocks(path):
        if keyword == "*PART":
            pid, secid, mid = ints(lines[1])[:3]
            parts[str(pid)] = {"heading": lines[0].strip(), "secid": secid, "mid": mid}
        elif keyword == "*SECTION_SHELL":
            head = fields(lines[0], 10)
            sections[head[0]] = {"elform": int(head[1]), "thickness": floats(lines[1])}
        elif keyword == "*MAT_RIGID":
            mid, ro, e, pr = fields(lines[0], 10)[:4]
            materials[mid] = {"ro": float(ro), "e": float(e), "pr": float(pr)}
        elif keyword == "*SET_NODE_LIST":
            sid = ints(lines[0])[0]
            node_sets[str(sid)] = [n for line in lines[1:] for n in ints(line)]
        elif keyword == "*DEFINE_CURVE":
            lcid = ints(lines[0])[0]
            curves[str(lcid)] = [floats(line, 20) for line in lines[1:]]
        elif keyword == "*CONTACT_DRAWBEAD":
            ssid, msid, sstyp, mstyp = ints(lines[0])[:4]
            card4 = fields(lines[3], 10)
            drawbeads.append(
                {
                    "ssid": ssid,
                    "msid": msid,
                    "sstyp": sstyp,
                    "mstyp": mstyp,
                    "cards": len(lines),
                    "lcidrf": int(card4[0]),
                    "lcidnf": int(card4[1]),
                    "dbdth": float(card4[2]),
                    "dfscl": float(card4[3]),
                }
            )
    return {
        "why": "lsdyna_mesh_reader reads nodes and elements only",
        "keywords": [k for k, _ in keyword_blocks(path)],
        "parts": parts,
        "sections": sections,
        "materials": materials,
        "node_sets": node_sets,
        "curves": curves,
        "drawbeads": drawbeads,
    }


# ---------------------------------------------------------------------------------
# Nastran


def read_pynastran(path):
    """Nodes, shells, PSHELL and MAT1 as pyNastran reads them."""
    pynastran = need("pyNastran")
    bdf = need("pyNastran.bdf.bdf")
    # The deck is bulk data from BEGIN BULK on; the analysis setup writes its executive
    # and case control ahead of it, and pyNastran reads a BEGIN BULK only after them, so
    # the smallest ones are put ahead here (in memory; the file is read as written).
    with open(path, encoding="ascii") as f:
        text = "SOL 101\nCEND\n" + f.read()
    model = bdf.read_bdf(io.StringIO(text), xref=False, punch=False, debug=None)
    nodes = {str(nid): [float(c) for c in node.xyz] for nid, node in model.nodes.items()}
    elements, counts, part_counts = {}, {}, {}
    for eid, element in model.elements.items():
        elements[str(eid)] = {
            "type": element.type,
            "property": element.pid,
            "nodes": list(element.node_ids),
        }
        counts[element.type] = counts.get(element.type, 0) + 1
        key = str(element.pid)
        part_counts[key] = part_counts.get(key, 0) + 1
    properties = {
        str(pid): {"type": p.type, "t": p.t, "mid1": p.mid1, "mid2": p.mid2}
        for pid, p in model.properties.items()
    }
    materials = {
        str(mid): {"type": m.type, "e": m.e, "nu": m.nu, "rho": m.rho}
        for mid, m in model.materials.items()
    }
    return {
        "reader": f"pyNastran {version(pynastran)}",
        "node_count": len(nodes),
        "nodes": nodes,
        "element_counts": counts,
        "part_element_counts": part_counts,
        "elements": elements,
        "properties": properties,
        "materials": materials,
        "unknown_cards": sorted(model.card_count.keys() - KNOWN_CARDS),
        "parsed_by_this_script": {
            "why": "Nastran has no draw bead card; the beads are comments",
            "beads": bead_comments(path),
        },
    }


KNOWN_CARDS = {"GRID", "CQUAD4", "CTRIA3", "PSHELL", "MAT1", "ENDDATA"}


def bead_comments(path):
    """Each `$ draw bead` comment block: its title, force (None when the block says no
    force was given) and the GRID ids listed after `$ nodes along the bead`."""
    beads = []
    listing = False
    with open(path, encoding="ascii") as f:
        for raw in f:
            line = raw.rstrip("\n")
            numbers = line[1:].split()
            if line.startswith("$ draw bead "):
                beads.append({"title": line[2:], "force": None, "nodes": []})
                listing = False
            elif not beads:
                continue
            elif line.startswith("$ restraining force: "):
                beads[-1]["force"] = float(line.split(":")[1].split()[0])
            elif line.startswith("$ nodes along the bead"):
                listing = True
            elif listing and line.startswith("$") and numbers and all(
                n.isdigit() for n in numbers
            ):
                beads[-1]["nodes"].extend(int(n) for n in numbers)
            else:
                listing = False
    return beads


def read_meshio(path):
    """Points and cells as meshio's Nastran reader reads them."""
    meshio = need("meshio")
    mesh = meshio.read(path, file_format="nastran")
    cells = {}
    refs = mesh.cell_data.get("nastran:ref", [None] * len(mesh.cells))
    for block, ids, ref in zip(mesh.cells, mesh.cells_id, refs):
        entry = cells.setdefault(block.type, {"ids": [], "nodes": [], "property": []})
        entry["ids"].extend(ids.tolist())
        entry["nodes"].extend(
            [[int(mesh.points_id[i]) for i in cell] for cell in block.data.tolist()]
        )
        entry["property"].extend(ref.tolist() if ref is not None else [])
    return {
        "reader": f"meshio {version(meshio)}",
        "node_count": len(mesh.points),
        "nodes": {
            str(nid): xyz for nid, xyz in zip(mesh.points_id.tolist(), mesh.points.tolist())
        },
        "cell_counts": {t: len(c["ids"]) for t, c in cells.items()},
        "cells": cells,
    }


def main(argv):
    if len(argv) != 3:
        print(__doc__, file=sys.stderr)
        return 2
    k_path, bdf_path = argv[1], argv[2]
    out = {
        "lsdyna": read_lsdyna(k_path),
        "nastran": read_pynastran(bdf_path),
        "meshio": read_meshio(bdf_path),
    }
    json.dump(out, sys.stdout, indent=1, sort_keys=True)
    sys.stdout.write("\n")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
