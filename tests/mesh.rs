//! Tests of the mesh kernel: construction and validation, geometry, triangulation,
//! welding, merging, and the half-edge topology (adjacency, free-edge loops, bowtie
//! vertices, non-manifold edges, dihedral angles, orientation, Euler characteristic).

use dieface::geom::error::GeomError;
use dieface::geom::mesh::holes::loops::free_edges;
use dieface::geom::mesh::stars::VertexStars;
use dieface::geom::mesh::{
    BoundaryChain, BoundaryLoops, EdgeId, Face, FaceId, HalfEdgeId, Mesh, Topology, VertexId,
};
use glam::DVec3;
use proptest::prelude::*;
use std::collections::BTreeSet;
use std::f64::consts::{FRAC_PI_2, PI};

// ---------------------------------------------------------------------------------
// Fixtures
// ---------------------------------------------------------------------------------

/// The unit cube as six quads wound counter-clockwise seen from outside.
/// Vertex `x + 2y + 4z` sits at `(x, y, z)`.
fn unit_cube() -> Mesh {
    let positions = (0..8)
        .map(|i| DVec3::new((i & 1) as f64, ((i >> 1) & 1) as f64, ((i >> 2) & 1) as f64))
        .collect();
    let faces = vec![
        Face::quad(0, 2, 3, 1), // z = 0
        Face::quad(4, 5, 7, 6), // z = 1
        Face::quad(0, 1, 5, 4), // y = 0
        Face::quad(2, 6, 7, 3), // y = 1
        Face::quad(0, 4, 6, 2), // x = 0
        Face::quad(1, 3, 7, 5), // x = 1
    ];
    Mesh::new(positions, faces).unwrap()
}

/// How one cell of a test grid is filled.
#[derive(Debug, Clone, Copy, PartialEq)]
enum Cell {
    Quad,
    /// Two triangles split along the diagonal from the cell's lower-left corner.
    TrisA,
    /// Two triangles split along the other diagonal.
    TrisB,
    Hole,
}

/// A flat `nx` by `ny` grid in the xy-plane with unit cells, faces wound
/// counter-clockwise seen from +z. Vertex `(i, j)` has index `j * (nx + 1) + i`; cell
/// `(i, j)` is `cells[j * nx + i]`. All grid vertices exist even around holes.
fn grid(nx: u32, ny: u32, cells: &[Cell]) -> Mesh {
    let mut positions = Vec::new();
    for j in 0..=ny {
        for i in 0..=nx {
            positions.push(DVec3::new(i as f64, j as f64, 0.0));
        }
    }
    let mut faces = Vec::new();
    for j in 0..ny {
        for i in 0..nx {
            let a = j * (nx + 1) + i;
            let (b, c, d) = (a + 1, a + nx + 2, a + nx + 1);
            match cells[(j * nx + i) as usize] {
                Cell::Quad => faces.push(Face::quad(a, b, c, d)),
                Cell::TrisA => {
                    faces.push(Face::triangle(a, b, c));
                    faces.push(Face::triangle(a, c, d));
                }
                Cell::TrisB => {
                    faces.push(Face::triangle(a, b, d));
                    faces.push(Face::triangle(b, c, d));
                }
                Cell::Hole => {}
            }
        }
    }
    Mesh::new(positions, faces).unwrap()
}

/// A grid of one cell kind with the listed cells `(i, j)` left out.
fn grid_with_holes(nx: u32, ny: u32, kind: Cell, holes: &[(u32, u32)]) -> Mesh {
    let cells: Vec<Cell> = (0..ny)
        .flat_map(|j| (0..nx).map(move |i| (i, j)))
        .map(|ij| {
            if holes.contains(&ij) {
                Cell::Hole
            } else {
                kind
            }
        })
        .collect();
    grid(nx, ny, &cells)
}

/// The signed area of a loop projected on the xy-plane (shoelace), positive for
/// counter-clockwise loops.
fn signed_area_xy(mesh: &Mesh, vertices: &[VertexId]) -> f64 {
    let n = vertices.len();
    (0..n)
        .map(|i| {
            let p = mesh.position(vertices[i]).unwrap();
            let q = mesh.position(vertices[(i + 1) % n]).unwrap();
            p.x * q.y - q.x * p.y
        })
        .sum::<f64>()
        / 2.0
}

fn assert_close(a: f64, b: f64, tol: f64) {
    assert!((a - b).abs() <= tol, "{a} vs {b} (tolerance {tol})");
}

/// Checks that every chain is connected (each half-edge ends where the next starts,
/// closed loops also around the end), lists the right vertices, that closed loops are
/// simple, and that every free half-edge of the topology is in exactly one chain.
fn check_chains(topo: &Topology, loops: &BoundaryLoops) {
    let mut seen = BTreeSet::new();
    let check = |chain: &BoundaryChain, closed: bool, seen: &mut BTreeSet<HalfEdgeId>| {
        assert!(!chain.half_edges.is_empty());
        let n = chain.half_edges.len();
        assert_eq!(chain.vertices.len(), if closed { n } else { n + 1 });
        for (i, &h) in chain.half_edges.iter().enumerate() {
            assert!(topo.is_boundary_edge(topo.edge(h)), "{h:?} is not free");
            assert!(seen.insert(h), "{h:?} is in two chains");
            assert_eq!(chain.vertices[i], topo.origin(h));
            if i + 1 < n {
                assert_eq!(topo.destination(h), topo.origin(chain.half_edges[i + 1]));
            }
        }
        let last = chain.half_edges[n - 1];
        if closed {
            assert_eq!(topo.destination(last), topo.origin(chain.half_edges[0]));
            let distinct: BTreeSet<VertexId> = chain.vertices.iter().copied().collect();
            assert_eq!(
                distinct.len(),
                n,
                "loop {:?} visits a vertex twice",
                chain.vertices
            );
        } else {
            assert_eq!(chain.vertices[n], topo.destination(last));
        }
    };
    for chain in &loops.loops {
        check(chain, true, &mut seen);
    }
    for chain in &loops.open_chains {
        check(chain, false, &mut seen);
    }
    let free: BTreeSet<HalfEdgeId> = topo
        .half_edges()
        .filter(|&h| topo.is_boundary_edge(topo.edge(h)))
        .collect();
    assert_eq!(seen, free);
    assert_eq!(free.len(), topo.free_edges().len());
}

/// The loop lengths, sorted.
fn loop_lengths(loops: &BoundaryLoops) -> Vec<usize> {
    let mut lengths: Vec<usize> = loops.loops.iter().map(|l| l.half_edges.len()).collect();
    lengths.sort_unstable();
    lengths
}

