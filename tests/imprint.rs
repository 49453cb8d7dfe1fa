//! A face imprinted onto a shell from above (`geom::imprint`): a bead's skin set into
//! the binder faces it stands on. Checked on flat faces where the answer is known: the
//! footprint leaves a hole in the one face it lies in, a notch in each face whose seam
//! it crosses, and cuts a face it spans into two; the shell stays oriented; the
//! imprinted shell meshes into one conforming mesh; a footprint off the shell or over
//! a whole face is refused.

use std::collections::BTreeMap;

use dieface::geom::imprint::{imprint, ImprintError};
use dieface::geom::mesh::quad::shell::quad_mesh_shell;
use dieface::geom::mesh::quad::surface::SurfaceMeshOptions;
use dieface::geom::sew::{sew, Face, Shape, Shell};
use dieface::geom::NurbsSurface;
use glam::DVec3;

/// The bilinear patch of the plane z = 0 over [x0, x1] x [y0, y1], its normal up
/// (`flip`: the same patch parametrized with its normal down).
fn flat(x0: f64, x1: f64, y0: f64, y1: f64, flip: bool) -> NurbsSurface {
    let k = vec![0.0, 0.0, 1.0, 1.0];
    let (a, b) = (DVec3::new(x0, y0, 0.0), DVec3::new(x0, y1, 0.0));
    let (c, d) = (DVec3::new(x1, y0, 0.0), DVec3::new(x1, y1, 0.0));
    let points = if flip {
        vec![vec![a, c], vec![b, d]]
    } else {
        vec![vec![a, b], vec![c, d]]
    };
    NurbsSurface::new(1, 1, k.clone(), k, points).expect("a bilinear patch")
}

fn patch(name: &str, s: NurbsSurface) -> Face {
    Face {
        name: name.into(),
        shape: Shape::Patch(s),
    }
}

fn shell_of(faces: &[(&str, [f64; 4])]) -> Shell {
    sew(
        faces
            .iter()
            .map(|(n, [x0, x1, y0, y1])| patch(n, flat(*x0, *x1, *y0, *y1, false)))
            .collect(),
        0.01,
    )
    .expect("the faces sew")
}

/// Every edge used at most twice, a shared edge once each way, and the free edges'
/// length.
fn check_oriented(shell: &Shell) -> f64 {
    let mut uses: BTreeMap<usize, Vec<bool>> = BTreeMap::new();
    for f in &shell.faces {
        for &(e, d) in f.loop_edges() {
            uses.entry(e).or_default().push(d);
        }
    }
    let mut free = 0.0;
    for (e, d) in &uses {
        assert!(d.len() <= 2, "edge {e} used {} times", d.len());
        if d.len() == 2 {
            assert_ne!(d[0], d[1], "edge {e} used the same way twice");
        } else {
            free += shell.edges[*e].curve.length();
        }
    }
    free
}

/// Each loop closes: every edge ends where the next starts.
fn check_loops_close(shell: &Shell) {
    for f in &shell.faces {
        for l in std::iter::once(&f.bound).chain(&f.holes) {
            for k in 0..l.len() {
                let ends = |(e, d): (usize, bool)| {
                    let edge = &shell.edges[e];
                    if d {
                        (edge.start, edge.end)
                    } else {
                        (edge.end, edge.start)
                    }
                };
                assert_eq!(
                    ends(l[k]).1,
                    ends(l[(k + 1) % l.len()]).0,
                    "`{}`: a loop that does not close",
                    f.face.name
                );
            }
        }
    }
}

/// The shell meshed at `size`: every element edge used at most twice, once each way,
/// and the free element edges as long as the shell's free edges.
fn check_mesh(shell: &Shell, size: f64, free_length: f64) {
    let sizes = vec![size; shell.faces.len()];
    let meshed = quad_mesh_shell(shell, &sizes, &SurfaceMeshOptions::at_size(size))
        .expect("the imprinted shell meshes");
    let mesh = meshed.whole().expect("one mesh");
    let mut uses: BTreeMap<(u32, u32), Vec<bool>> = BTreeMap::new();
    for f in mesh.faces() {
        let ids = f.indices();
        for i in 0..ids.len() {
            let (a, b) = (ids[i], ids[(i + 1) % ids.len()]);
            uses.entry((a.min(b), a.max(b))).or_default().push(a < b);
        }
    }
    let mut free = 0.0;
    for ((a, b), d) in &uses {
        assert!(d.len() <= 2);
        if d.len() == 2 {
            assert_ne!(d[0], d[1], "an element edge used the same way twice");
        } else {
            free += mesh.positions()[*a as usize].distance(mesh.positions()[*b as usize]);
        }
    }
    assert!(
        (free - free_length).abs() < 1e-6 * free_length,
        "free element edges {free} mm against the shell's {free_length} mm"
    );
}

