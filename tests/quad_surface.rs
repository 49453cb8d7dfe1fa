//! Quad meshing of trimmed surfaces (issue 18, paper 004 sections 2-4): trim loops
//! given as 3-D points mapped to the surface, the region meshed in a plane and mapped
//! back. The mesh must be sound on the surface (conforming, oriented along the surface
//! normal, its free edges the trim loops), follow the surface within the chordal
//! tolerance, and bad trims are refused with the loop and point named.

#[path = "common/quad_surfaces.rs"]
mod surfaces;

use surfaces::shapes;

use dieface::geom::mesh::quad::quality::mesh_quality;
use dieface::geom::mesh::quad::surface::{
    quad_mesh_surface, MeshPlane, SurfaceMesh, SurfaceMeshError, SurfaceMeshOptions, SurfaceRegion,
};
use dieface::geom::NurbsSurface;
use glam::{DVec2, DVec3};

/// The distance from `p` to the closed polyline `l`.
fn to_polyline(p: DVec2, l: &[DVec2]) -> f64 {
    (0..l.len())
        .map(|i| {
            let (a, b) = (l[i], l[(i + 1) % l.len()]);
            let t = ((p - a).dot(b - a) / (b - a).length_squared()).clamp(0.0, 1.0);
            p.distance(a.lerp(b, t))
        })
        .fold(f64::INFINITY, f64::min)
}

/// What every surface mesh must be: each inner edge shared by two elements, wound one
/// way, the free loops exactly the trim loops (`off_trim` of each boundary node's
/// position and parameters, the distance from the trim loop as the case drew it, at
/// most `on_trim`), each element's normal along the surface's, every node on the
/// surface at its parameters.
fn assert_sound(
    surface: &NurbsSurface,
    region: &SurfaceRegion,
    meshed: &SurfaceMesh,
    off_trim: impl Fn(DVec3, DVec2) -> f64,
    on_trim: f64,
) {
    let mesh = &meshed.mesh;
    let topology = mesh.topology();
    assert!(
        topology.non_manifold_edges().is_empty(),
        "an edge of three elements"
    );
    assert!(
        topology.is_consistently_oriented(),
        "elements wound both ways"
    );
    let loops = topology.boundary_loops();
    assert!(loops.open_chains.is_empty(), "an open chain of free edges");
    let expected = region.holes.len() + 1;
    assert_eq!(loops.loops.len(), expected, "free loops");
    for l in &loops.loops {
        for v in &l.vertices {
            assert!(
                v.index() < meshed.boundary_nodes,
                "a free edge inside the region"
            );
            let (p, uv) = (mesh.positions()[v.index()], meshed.uv[v.index()]);
            let off = off_trim(p, uv);
            assert!(
                off <= on_trim,
                "a boundary node {off} mm off its trim loop at {p}"
            );
        }
    }
    for (p, uv) in mesh.positions().iter().zip(&meshed.uv) {
        assert!(
            p.distance(surface.point_at(uv.x, uv.y)) < 1e-9,
            "a node off the surface"
        );
    }
    for face in mesh.faces() {
        let p: Vec<DVec3> = face
            .indices()
            .iter()
            .map(|&v| mesh.positions()[v as usize])
            .collect();
        let n = if p.len() == 4 {
            (p[2] - p[0]).cross(p[3] - p[1])
        } else {
            (p[1] - p[0]).cross(p[2] - p[0])
        };
        let uv = face
            .indices()
            .iter()
            .map(|&v| meshed.uv[v as usize])
            .sum::<glam::DVec2>()
            / p.len() as f64;
        let d = surface.derivatives::<2>(uv.x, uv.y);
        assert!(
            n.dot(d[1][0].cross(d[0][1])) > 0.0,
            "an element facing against the surface"
        );
    }
    assert_eq!(mesh_quality(mesh).inverted, 0, "inverted elements");
}