// ---------------------------------------------------------------------------------
// Construction and validation
// ---------------------------------------------------------------------------------

#[test]
fn a_renumbered_face_keeps_its_corner_count_and_order() {
    let quad = Face::quad(0, 1, 2, 3).renumbered(|v| 10 * v + 7);
    assert_eq!(quad.indices(), &[7, 17, 27, 37]);
    let triangle = Face::triangle(4, 2, 9).renumbered(|v| v + 1);
    assert_eq!(triangle.indices(), &[5, 3, 10]);
    assert!(triangle.is_triangle());
    // Renumbering and turning round commute: corner 0 stays first either way.
    let turned = Face::quad(3, 5, 8, 1);
    assert_eq!(
        turned.reversed().renumbered(|v| v * 2),
        turned.renumbered(|v| v * 2).reversed()
    );
}

#[test]
fn index_out_of_range_is_an_error() {
    let p = vec![DVec3::ZERO, DVec3::X, DVec3::Y];
    let err = Mesh::new(p, vec![Face::triangle(0, 1, 3)]).unwrap_err();
    assert!(
        matches!(err, GeomError::InvalidMesh { ref reason } if reason.contains("vertex 3")),
        "{err}"
    );
}

#[test]
fn repeated_vertex_is_an_error() {
    let p = vec![DVec3::ZERO, DVec3::X, DVec3::Y, DVec3::Z];
    let err = Mesh::new(p.clone(), vec![Face::triangle(0, 1, 1)]).unwrap_err();
    assert!(matches!(err, GeomError::InvalidMesh { .. }), "{err}");
    // Repeated, but not neighbouring, corners of a quad.
    let err = Mesh::new(p, vec![Face::quad(0, 1, 0, 2)]).unwrap_err();
    assert!(matches!(err, GeomError::InvalidMesh { .. }), "{err}");
}

#[test]
fn non_finite_positions_are_errors() {
    for bad in [f64::NAN, f64::INFINITY, f64::NEG_INFINITY] {
        let p = vec![DVec3::ZERO, DVec3::X, DVec3::new(0.0, bad, 0.0)];
        let err = Mesh::new(p, vec![Face::triangle(0, 1, 2)]).unwrap_err();
        assert!(matches!(err, GeomError::NotFinite { .. }), "{err}");
    }
}

#[test]
fn face_sizes_other_than_three_or_four_are_errors() {
    assert!(Face::from_slice(&[0, 1]).is_err());
    assert!(Face::from_slice(&[0, 1, 2, 3, 4]).is_err());
    assert!(Face::from_slice(&[]).is_err());
    assert_eq!(
        Face::from_slice(&[0, 1, 2]).unwrap(),
        Face::triangle(0, 1, 2)
    );
    assert_eq!(
        Face::from_slice(&[0, 1, 2, 3]).unwrap(),
        Face::quad(0, 1, 2, 3)
    );
}

#[test]
fn normals_are_validated() {
    let mesh = unit_cube();
    let err = mesh.clone().with_normals(vec![DVec3::Z; 7]).unwrap_err();
    assert_eq!(
        err,
        GeomError::LengthMismatch {
            what: "vertex normals",
            expected: 8,
            given: 7
        }
    );
    let mut normals = vec![DVec3::Z; 8];
    normals[3].x = f64::NAN;
    assert!(matches!(
        mesh.clone().with_normals(normals),
        Err(GeomError::NotFinite { .. })
    ));
    let with = mesh.with_normals(vec![DVec3::Z; 8]).unwrap();
    assert_eq!(with.normals().unwrap().len(), 8);
    assert!(with.without_normals().normals().is_none());
}

#[test]
fn groups_are_validated_and_kept_in_order() {
    let mut mesh = unit_cube();
    mesh.add_group("top", [FaceId(1)]).unwrap();
    mesh.add_group(
        "sides",
        [FaceId(5), FaceId(2), FaceId(3), FaceId(4), FaceId(2)],
    )
    .unwrap();
    assert!(matches!(
        mesh.add_group("top", [FaceId(0)]),
        Err(GeomError::InvalidMesh { .. })
    ));
    assert!(matches!(
        mesh.add_group("bad", [FaceId(6)]),
        Err(GeomError::InvalidMesh { .. })
    ));
    let names: Vec<&str> = mesh.groups().iter().map(|g| g.name()).collect();
    assert_eq!(names, ["top", "sides"]);
    assert_eq!(
        mesh.group("sides").unwrap().faces(),
        [FaceId(2), FaceId(3), FaceId(4), FaceId(5)]
    );
}

#[test]
fn set_position_checks_its_input() {
    let mut mesh = unit_cube();
    assert!(mesh.set_position(VertexId(8), DVec3::ZERO).is_err());
    assert!(mesh
        .set_position(VertexId(0), DVec3::splat(f64::NAN))
        .is_err());
    mesh.set_position(VertexId(0), DVec3::splat(-1.0)).unwrap();
    assert_eq!(mesh.position(VertexId(0)), Some(DVec3::splat(-1.0)));
}

#[test]
fn out_of_range_queries_return_nothing() {
    let mesh = unit_cube();
    let topo = mesh.topology();
    assert_eq!(mesh.face(FaceId(6)), None);
    assert_eq!(mesh.face_normal(FaceId(6)), None);
    assert_eq!(mesh.face_area(FaceId(99)), None);
    assert_eq!(mesh.position(VertexId(8)), None);
    assert!(topo.vertex_faces(VertexId(8)).is_empty());
    assert!(topo.vertex_neighbors(VertexId(100)).is_empty());
    assert_eq!(topo.face_half_edges(FaceId(6)).count(), 0);
    assert!(Mesh::default().bounding_box().is_none());
}

// ---------------------------------------------------------------------------------
// Geometry
// ---------------------------------------------------------------------------------

#[test]
fn cube_geometry() {
    let mesh = unit_cube();
    let center = DVec3::splat(0.5);
    for f in mesh.face_ids() {
        let n = mesh.face_normal(f).unwrap();
        let c = mesh.face_centroid(f).unwrap();
        // Outward: the normal points from the centre through the face centroid.
        assert!(
            (c - center - n * 0.5).length() < 1e-12,
            "face {f:?}: {n} at {c}"
        );
        assert_close(mesh.face_area(f).unwrap(), 1.0, 1e-12);
    }
    assert_close(mesh.total_area(), 6.0, 1e-12);
    assert_eq!(mesh.bounding_box(), Some((DVec3::ZERO, DVec3::ONE)));

    let normals = mesh.compute_vertex_normals();
    for (v, n) in normals.iter().enumerate() {
        let expected = (mesh.positions()[v] - center).normalize();
        assert!((*n - expected).length() < 1e-12, "vertex {v}: {n}");
    }
    // Angle weighting: splitting the planar quads does not change the normals.
    let split = mesh.triangulated().compute_vertex_normals();
    for (a, b) in normals.iter().zip(&split) {
        assert!((*a - *b).length() < 1e-12, "{a} vs {b}");
    }
}