#[test]
fn a_footprint_inside_one_face_leaves_a_hole_in_it() {
    let mut shell = shell_of(&[("binder", [0.0, 200.0, 0.0, 100.0])]);
    let done = imprint(
        &mut shell,
        patch("bead", flat(50.0, 150.0, 40.0, 60.0, false)),
        0.01,
    )
    .expect("imprinted");
    assert_eq!(done.face, 1);
    assert!(done.split.is_empty());
    assert_eq!(shell.faces[0].holes.len(), 1, "the binder has a hole");
    assert_eq!(shell.faces[0].bound.len(), 4, "its outer loop as it was");
    assert_eq!(shell.faces[1].holes.len(), 0);
    assert!(!shell.faces[1].reversed);
    let free = check_oriented(&shell);
    assert!((free - 600.0).abs() < 1e-9, "free edges {free}");
    check_loops_close(&shell);
    check_mesh(&shell, 10.0, 600.0);
}

#[test]
fn a_footprint_across_a_seam_notches_both_faces() {
    let mut shell = shell_of(&[
        ("left", [0.0, 100.0, 0.0, 100.0]),
        ("right", [100.0, 200.0, 0.0, 100.0]),
    ]);
    let before = shell.edges.len();
    let done = imprint(
        &mut shell,
        patch("bead", flat(50.0, 150.0, 40.0, 60.0, false)),
        0.01,
    )
    .expect("imprinted");
    assert_eq!(done.face, 2);
    assert!(done.split.is_empty());
    // The seam is cut in three at y = 40 and 60; the bead's sides along x at x = 100.
    let seam_pieces = shell
        .edges
        .iter()
        .filter(|e| {
            let (a, b) = (e.curve.start_point(), e.curve.end_point());
            (a.x - 100.0).abs() < 1e-9 && (b.x - 100.0).abs() < 1e-9
        })
        .count();
    assert_eq!(seam_pieces, 3);
    assert_eq!(shell.edges.len(), before + 2 + 6);
    assert!(shell.faces.iter().all(|f| f.holes.is_empty()));
    assert_eq!(shell.faces[2].bound.len(), 6, "the footprint in six pieces");
    // The middle third of the seam is under the bead: used by no face.
    let uses = shell.edge_uses();
    assert_eq!(uses.iter().filter(|&&u| u == 0).count(), 1);
    let free = check_oriented(&shell);
    assert!((free - 600.0).abs() < 1e-9, "free edges {free}");
    check_loops_close(&shell);
    check_mesh(&shell, 10.0, 600.0);
}

#[test]
fn a_footprint_spanning_a_face_cuts_it_in_two() {
    let mut shell = shell_of(&[
        ("low", [0.0, 100.0, 0.0, 100.0]),
        ("middle", [0.0, 100.0, 100.0, 200.0]),
        ("high", [0.0, 100.0, 200.0, 300.0]),
    ]);
    let done = imprint(
        &mut shell,
        patch("bead", flat(40.0, 60.0, 50.0, 250.0, false)),
        0.01,
    )
    .expect("imprinted");
    assert_eq!(done.split, vec![(3, 1)], "the middle face cut in two");
    assert_eq!(done.face, 4);
    assert_eq!(shell.faces[3].face.name, "middle");
    let area = |f: usize| -> f64 {
        let l = &shell.faces[f].bound;
        let p: Vec<DVec3> = l
            .iter()
            .map(|&(e, d)| {
                let edge = &shell.edges[e];
                shell.vertices[if d { edge.start } else { edge.end }]
            })
            .collect();
        (0..p.len())
            .map(|i| p[i].cross(p[(i + 1) % p.len()]).z)
            .sum::<f64>()
            * 0.5
    };
    // Both halves 40 mm wide (their straight edges' corners give the exact area).
    assert!((area(1) - 4000.0).abs() < 1e-6, "{}", area(1));
    assert!((area(3) - 4000.0).abs() < 1e-6, "{}", area(3));
    let free = check_oriented(&shell);
    assert!((free - 800.0).abs() < 1e-9, "free edges {free}");
    check_loops_close(&shell);
    check_mesh(&shell, 10.0, 800.0);
}