/// The largest sag of an element edge's midpoint off the surface (the edge's middle
/// parameters' surface point against the chord's middle).
fn largest_sag(surface: &NurbsSurface, meshed: &SurfaceMesh) -> f64 {
    let mut sag: f64 = 0.0;
    for face in meshed.mesh.faces() {
        let ids = face.indices();
        for i in 0..ids.len() {
            let (a, b) = (ids[i] as usize, ids[(i + 1) % ids.len()] as usize);
            let mid = 0.5 * (meshed.uv[a] + meshed.uv[b]);
            let chord = 0.5 * (meshed.mesh.positions()[a] + meshed.mesh.positions()[b]);
            sag = sag.max(surface.point_at(mid.x, mid.y).distance(chord));
        }
    }
    sag
}

#[test]
fn a_door_inner_on_a_coons_patch_is_meshed_in_its_projection_plane() {
    let (surface, region) = surfaces::door_inner_on_surface();
    let meshed =
        quad_mesh_surface(&surface, &region, &SurfaceMeshOptions::at_size(20.0)).expect("meshed");
    assert_eq!(meshed.plane, MeshPlane::Projection);
    // The trims were drawn at S(x / 900, y / 700) of the plane door inner's loops.
    let plane = shapes::door_inner();
    let loops: Vec<&Vec<DVec2>> = std::iter::once(&plane.outer).chain(&plane.holes).collect();
    let off = |_: DVec3, uv: DVec2| {
        let drawn = uv * DVec2::new(900.0, 700.0);
        loops
            .iter()
            .map(|l| to_polyline(drawn, l))
            .fold(f64::INFINITY, f64::min)
    };
    assert_sound(&surface, &region, &meshed, off, 1e-6);
    let q = mesh_quality(&meshed.mesh);
    assert!(q.quad_share() > 0.97, "{q:?}");
    assert!(q.min_scaled_jacobian > 0.3, "{q:?}");
}

#[test]
fn a_vessel_end_is_meshed_seen_along_its_axis() {
    let (surface, region) = surfaces::vessel_end();
    let meshed =
        quad_mesh_surface(&surface, &region, &SurfaceMeshOptions::at_size(15.0)).expect("meshed");
    // A full turn's corners overlap: no corner plane; the region's mean normal is the axis.
    match meshed.plane {
        MeshPlane::View(d) => assert!(d.normalize().dot(DVec3::Z).abs() > 0.999, "{d}"),
        other => panic!("meshed in {other:?}"),
    }
    // The trims are circles seen from above: a node's distance from their polylines in
    // plan, at most their chords' sag off the circles (0.096 mm at most, on the central nozzle's 48 points), since
    // between trim points a node follows the trim straight in the parameters.
    let seen_from_above = |l: &Vec<DVec3>| l.iter().map(|p| p.truncate()).collect::<Vec<_>>();
    let loops: Vec<Vec<DVec2>> = region
        .outer
        .iter()
        .chain(&region.holes)
        .map(seen_from_above)
        .collect();
    let off = |p: DVec3, _: DVec2| {
        loops
            .iter()
            .map(|l| to_polyline(p.truncate(), l))
            .fold(f64::INFINITY, f64::min)
    };
    assert_sound(&surface, &region, &meshed, off, 0.1);
    let q = mesh_quality(&meshed.mesh);
    assert!(q.quad_share() > 0.97, "{q:?}");
    assert!(q.min_scaled_jacobian > 0.3, "{q:?}");
}

#[test]
fn a_tight_radius_makes_the_elements_finer_until_the_chord_sags_within_tolerance() {
    let surface = surfaces::half_cylinder();
    let region = SurfaceRegion::default();
    let mut options = SurfaceMeshOptions::at_size(20.0);
    options.quad.chord_tolerance = 0.1;
    let fine = quad_mesh_surface(&surface, &region, &options).expect("meshed");
    // Seen from its corners' plane the half cylinder stands on edge: its parameters.
    assert_eq!(fine.plane, MeshPlane::Parameters);
    // Untrimmed: the free loop is the surface's own edge, at u or v = 0 or 1.
    let off = |_: DVec3, uv: DVec2| uv.min(DVec2::ONE - uv).min_element().abs();
    assert_sound(&surface, &region, &fine, off, 1e-12);
    let sag = largest_sag(&surface, &fine);
    assert!(sag <= 0.12, "sag {sag}");
    // 2 sqrt(2 R t - t^2) on R = 50 mm, t = 0.1 mm: 6.3 mm at most across.
    assert!((fine.least_size - 6.32).abs() < 0.05, "{}", fine.least_size);
    options.quad.chord_tolerance = 5.0;
    let coarse = quad_mesh_surface(&surface, &region, &options).expect("meshed");
    assert!(largest_sag(&surface, &coarse) > 1.0);
    assert!(fine.mesh.face_count() > 3 * coarse.mesh.face_count());
}