#[test]
fn triangulated_area_equals_quad_area() {
    // A planar quad and a warped one.
    let positions = vec![
        DVec3::new(0.0, 0.0, 0.0),
        DVec3::new(3.0, 0.0, 0.0),
        DVec3::new(4.0, 2.0, 0.0),
        DVec3::new(0.5, 1.5, 0.0),
        DVec3::new(0.0, 0.0, 5.0),
        DVec3::new(1.0, 0.0, 5.0),
        DVec3::new(1.0, 1.0, 5.7),
        DVec3::new(0.0, 1.0, 5.0),
    ];
    let mesh = Mesh::new(
        positions,
        vec![Face::quad(0, 1, 2, 3), Face::quad(4, 5, 6, 7)],
    )
    .unwrap();
    let tri = mesh.triangulated();
    assert_eq!(tri.face_count(), 4);
    assert!(tri.faces().iter().all(Face::is_triangle));
    assert_close(tri.total_area(), mesh.total_area(), 1e-12);
    assert_close(
        tri.face_area(FaceId(0)).unwrap() + tri.face_area(FaceId(1)).unwrap(),
        mesh.face_area(FaceId(0)).unwrap(),
        1e-12,
    );
    // Planar quad: the shoelace area of the outline.
    let outline: Vec<VertexId> = (0..4).map(VertexId).collect();
    assert_close(
        mesh.face_area(FaceId(0)).unwrap(),
        signed_area_xy(&mesh, &outline),
        1e-12,
    );
    // Shorter diagonal: |0-2| = sqrt(20) > |1-3| = sqrt(8.5), so the split uses 1-3.
    assert_eq!(tri.faces()[0], Face::triangle(1, 2, 3));
    assert_eq!(tri.faces()[1], Face::triangle(1, 3, 0));
    // Winding kept: same normal side as the quad.
    for t in 0..2 {
        assert!(tri.face_normal(FaceId(t)).unwrap().z > 0.0);
    }
}

#[test]
fn triangulation_carries_groups_and_map() {
    let mesh = grid(2, 1, &[Cell::Quad, Cell::TrisA])
        .with_group("right", [FaceId(1), FaceId(2)])
        .unwrap();
    let (tri, map) = mesh.triangulated_with_map();
    assert_eq!(map, [FaceId(0), FaceId(0), FaceId(1), FaceId(2)]);
    assert_eq!(tri.group("right").unwrap().faces(), [FaceId(2), FaceId(3)]);
}

// ---------------------------------------------------------------------------------
// Topology: closed shells
// ---------------------------------------------------------------------------------

#[test]
fn cube_topology() {
    let mesh = unit_cube();
    let topo = mesh.topology();
    assert_eq!(topo.half_edge_count(), 24);
    assert_eq!(topo.edge_count(), 12);
    assert!(topo.free_edges().is_empty());
    assert!(topo.is_closed());
    assert_eq!(topo.euler_characteristic(), 2);
    assert!(topo.is_consistently_oriented());
    assert_eq!(topo.connected_components().len(), 1);
    let loops = topo.boundary_loops();
    assert!(loops.loops.is_empty() && loops.open_chains.is_empty());
    for e in topo.edges() {
        assert!(topo.is_manifold_edge(e));
        assert_close(topo.dihedral_angle(&mesh, e).unwrap(), FRAC_PI_2, 1e-12);
        // Every edge of a cube with outward normals is convex.
        assert_close(
            topo.signed_dihedral_angle(&mesh, e).unwrap(),
            FRAC_PI_2,
            1e-12,
        );
    }
    for v in mesh.vertex_ids() {
        assert_eq!(topo.vertex_faces(v).len(), 3);
        assert_eq!(topo.vertex_half_edges(v).len(), 3);
        assert_eq!(topo.vertex_neighbors(v).len(), 3);
        assert!(!topo.is_boundary_vertex(v));
    }
    // Vertex 0's neighbours differ from it in exactly one coordinate.
    assert_eq!(
        topo.vertex_neighbors(VertexId(0)),
        [VertexId(1), VertexId(2), VertexId(4)]
    );
    for h in topo.half_edges() {
        let t = topo.twin(h).unwrap();
        assert_eq!(topo.origin(t), topo.destination(h));
        assert_eq!(topo.twin(t), Some(h));
    }
}

#[test]
fn inverted_cube_is_concave_everywhere() {
    let cube = unit_cube();
    let flipped: Vec<Face> = cube.faces().iter().map(Face::reversed).collect();
    let mesh = Mesh::new(cube.positions().to_vec(), flipped).unwrap();
    let topo = mesh.topology();
    for e in topo.edges() {
        assert_close(
            topo.signed_dihedral_angle(&mesh, e).unwrap(),
            -FRAC_PI_2,
            1e-12,
        );
    }
}

#[test]
fn dihedral_angles_of_a_folded_strip() {
    // Two triangles over the edge 0-1 (the x-axis): flat, then folded up by 60 degrees.
    let fold = |angle: f64| {
        let positions = vec![
            DVec3::ZERO,
            DVec3::X,
            DVec3::new(0.5, -1.0, 0.0),
            DVec3::new(0.5, angle.cos(), angle.sin()),
        ];
        Mesh::new(
            positions,
            vec![Face::triangle(0, 2, 1), Face::triangle(0, 1, 3)],
        )
        .unwrap()
    };
    let flat = fold(0.0);
    let topo = flat.topology();
    let e = topo.find_edge(VertexId(1), VertexId(0)).unwrap();
    assert_close(topo.dihedral_angle(&flat, e).unwrap(), 0.0, 1e-12);
    assert!(topo.is_boundary_edge(topo.find_edge(VertexId(0), VertexId(2)).unwrap()));
    assert_eq!(
        topo.dihedral_angle(&flat, topo.find_edge(VertexId(0), VertexId(2)).unwrap()),
        None
    );

    // Folding the second triangle up (towards the normals, +z) makes a valley.
    let up = fold(PI / 3.0);
    assert_close(topo.dihedral_angle(&up, e).unwrap(), PI / 3.0, 1e-12);
    assert_close(
        topo.signed_dihedral_angle(&up, e).unwrap(),
        -PI / 3.0,
        1e-12,
    );
    let down = fold(-PI / 3.0);
    assert_close(
        topo.signed_dihedral_angle(&down, e).unwrap(),
        PI / 3.0,
        1e-12,
    );
}