#[test]
fn a_footprint_parametrized_downwards_is_turned_to_match_the_faces_under_it() {
    let mut shell = shell_of(&[
        ("left", [0.0, 100.0, 0.0, 100.0]),
        ("right", [100.0, 200.0, 0.0, 100.0]),
    ]);
    let done = imprint(
        &mut shell,
        patch("bead", flat(50.0, 150.0, 40.0, 60.0, true)),
        0.01,
    )
    .expect("imprinted");
    assert!(
        shell.faces[done.face].reversed,
        "the bead's face turned over"
    );
    check_oriented(&shell);
    check_loops_close(&shell);
    check_mesh(&shell, 10.0, 600.0);
}

#[test]
fn a_footprint_off_the_shell_or_over_a_whole_face_is_refused() {
    let mut shell = shell_of(&[("binder", [0.0, 200.0, 0.0, 100.0])]);
    let before = shell.clone();
    let err = imprint(
        &mut shell,
        patch("bead", flat(150.0, 250.0, 40.0, 60.0, false)),
        0.01,
    )
    .expect_err("it runs off the binder");
    match err {
        ImprintError::OffShell { at } => assert!((at.x - 200.0).abs() < 1e-6, "{at}"),
        other => panic!("{other}"),
    }
    assert_eq!(shell, before, "the shell is left as it was");
    // A 3 x 3 grid of faces, the footprint over the whole middle one.
    let mut cells = Vec::new();
    let names = ["a", "b", "c", "d", "e", "f", "g", "h", "i"];
    for (k, name) in names.iter().enumerate() {
        let (i, j) = ((k % 3) as f64, (k / 3) as f64);
        cells.push((
            *name,
            [100.0 * i, 100.0 * (i + 1.0), 100.0 * j, 100.0 * (j + 1.0)],
        ));
    }
    let mut grid = shell_of(&cells);
    let err = imprint(
        &mut grid,
        patch("bead", flat(90.0, 210.0, 90.0, 210.0, false)),
        0.01,
    )
    .expect_err("it covers the middle face");
    assert_eq!(err, ImprintError::Covers { name: "e".into() });
    // Through a corner of the faces under it.
    let mut two = shell_of(&[
        ("left", [0.0, 100.0, 0.0, 100.0]),
        ("right", [100.0, 200.0, 0.0, 100.0]),
    ]);
    let err = imprint(
        &mut two,
        patch("bead", flat(50.0, 150.0, 0.0, 50.0, false)),
        0.01,
    )
    .expect_err("its edge runs along the binder's edge");
    assert!(
        matches!(
            err,
            ImprintError::ThroughCorner { .. } | ImprintError::Tangled { .. }
        ),
        "{err}"
    );
}

#[test]
fn a_hole_left_by_an_imprint_is_written_to_step_as_an_inner_bound() {
    use dieface::export::step::{encode_step, StepModel};
    let mut shell = shell_of(&[("binder", [0.0, 200.0, 0.0, 100.0])]);
    imprint(
        &mut shell,
        patch("bead", flat(50.0, 150.0, 40.0, 60.0, false)),
        0.01,
    )
    .expect("imprinted");
    let text = String::from_utf8(encode_step(&StepModel {
        name: "imprint".into(),
        shells: vec![("die_face".into(), &shell)],
        uncertainty: 0.01,
    }))
    .expect("STEP is text");
    assert_eq!(text.matches("FACE_OUTER_BOUND(").count(), 2, "two faces");
    assert_eq!(text.matches("FACE_BOUND(").count(), 1, "the binder's hole");
    // The binder's face lists both bounds.
    let binder = text
        .lines()
        .find(|l| l.contains("ADVANCED_FACE('binder'"))
        .expect("the binder's face");
    let bounds = binder
        .split("'binder',(")
        .nth(1)
        .and_then(|rest| rest.split(')').next())
        .expect("its bounds");
    assert_eq!(bounds.split(',').count(), 2, "{binder}");
}