#[test]
fn a_trim_point_off_the_surface_is_named() {
    let (surface, mut region) = surfaces::door_inner_on_surface();
    region.holes[2][5].z += 3.0;
    match quad_mesh_surface(&surface, &region, &SurfaceMeshOptions::at_size(20.0)) {
        Err(SurfaceMeshError::OffSurface {
            loop_index,
            point,
            distance,
            ..
        }) => {
            assert_eq!((loop_index, point), (3, 5));
            assert!(distance > 2.0 && distance <= 3.0, "{distance}");
        }
        other => panic!("{other:?}"),
    }
}

#[test]
fn crossing_trim_loops_are_refused_with_the_loops_named() {
    let (surface, mut region) = surfaces::door_inner_on_surface();
    let moved: Vec<DVec3> = region.holes[1].clone();
    // The 70 mm hole moved onto the rounded rectangle above it.
    region.holes[1] = moved
        .iter()
        .map(|p| {
            let uv = glam::DVec2::new(p.x / 900.0, (p.y + 230.0) / 700.0);
            surface.point_at(uv.x, uv.y)
        })
        .collect();
    let err = quad_mesh_surface(&surface, &region, &SurfaceMeshOptions::at_size(20.0)).unwrap_err();
    assert!(
        matches!(
            err,
            SurfaceMeshError::Region(dieface::geom::mesh::quad::QuadError::Crossing { .. })
        ),
        "{err:?}"
    );
}

#[test]
fn quad_mesh_in_a_script_takes_loops_as_top_view_points_sketches_and_3d_points() {
    use dieface::eval::value::Data;
    use dieface::eval::Engine;
    // A flat panel: a loop of 2-D points laid onto it, a circle drawn in the top view,
    // and the same outline as 3-D points on it, each meshed.
    let text = "units mm
let panel = coons(line_between((0, 0, 0), (200, 0, 0)), line_between((0, 100, 0), (200, 100, 0)),
                  line_between((0, 0, 0), (0, 100, 0)), line_between((200, 0, 0), (200, 100, 0)))
let flat = quad_mesh(panel, size: 10 mm, outline: [(20, 20), (180, 20), (180, 80), (20, 80)],
                     holes: [circle((100, 50), 15 mm)])
let spatial = quad_mesh(panel, size: 10 mm, outline: [(20, 20, 0), (180, 20, 0), (180, 80, 0), (20, 80, 0)])
";
    let mut engine = Engine::new(None);
    let out = engine.evaluate("panel.die", text, None);
    assert!(out.diagnostics.is_empty(), "{:?}", out.diagnostics);
    for name in ["flat", "spatial"] {
        let decl = out.decls.iter().find(|d| d.name == name).expect("declared");
        let Some(Data::Mesh(mesh)) = decl.value.as_ref().map(|v| &v.data) else {
            panic!("{name} is not a mesh");
        };
        let q = mesh_quality(mesh);
        assert_eq!(q.triangles, 0, "{name}: {q:?}");
        assert!(q.quads >= 80, "{name}: {q:?}");
        // Every node within the outline's 160 x 60 mm.
        assert!(mesh.positions().iter().all(|p| p.x >= 20.0 - 1e-9
            && p.x <= 180.0 + 1e-9
            && p.y >= 20.0 - 1e-9
            && p.y <= 80.0 + 1e-9));
    }
}