// ---------------------------------------------------------------------------------
// Topology: open patches, holes, bowties, non-manifold edges
// ---------------------------------------------------------------------------------

#[test]
fn grid_with_a_hole_has_two_loops() {
    // 4 x 4 cells of triangles with the middle 2 x 2 cells removed.
    let mesh = grid_with_holes(4, 4, Cell::TrisA, &[(1, 1), (2, 1), (1, 2), (2, 2)]);
    let topo = mesh.topology();
    assert_eq!(topo.free_edges().len(), 16 + 8);
    assert_eq!(topo.euler_characteristic(), 0); // an annulus
    assert!(topo.is_consistently_oriented());
    let loops = topo.boundary_loops();
    check_chains(&topo, &loops);
    assert!(loops.open_chains.is_empty());
    assert_eq!(loop_lengths(&loops), [8, 16]);
    for l in &loops.loops {
        let area = signed_area_xy(&mesh, &l.vertices);
        if l.half_edges.len() == 16 {
            assert_close(area, 16.0, 1e-12); // outer rim: counter-clockwise
        } else {
            assert_close(area, -4.0, 1e-12); // hole: clockwise
            assert!(l.vertices.iter().all(|v| {
                let p = mesh.position(*v).unwrap();
                (1.0..=3.0).contains(&p.x) && (1.0..=3.0).contains(&p.y)
            }));
        }
        assert!(l.vertices.iter().all(|&v| topo.is_boundary_vertex(v)));
    }
    // The loop order is by lowest half-edge; recomputing gives the same answer.
    assert_eq!(topo.boundary_loops(), loops);
}

#[test]
fn single_quad_loop_follows_its_winding() {
    let mesh = grid(1, 1, &[Cell::Quad]);
    let topo = mesh.topology();
    let loops = topo.boundary_loops();
    assert_eq!(loops.loops.len(), 1);
    assert_eq!(
        loops.loops[0].vertices,
        [VertexId(0), VertexId(1), VertexId(3), VertexId(2)]
    );
    assert_eq!(topo.euler_characteristic(), 1);
    assert!(topo.twin(loops.loops[0].half_edges[0]).is_none());
}

#[test]
fn bowtie_squares_give_two_loops() {
    // Two unit squares touching only at vertex 2 = (1, 1). The second square's faces
    // come first so that "lowest id" alone would jump across the bowtie.
    let positions = vec![
        DVec3::new(0.0, 0.0, 0.0),
        DVec3::new(1.0, 0.0, 0.0),
        DVec3::new(1.0, 1.0, 0.0),
        DVec3::new(0.0, 1.0, 0.0),
        DVec3::new(2.0, 1.0, 0.0),
        DVec3::new(2.0, 2.0, 0.0),
        DVec3::new(1.0, 2.0, 0.0),
    ];
    let faces = vec![
        Face::triangle(2, 4, 5),
        Face::triangle(2, 5, 6),
        Face::triangle(0, 1, 2),
        Face::triangle(0, 2, 3),
    ];
    let mesh = Mesh::new(positions, faces).unwrap();
    let topo = mesh.topology();
    assert_eq!(topo.vertex_faces(VertexId(2)).len(), 4);
    let free_out = topo
        .vertex_half_edges(VertexId(2))
        .iter()
        .filter(|&&h| topo.is_boundary_edge(topo.edge(h)))
        .count();
    assert_eq!(free_out, 2);
    assert_eq!(
        topo.connected_components(),
        [vec![FaceId(0), FaceId(1)], vec![FaceId(2), FaceId(3)]]
    );
    assert_eq!(topo.euler_characteristic(), 1); // 7 - 9 + 4: two discs sharing a point

    let loops = topo.boundary_loops();
    check_chains(&topo, &loops);
    assert!(loops.open_chains.is_empty());
    assert_eq!(loop_lengths(&loops), [4, 4]);
    let sets: Vec<BTreeSet<u32>> = loops
        .loops
        .iter()
        .map(|l| l.vertices.iter().map(|v| v.0).collect())
        .collect();
    assert_eq!(sets[0], BTreeSet::from([2, 4, 5, 6]));
    assert_eq!(sets[1], BTreeSet::from([0, 1, 2, 3]));
    for l in &loops.loops {
        assert_close(signed_area_xy(&mesh, &l.vertices), 1.0, 1e-12);
    }
}

#[test]
fn patches_touching_at_two_corners_get_a_loop_each() {
    // Patch A: the unit square 0-1-2-3 as a fan of two triangles around vertex 2.
    // Patch B: a warped quad 0-4-2-5 (two triangles) touching A only at 0 and 2.
    // Faces are interleaved so that at vertex 2 the lowest-numbered free half-edge
    // belongs to B: only turning within A's fan finds A's own continuation.
    let positions = vec![
        DVec3::new(0.0, 0.0, 0.0),
        DVec3::new(1.0, 0.0, 0.0),
        DVec3::new(1.0, 1.0, 0.0),
        DVec3::new(0.0, 1.0, 0.0),
        DVec3::new(1.0, 0.0, 1.0),
        DVec3::new(0.0, 1.0, 1.0),
    ];
    let faces = vec![
        Face::triangle(0, 1, 2), // A
        Face::triangle(4, 2, 5), // B
        Face::triangle(0, 2, 3), // A
        Face::triangle(0, 4, 5), // B
    ];
    let mesh = Mesh::new(positions, faces).unwrap();
    let topo = mesh.topology();
    let loops = topo.boundary_loops();
    check_chains(&topo, &loops);
    assert!(loops.open_chains.is_empty());
    let sets: Vec<BTreeSet<u32>> = loops
        .loops
        .iter()
        .map(|l| l.vertices.iter().map(|v| v.0).collect())
        .collect();
    assert_eq!(
        sets,
        [BTreeSet::from([0, 1, 2, 3]), BTreeSet::from([0, 2, 4, 5])]
    );
    assert_eq!(
        loops.loops[0].vertices,
        [VertexId(0), VertexId(1), VertexId(2), VertexId(3)]
    );
    assert_eq!(topo.connected_components().len(), 2);
}

#[test]
fn holes_touching_at_a_corner_stay_separate() {
    // Two one-cell holes meeting diagonally at vertex (2, 2), in quads and triangles.
    for kind in [Cell::Quad, Cell::TrisA, Cell::TrisB] {
        let mesh = grid_with_holes(4, 4, kind, &[(1, 1), (2, 2)]);
        let topo = mesh.topology();
        let loops = topo.boundary_loops();
        check_chains(&topo, &loops);
        assert!(loops.open_chains.is_empty());
        assert_eq!(loop_lengths(&loops), [4, 4, 16], "{kind:?}");
        for l in &loops.loops {
            let expected = if l.half_edges.len() == 16 { 16.0 } else { -1.0 };
            assert_close(signed_area_xy(&mesh, &l.vertices), expected, 1e-12);
        }
        // V - E + F = 25 - 40 + 14 for quads (each triangle cell adds an edge and a
        // face): a disc with two holes.
        assert_eq!(topo.euler_characteristic(), -1, "{kind:?}");
    }
}

#[test]
fn edge_shared_by_three_triangles_is_non_manifold() {
    // Three sheets hinged on the edge 0-1 (the x-axis).
    let positions = vec![
        DVec3::ZERO,
        DVec3::X,
        DVec3::new(0.5, 1.0, 0.0),
        DVec3::new(0.5, -1.0, 0.0),
        DVec3::new(0.5, 0.0, 1.0),
    ];
    let faces = vec![
        Face::triangle(0, 1, 2),
        Face::triangle(1, 0, 3),
        Face::triangle(0, 1, 4),
    ];
    let mesh = Mesh::new(positions, faces).unwrap();
    let topo = mesh.topology();
    let hinge = topo.find_edge(VertexId(0), VertexId(1)).unwrap();
    assert_eq!(
        topo.edge_faces(hinge).collect::<Vec<_>>(),
        [FaceId(0), FaceId(1), FaceId(2)]
    );
    assert!(topo.is_non_manifold_edge(hinge));
    assert!(!topo.is_manifold_edge(hinge) && !topo.is_boundary_edge(hinge));
    assert_eq!(topo.non_manifold_edges(), [hinge]);
    assert_eq!(topo.dihedral_angle(&mesh, hinge), None);
    for &h in topo.edge_half_edges(hinge) {
        assert_eq!(topo.twin(h), None);
        assert_eq!(topo.edge(h), hinge);
    }
    assert_eq!(topo.edge_count(), 7);
    assert_eq!(topo.free_edges().len(), 6);
    assert_eq!(topo.connected_components().len(), 1);
    assert_eq!(topo.face_neighbors(FaceId(1)), [FaceId(0), FaceId(2)]);
    assert_eq!(
        topo.vertex_neighbors(VertexId(0)),
        (1..5).map(VertexId).collect::<Vec<_>>()
    );
    // The free edges still get chained, each exactly once.
    let loops = topo.boundary_loops();
    check_chains(&topo, &loops);
    let total: usize = loops
        .loops
        .iter()
        .chain(&loops.open_chains)
        .map(|c| c.half_edges.len())
        .sum();
    assert_eq!(total, 6);
    assert!(
        !loops.open_chains.is_empty(),
        "3 half-edges cannot pair up around the hinge"
    );
}

#[test]
fn inconsistent_orientation_is_detected() {
    // Two triangles on edge 0-1, both running 0 -> 1.
    let positions = vec![DVec3::ZERO, DVec3::X, DVec3::Y, DVec3::NEG_Y];
    let mesh = Mesh::new(
        positions,
        vec![Face::triangle(0, 1, 2), Face::triangle(0, 1, 3)],
    )
    .unwrap();
    let topo = mesh.topology();
    let e = topo.find_edge(VertexId(0), VertexId(1)).unwrap();
    assert!(!topo.is_consistently_oriented());
    assert_eq!(topo.inconsistent_edges(), [e]);
    assert!(topo.is_manifold_edge(e));
    // Normals +z and -z: the unsigned angle is defined, the signed one is not.
    assert_close(topo.dihedral_angle(&mesh, e).unwrap(), PI, 1e-12);
    assert_eq!(topo.signed_dihedral_angle(&mesh, e), None);
    let loops = topo.boundary_loops();
    check_chains(&topo, &loops);
    assert_eq!(loops.open_chains.len(), 2);
    assert!(loops.loops.is_empty());
}

#[test]
fn components_are_ordered_and_sorted() {
    let a = grid(1, 1, &[Cell::TrisA]);
    let b = unit_cube();
    let mesh = b.merged(&a).unwrap().merged(&b).unwrap();
    let comps = mesh.topology().connected_components();
    assert_eq!(comps.len(), 3);
    assert_eq!(comps[0], (0..6).map(FaceId).collect::<Vec<_>>());
    assert_eq!(comps[1], [FaceId(6), FaceId(7)]);
    assert_eq!(comps[2], (8..14).map(FaceId).collect::<Vec<_>>());
}

#[test]
fn half_edge_lookup() {
    let mesh = grid(1, 1, &[Cell::TrisA]);
    let topo = mesh.topology();
    let h = topo.find_half_edge(VertexId(0), VertexId(3)).unwrap();
    assert_eq!(topo.origin(h), VertexId(0));
    assert_eq!(topo.destination(h), VertexId(3));
    // TrisA splits the cell into (0, 1, 3) and (0, 3, 2).
    assert_eq!(topo.face(h), FaceId(1));
    let t = topo.twin(h).unwrap();
    assert_eq!(topo.face(t), FaceId(0));
    assert_eq!(topo.find_half_edge(VertexId(1), VertexId(2)), None);
    assert_eq!(topo.edge_vertices(topo.edge(h)), [VertexId(0), VertexId(3)]);
    let rec = topo.half_edge(h).unwrap();
    assert_eq!((rec.next, rec.prev), (topo.next(h), topo.prev(h)));
    // Edges are numbered by vertex pair.
    let pairs: Vec<[VertexId; 2]> = topo.edges().map(|e| topo.edge_vertices(e)).collect();
    let mut sorted = pairs.clone();
    sorted.sort();
    assert_eq!(pairs, sorted);
    let _: Vec<EdgeId> = topo.vertex_edges(VertexId(0)).to_vec();
}

// ---------------------------------------------------------------------------------
// Weld and merge
// ---------------------------------------------------------------------------------

#[test]
fn weld_merges_a_seam() {
    // Two triangles sharing an edge, but each with its own copies of the seam vertices
    // (one copy off by 1e-9), plus a sliver that collapses.
    let positions = vec![
        DVec3::new(0.0, 0.0, 0.0),
        DVec3::new(1.0, 0.0, 0.0),
        DVec3::new(0.0, 1.0, 0.0),
        DVec3::new(1.0, 0.0, 1e-9),
        DVec3::new(1.0, 1.0, 0.0),
        DVec3::new(0.0, 1.0, 0.0),
        DVec3::new(1.0 + 1e-9, 0.0, 0.0),
    ];
    let faces = vec![
        Face::triangle(0, 1, 2),
        Face::triangle(3, 4, 5),
        Face::triangle(1, 6, 4),
    ];
    let mesh = Mesh::new(positions, faces)
        .unwrap()
        .with_group("all", [FaceId(0), FaceId(1), FaceId(2)])
        .unwrap();
    assert_eq!(mesh.topology().free_edges().len(), 9);

    let (welded, map) = mesh.weld_with_map(1e-6).unwrap();
    assert_eq!(welded.vertex_count(), 4);
    assert_eq!(
        map.iter().map(|v| v.0).collect::<Vec<_>>(),
        [0, 1, 2, 1, 3, 2, 1]
    );
    assert_eq!(
        welded.position(VertexId(1)),
        Some(DVec3::X),
        "representatives keep their position"
    );
    assert_eq!(
        welded.faces(),
        [Face::triangle(0, 1, 2), Face::triangle(1, 3, 2)]
    );
    assert_eq!(welded.group("all").unwrap().faces(), [FaceId(0), FaceId(1)]);
    let topo = welded.topology();
    assert_eq!(topo.free_edges().len(), 4);
    assert!(topo.is_consistently_oriented());

    // With zero tolerance only exact duplicates merge.
    let exact = mesh.weld(0.0).unwrap();
    assert_eq!(exact.vertex_count(), 6);
    assert!(matches!(
        mesh.weld(-1.0),
        Err(GeomError::NotPositive { .. })
    ));
    assert!(matches!(
        mesh.weld(f64::NAN),
        Err(GeomError::NotPositive { .. })
    ));
    assert!(mesh.weld(f64::INFINITY).is_err());
}

#[test]
fn weld_turns_a_quad_with_merged_neighbours_into_a_triangle() {
    let positions = vec![DVec3::ZERO, DVec3::X, DVec3::new(1.0, 1e-12, 0.0), DVec3::Y];
    let mesh = Mesh::new(positions, vec![Face::quad(0, 1, 2, 3)]).unwrap();
    let welded = mesh.weld(1e-9).unwrap();
    assert_eq!(welded.faces(), [Face::triangle(0, 1, 2)]);
}

#[test]
fn weld_does_not_chain_beyond_the_tolerance() {
    // Points 0.6 apart with tolerance 1: 0 and 1 merge, 2 is 1.2 from 0 and stays.
    let positions: Vec<DVec3> = (0..3)
        .map(|i| DVec3::new(0.6 * i as f64, 0.0, 0.0))
        .collect();
    let mesh = Mesh::new(positions, vec![]).unwrap();
    let (welded, map) = mesh.weld_with_map(1.0).unwrap();
    assert_eq!(map, [VertexId(0), VertexId(0), VertexId(1)]);
    assert_eq!(welded.vertex_count(), 2);
}

#[test]
fn weld_averages_normals() {
    let positions = vec![DVec3::ZERO, DVec3::ZERO];
    let mesh = Mesh::new(positions, vec![])
        .unwrap()
        .with_normals(vec![DVec3::X, DVec3::Y])
        .unwrap();
    let welded = mesh.weld(0.0).unwrap();
    let n = welded.normals().unwrap()[0];
    assert!((n - DVec3::new(1.0, 1.0, 0.0).normalize()).length() < 1e-12);
}

#[test]
fn merge_offsets_indices_and_keeps_groups() {
    let a = grid(1, 1, &[Cell::Quad])
        .with_group("binder", [FaceId(0)])
        .unwrap();
    let b = grid(1, 1, &[Cell::TrisA])
        .with_group("binder", [FaceId(1)])
        .unwrap()
        .with_group("punch", [FaceId(0)])
        .unwrap()
        .with_computed_normals();
    let m = a.merged(&b).unwrap();
    assert_eq!(m.vertex_count(), 8);
    assert_eq!(
        m.faces(),
        [
            Face::quad(0, 1, 3, 2),
            Face::triangle(4, 5, 7),
            Face::triangle(4, 7, 6)
        ]
    );
    assert_eq!(m.group("binder").unwrap().faces(), [FaceId(0), FaceId(2)]);
    assert_eq!(m.group("punch").unwrap().faces(), [FaceId(1)]);
    assert_eq!(m.groups().len(), 2);
    // Only b had normals; a's were computed so none are lost.
    let normals = m.normals().unwrap();
    assert_eq!(normals.len(), 8);
    assert!(normals.iter().all(|n| (*n - DVec3::Z).length() < 1e-12));
    // Welding the merged flat squares side by side would need them to touch; here
    // they overlap exactly, so welding leaves 4 vertices and 3 faces on them.
    let w = m.weld(1e-9).unwrap();
    assert_eq!(w.vertex_count(), 4);
    assert_eq!(w.face_count(), 3);
}

// ---------------------------------------------------------------------------------
// Properties
// ---------------------------------------------------------------------------------

fn cell_strategy() -> impl Strategy<Value = Cell> {
    prop_oneof![
        Just(Cell::Quad),
        Just(Cell::TrisA),
        Just(Cell::TrisB),
        Just(Cell::Hole)
    ]
}

/// A random grid: size, and a filling for every cell (holes included).
fn grid_strategy(holes: bool) -> impl Strategy<Value = (u32, u32, Vec<Cell>)> {
    (1u32..7, 1u32..7).prop_flat_map(move |(nx, ny)| {
        let cell = if holes {
            cell_strategy().boxed()
        } else {
            prop_oneof![Just(Cell::Quad), Just(Cell::TrisA), Just(Cell::TrisB)].boxed()
        };
        (
            Just(nx),
            Just(ny),
            prop::collection::vec(cell, (nx * ny) as usize),
        )
    })
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(256))]

    #[test]
    fn grid_topology_invariants((nx, ny, cells) in grid_strategy(true)) {
        let mesh = grid(nx, ny, &cells);
        let topo = mesh.topology();
        let (tris, quads) = mesh.triangle_and_quad_counts();

        // Incidences counted from the vertex side match the faces.
        let incidences: usize = mesh.vertex_ids().map(|v| topo.vertex_faces(v).len()).sum();
        prop_assert_eq!(incidences, 3 * tris + 4 * quads);
        prop_assert_eq!(topo.half_edge_count(), 3 * tris + 4 * quads);
        let radial: usize = topo.edges().map(|e| topo.edge_face_count(e)).sum();
        prop_assert_eq!(radial, topo.half_edge_count());

        for h in topo.half_edges() {
            let f = topo.face(h);
            let size = mesh.face(f).unwrap().vertex_count();
            let mut g = h;
            for step in 1..=size {
                g = topo.next(g);
                prop_assert_eq!(topo.face(g), f);
                prop_assert_eq!(g == h, step == size, "next cycle of {:?}", h);
            }
            prop_assert_eq!(topo.prev(topo.next(h)), h);
            prop_assert!(topo.vertex_half_edges(topo.origin(h)).contains(&h));
            prop_assert!(topo.edge_half_edges(topo.edge(h)).contains(&h));
            if let Some(t) = topo.twin(h) {
                prop_assert_eq!(topo.twin(t), Some(h));
                prop_assert_eq!(topo.origin(t), topo.destination(h));
                prop_assert_eq!(topo.destination(t), topo.origin(h));
            }
            // A flat grid has only free and manifold edges.
            prop_assert!(topo.edge_face_count(topo.edge(h)) <= 2);
        }
        prop_assert!(topo.is_consistently_oriented());
        for e in topo.edges() {
            if let Some(angle) = topo.dihedral_angle(&mesh, e) {
                prop_assert!(angle.abs() < 1e-12);
            }
        }

        // Boundary loops: all closed, every free half-edge once, and the loops' signed
        // areas add up to the area of the faces (outer rims count up, holes down).
        let loops = topo.boundary_loops();
        check_chains(&topo, &loops);
        prop_assert!(loops.open_chains.is_empty());
        let loop_area: f64 = loops.loops.iter().map(|l| signed_area_xy(&mesh, &l.vertices)).sum();
        prop_assert!((loop_area - mesh.total_area()).abs() < 1e-9);
        // Bowtie vertices are resolved so that every loop is a simple lattice polygon
        // (check_chains checks that no vertex repeats), enclosing at least one cell.
        for l in &loops.loops {
            prop_assert!(signed_area_xy(&mesh, &l.vertices).abs() >= 1.0 - 1e-9);
        }

        // Triangulation keeps the area and the vertex set.
        let tri = mesh.triangulated();
        prop_assert_eq!(tri.face_count(), tris + 2 * quads);
        prop_assert!((tri.total_area() - mesh.total_area()).abs() < 1e-9);
        prop_assert_eq!(tri.topology().free_edges().len(), topo.free_edges().len());

        // Components partition the faces.
        let mut all: Vec<FaceId> = topo.connected_components().concat();
        all.sort();
        prop_assert_eq!(all, mesh.face_ids().collect::<Vec<_>>());
    }

    #[test]
    fn full_grid_is_a_disc((nx, ny, cells) in grid_strategy(false)) {
        let mesh = grid(nx, ny, &cells);
        let topo = mesh.topology();
        prop_assert_eq!(topo.euler_characteristic(), 1);
        prop_assert_eq!(topo.connected_components().len(), 1);
        let loops = topo.boundary_loops();
        prop_assert_eq!(loops.loops.len(), 1);
        prop_assert_eq!(loops.loops[0].vertices.len() as u32, 2 * (nx + ny));
        prop_assert!((signed_area_xy(&mesh, &loops.loops[0].vertices) - (nx * ny) as f64).abs() < 1e-9);
    }

    #[test]
    fn welding_a_soup_restores_the_grid((nx, ny, cells) in grid_strategy(true)) {
        let mesh = grid(nx, ny, &cells);
        // Explode into a soup: every face gets its own copies of its corners.
        let mut positions = Vec::new();
        let mut faces = Vec::new();
        for face in mesh.faces() {
            let base = positions.len() as u32;
            positions.extend(face.indices().iter().map(|&v| mesh.positions()[v as usize]));
            let local: Vec<u32> = (0..face.vertex_count() as u32).map(|i| base + i).collect();
            faces.push(Face::from_slice(&local).unwrap());
        }
        let soup = Mesh::new(positions, faces).unwrap();
        let welded = soup.weld(1e-9).unwrap();
        let used = mesh.vertex_ids().filter(|&v| !mesh.topology().vertex_faces(v).is_empty()).count();
        prop_assert_eq!(welded.vertex_count(), used);
        prop_assert_eq!(welded.face_count(), mesh.face_count());
        let (a, b) = (mesh.topology(), welded.topology());
        prop_assert_eq!(a.edge_count(), b.edge_count());
        prop_assert_eq!(a.free_edges().len(), b.free_edges().len());
        prop_assert_eq!(a.euler_characteristic(), b.euler_characteristic());
        prop_assert_eq!(loop_lengths(&a.boundary_loops()), loop_lengths(&b.boundary_loops()));
    }

    /// Arbitrary faces over a few points on a coarse lattice (so coincident and
    /// collinear points, degenerate faces, duplicate faces, non-manifold edges and
    /// flipped windings all occur): invalid faces give a clean error, valid ones a
    /// topology on which every query runs and the structural invariants hold. Nothing
    /// may panic.
    #[test]
    fn arbitrary_meshes_never_panic(
        coords in prop::collection::vec((0i32..3, 0i32..3, 0i32..2), 0..9),
        raw_faces in prop::collection::vec(prop::collection::vec(0u32..10, 2..6), 0..12),
        tolerance in 0.0f64..1.5,
    ) {
        let positions: Vec<DVec3> =
            coords.iter().map(|&(x, y, z)| DVec3::new(x as f64, y as f64, z as f64)).collect();
        let faces: Vec<Face> = raw_faces.iter().filter_map(|f| Face::from_slice(f).ok()).collect();
        let valid = |f: &Face| {
            let v = f.indices();
            v.iter().all(|&i| (i as usize) < positions.len())
                && (0..v.len()).all(|i| !v[i + 1..].contains(&v[i]))
        };
        // The whole list is accepted exactly when every face is valid ...
        let all_valid = faces.iter().all(valid);
        prop_assert_eq!(Mesh::new(positions.clone(), faces.clone()).is_ok(), all_valid);
        // ... and the valid faces always make a mesh.
        let faces: Vec<Face> = faces.into_iter().filter(valid).collect();
        let mesh = Mesh::new(positions, faces).unwrap();
        let topo = mesh.topology();
        for h in topo.half_edges() {
            if let Some(t) = topo.twin(h) {
                prop_assert_eq!(topo.twin(t), Some(h));
            }
            prop_assert_eq!(topo.prev(topo.next(h)), h);
        }
        let loops = topo.boundary_loops();
        check_chains(&topo, &loops);
        for e in topo.edges() {
            let _ = topo.dihedral_angle(&mesh, e);
            let _ = topo.signed_dihedral_angle(&mesh, e);
        }
        for v in mesh.vertex_ids() {
            let _ = topo.vertex_neighbors(v);
            let _ = topo.is_boundary_vertex(v);
        }
        for f in mesh.face_ids() {
            let _ = (mesh.face_normal(f), mesh.face_area(f), mesh.face_centroid(f));
            let _ = topo.face_neighbors(f);
        }
        let _ = (topo.euler_characteristic(), topo.is_consistently_oriented());
        let mut all: Vec<FaceId> = topo.connected_components().concat();
        all.sort();
        prop_assert_eq!(all, mesh.face_ids().collect::<Vec<_>>());
        prop_assert!(mesh.compute_vertex_normals().iter().all(|n| n.is_finite()));
        let tri = mesh.triangulated();
        prop_assert!((tri.total_area() - mesh.total_area()).abs() < 1e-9);
        let welded = mesh.weld(tolerance).unwrap();
        check_chains(&welded.topology(), &welded.topology().boundary_loops());
        let merged = mesh.merged(&welded).unwrap();
        prop_assert_eq!(merged.face_count(), mesh.face_count() + welded.face_count());
        // The edges against the plain definition: each unordered vertex pair its
        // half-edges run between is one edge, the edges numbered in pair order, each
        // one's half-edges (its radial list) in id order, and each vertex's edges in
        // id order.
        let mut by_pair: std::collections::BTreeMap<(VertexId, VertexId), Vec<HalfEdgeId>> =
            std::collections::BTreeMap::new();
        for h in topo.half_edges() {
            let (a, b) = (topo.origin(h), topo.destination(h));
            by_pair.entry((a.min(b), a.max(b))).or_default().push(h);
        }
        prop_assert_eq!(topo.edge_count(), by_pair.len());
        for (e, ((a, b), radial)) in topo.edges().zip(&by_pair) {
            prop_assert_eq!(topo.edge_vertices(e), [*a, *b]);
            prop_assert_eq!(topo.edge_half_edges(e), radial.as_slice());
            for &h in radial {
                prop_assert_eq!(topo.edge(h), e);
            }
        }
        for v in mesh.vertex_ids() {
            let touching: Vec<EdgeId> = topo
                .edges()
                .filter(|&e| topo.edge_vertices(e).contains(&v))
                .collect();
            prop_assert_eq!(topo.vertex_edges(v), touching.as_slice());
            let leaving: Vec<HalfEdgeId> = topo.half_edges().filter(|&h| topo.origin(h) == v).collect();
            prop_assert_eq!(topo.vertex_half_edges(v), leaving.as_slice());
            let faces: Vec<FaceId> = leaving.iter().map(|&h| topo.face(h)).collect();
            prop_assert_eq!(topo.vertex_faces(v), faces.as_slice());
            // One node's normal is the one every node's pass gives it, bit for bit.
            prop_assert_eq!(
                mesh.vertex_normal(v, topo.vertex_faces(v)),
                mesh.compute_vertex_normals()[v.index()]
            );
        }
        // Determinism: building twice gives identical results.
        prop_assert_eq!(mesh.topology(), topo);
    }

    /// The light connectivity hole filling uses, against the half-edge topology on the
    /// same arbitrary meshes (non-manifold edges, flipped windings, bowties, duplicate
    /// faces): each node's star is its faces; a node's faces close round it exactly
    /// where each of its edges runs as often one way as the other; and the free-edge
    /// scan finds the loops and open chains `boundary_loops` traces, with the faces on
    /// their edges, and as many free edges.
    #[test]
    fn stars_and_the_free_edge_scan_agree_with_the_topology(
        coords in prop::collection::vec((0i32..3, 0i32..3, 0i32..2), 3..9),
        raw_faces in prop::collection::vec(prop::collection::vec(0u32..9, 3..5), 0..14),
    ) {
        let positions: Vec<DVec3> =
            coords.iter().map(|&(x, y, z)| DVec3::new(x as f64, y as f64, z as f64)).collect();
        let faces: Vec<Face> = raw_faces
            .iter()
            .filter_map(|f| Face::from_slice(f).ok())
            .filter(|f| {
                let v = f.indices();
                v.iter().all(|&i| (i as usize) < positions.len())
                    && (0..v.len()).all(|i| !v[i + 1..].contains(&v[i]))
            })
            .collect();
        let mesh = Mesh::new(positions, faces).unwrap();
        let topo = mesh.topology();
        let stars = VertexStars::build(&mesh);
        for v in mesh.vertex_ids() {
            prop_assert_eq!(stars.faces(v), topo.vertex_faces(v));
            let balanced = topo.vertex_edges(v).iter().all(|&e| {
                let from_v = topo
                    .edge_half_edges(e)
                    .iter()
                    .filter(|&&h| topo.origin(h) == v)
                    .count();
                2 * from_v == topo.edge_half_edges(e).len()
            });
            prop_assert_eq!(stars.closes(v), balanced, "node {}", v.0);
        }
        let free = free_edges(&mesh, None);
        let traced = topo.boundary_loops();
        prop_assert_eq!(free.loops.len(), traced.loops.len());
        for (l, chain) in free.loops.iter().zip(&traced.loops) {
            prop_assert_eq!(&l.nodes, &chain.vertices);
            let faces: Vec<FaceId> = chain.half_edges.iter().map(|&h| topo.face(h)).collect();
            prop_assert_eq!(&l.faces, &faces);
        }
        let open: Vec<Vec<VertexId>> =
            traced.open_chains.iter().map(|c| c.vertices.clone()).collect();
        prop_assert_eq!(&free.open_chains, &open);
        prop_assert_eq!(free.count, topo.free_edges().len());
        // The pieces are the faces joined across edges, but where two sheets touch
        // only at a node inside both (its faces closing round it in two fans), which
        // joins them.
        let components = topo.connected_components();
        let mut piece_of = vec![0; mesh.face_count()];
        for (k, c) in components.iter().enumerate() {
            for f in c {
                piece_of[f.index()] = k;
            }
        }
        let kissing = mesh.vertex_ids().any(|v| {
            stars.closes(v)
                && topo.vertex_faces(v).iter().any(|f| piece_of[f.index()] != piece_of[topo.vertex_faces(v)[0].index()])
        });
        if !kissing {
            prop_assert_eq!(free.pieces, components.len());
        }
    }
}
