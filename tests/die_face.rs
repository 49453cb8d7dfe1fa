//! Issue 12: the die face judged as a die engineer judges it (`docs/methods.md`, "What a
//! die engineer checks"), on the fender, the door and a hood drawn mirror-symmetric
//! about x = 0: radii as drawn in every step-draw patch, key sections reproduced,
//! tangent at the trim line and across the punch opening, no dip below the opening,
//! walls at their drawn draft, and the same surfaces whatever corner the trim sketch
//! starts at and on both halves of a symmetric part.
//!
//! The smallest radius and the draft are measured here independently of `inspect`'s own
//! figures: the principal curvatures on a grid of every patch (`geom::curvature`) and
//! the normal's angle to the press direction.

#[allow(dead_code)] // the shared helpers this file does not use
mod common;

#[path = "common/example.rs"]
mod example;
#[path = "common/script.rs"]
mod script;

use dieface::die::figures::{edge_samples, seam, Edge, Facing};
use dieface::die::step_draw::StepDraw;
use dieface::eval::Data;
use dieface::geom::curvature::min_radius;
use dieface::geom::inversion::{closest_point_on_surface, project_to_surface_near};
use dieface::geom::NurbsSurface;
use glam::DVec3;

/// The step draw `addendum` and the binder of an example.
fn example_step_draw(path: &str) -> (StepDraw, Vec<NurbsSurface>, NurbsSurface) {
    let values = example::example_values(path);
    pick(values.into_iter().map(|(n, v)| (n, v.data)).collect())
}

/// The step draw, the binder's patches and the product surface among evaluated values.
fn pick(values: Vec<(String, Data)>) -> (StepDraw, Vec<NurbsSurface>, NurbsSurface) {
    let mut step = None;
    let mut binder = Vec::new();
    let mut product = None;
    for (_, data) in values {
        match &data {
            Data::Record(r) => {
                if let Some(s) = r.model::<StepDraw>() {
                    step = Some(s.clone());
                }
                if let Some(b) = r.model::<dieface::die::blankholder::Blankholder>() {
                    binder = b.patches.iter().map(|p| p.surface.clone()).collect()
                }
            }
            Data::Trimmed(t) => product = Some(t.surface().clone()),
            _ => {}
        }
    }
    (
        step.expect("a step draw"),
        binder,
        product.expect("a trimmed product"),
    )
}

/// A hood, mirror-symmetric about x = 0: panel, trim line, punch opening, binder and
/// step draw. `trim` is the trim sketch (so a test can start it at another corner).
fn hood(trim: &str) -> String {
    format!(
        r#"
import "std/addendum" as add
units mm deg
fn height(i, j) = 40 mm * (1 - ((i - 2) / 2) * ((i - 2) / 2)) * (1 - ((j - 1.5) / 1.5) * ((j - 1.5) / 1.5))
let net = [ [ (-500 + i * 250, -350 + j * 700 / 3, height(i, j)) for j in range(0, 4) ] for i in range(0, 5) ]
let panel = nurbs_surface(degree: (3, 3), points: net)
let trim_line = {trim}
let outline = project(trim_line, panel)
product hood = trim(panel, outline)
let opening_top = sketch(top) {{
    from (-600, -440)
    fillet 110
    line to (600, -440)
    fillet 110
    line to (600, 440)
    fillet 110
    line to (-600, 440)
    fillet 110
    close
}}
let wrap_x = sketch(side_xz) {{
    from (-700, -70)
    spline through [(-300, -60), (0, -57), (300, -60), (700, -70)]
}}
let wrap_y = sketch(side_yz) {{
    from (-520, -75)
    spline through [(-250, -62), (0, -58), (250, -62), (520, -75)]
}}
punch_opening opening {{
    top = opening_top
    side front = wrap_x
    side nose = wrap_y
    side top = wrap_x
    side rear = wrap_y
    corners {{ tangent = 100 % }}
}}
blankholder binder {{
    opening = opening
    width = 150 mm
    corners {{ tautness = 30 % }}
}}
fn plain(product, opening) = add.wall(product, opening, draft: 8 deg, punch_radius: 12 mm, die_radius: 8 mm)
fn stepped(product, opening) = add.step(product, opening, step_depth: 15 mm, step_width: 15 mm, draft: 8 deg)
step_draw addendum {{
    product = hood
    opening = opening
    binder = binder
    section front {{ at = ((0, -200), (0, -560)); profile = stepped }}
    section front_nose {{ at = ((380, -200), (700, -560)); profile = plain }}
    section nose {{ at = ((400, 0), (760, 0)); profile = plain }}
    section nose_top {{ at = ((380, 200), (700, 560)); profile = plain }}
    section top {{ at = ((0, 200), (0, 560)); profile = stepped }}
    section top_rear {{ at = ((-380, 200), (-700, 560)); profile = plain }}
    section rear {{ at = ((-400, 0), (-760, 0)); profile = plain }}
    section rear_front {{ at = ((-380, -200), (-700, -560)); profile = plain }}
}}
"#
    )
}

/// The hood's trim line, a rounded rectangle drawn from corner `start` (0 to 3) round.
fn trim_from(start: usize) -> String {
    let corners = [(-450, -300), (450, -300), (450, 300), (-450, 300)];
    let mut s = String::from("sketch(top) {\n");
    let (x, y) = corners[start];
    s += &format!("    from ({x}, {y})\n    fillet 80\n");
    for k in 1..4 {
        let (x, y) = corners[(start + k) % 4];
        s += &format!("    line to ({x}, {y})\n    fillet 80\n");
    }
    s += "    close\n}";
    s
}

fn hood_step_draw(start: usize) -> (StepDraw, Vec<NurbsSurface>, NurbsSurface) {
    pick(script::evaluate_clean("hood.die", &hood(&trim_from(start))))
}

/// The largest distance from points to the nearest of `surfaces`: each point projected
/// onto every surface from that surface's grid sample nearest to it (a global search
/// alone can settle on a far local minimum of a long, twisting patch).
fn farthest(points: &[DVec3], surfaces: &[&NurbsSurface]) -> f64 {
    let grids: Vec<Vec<((f64, f64), DVec3)>> = surfaces
        .iter()
        .map(|s| {
            let (u0, u1) = s.domain_u();
            let (v0, v1) = s.domain_v();
            let mut g = Vec::new();
            for i in 0..=80 {
                for j in 0..=20 {
                    let (u, v) = (
                        u0 + (u1 - u0) * i as f64 / 80.0,
                        v0 + (v1 - v0) * j as f64 / 20.0,
                    );
                    g.push(((u, v), s.point_at(u, v)));
                }
            }
            g
        })
        .collect();
    points
        .iter()
        .map(|&p| {
            surfaces
                .iter()
                .zip(&grids)
                .filter_map(|(s, g)| {
                    let start = g
                        .iter()
                        .min_by(|a, b| a.1.distance(p).total_cmp(&b.1.distance(p)))
                        .map(|x| x.0)?;
                    project_to_surface_near(s, p, start)
                        .ok()
                        .map(|h| h.distance)
                        .or_else(|| closest_point_on_surface(s, p).ok().map(|h| h.distance))
                })
                .fold(f64::INFINITY, f64::min)
        })
        .fold(0.0, f64::max)
}

/// Points on a grid over every patch.
fn grid_points(sd: &StepDraw, n: usize) -> Vec<DVec3> {
    let mut out = Vec::new();
    for p in &sd.patches {
        let (u0, u1) = p.surface.domain_u();
        let (v0, v1) = p.surface.domain_v();
        for i in 0..=n {
            for j in 0..=4 {
                let u = u0 + (u1 - u0) * i as f64 / n as f64;
                let v = v0 + (v1 - v0) * j as f64 / 4.0;
                out.push(p.surface.point_at(u, v));
            }
        }
    }
    out
}

/// The share of the smallest drawn radius every patch keeps, as the issue asks. The
/// step draw keeps 0.94 or more on the fender, 0.95 on the door and 0.92 on the hood.
/// It was 0.89 on the fender (`rear_to_rear_front`) while the sections' slant at the
/// opening followed the opening's bare tangent, whose turning rate jumps where its
/// lines and arcs meet; 0.68 before the sections were matched along the product's
/// normals and the runs paced to their corners, and 0.24 before that.
const RADIUS_SHARE: f64 = 0.9;

/// Item 1: no step-draw patch much tighter than the smallest radius drawn in its two
/// key sections, anywhere in the patch ([`RADIUS_SHARE`]); the key sections reproduced
/// within the fit tolerance.
fn radii_as_drawn(label: &str, sd: &StepDraw) {
    for p in &sd.patches {
        let m = min_radius(&p.surface, 4);
        eprintln!(
            "{label} {}: smallest radius {:.3} mm (drawn {:.1}) at {:.1?}",
            p.name, m.radius, p.drawn_radius, m.point
        );
        assert!(
            m.radius >= RADIUS_SHARE * p.drawn_radius,
            "{label} {}: radius {:.3} mm at {:?} below {RADIUS_SHARE} of the drawn {} mm",
            p.name,
            m.radius,
            m.point,
            p.drawn_radius
        );
    }
    assert!(
        sd.quality.section_fit <= 0.01,
        "{label}: key sections {} mm from their profiles",
        sd.quality.section_fit
    );
}

/// Items 2 and 3: tangent at the trim line and across the punch opening, measured
/// along each patch's edges against the product surface and the binder's patches.
fn tangent_seams(label: &str, sd: &StepDraw, binder: &[NurbsSurface], product: &NurbsSurface) {
    let binder: Vec<Facing> = binder.iter().map(Facing::new).collect();
    let product = Facing::new(product);
    let (mut trim, mut opening): ((f64, f64), (f64, f64)) = ((0.0, 0.0), (0.0, 0.0));
    for p in &sd.patches {
        let (product_edge, opening_edge) = if p.reversed {
            (Edge::V0, Edge::V1)
        } else {
            (Edge::V1, Edge::V0)
        };
        let t = seam(
            Facing::new(&p.surface),
            &edge_samples(&p.surface, product_edge, 6),
            &[product],
        )
        .expect("trim seam");
        let o = seam(
            Facing::new(&p.surface),
            &edge_samples(&p.surface, opening_edge, 6),
            &binder,
        )
        .expect("opening seam");
        trim = (trim.0.max(t.gap), trim.1.max(t.crease));
        opening = (opening.0.max(o.gap), opening.1.max(o.crease));
    }
    eprintln!(
        "{label}: trim line gap {:.2e} mm crease {:.4} deg; opening gap {:.2e} mm crease {:.4} deg",
        trim.0, trim.1, opening.0, opening.1
    );
    assert!(trim.0 <= 1e-3, "{label}: trim gap {} mm", trim.0);
    assert!(
        trim.1 <= 0.5,
        "{label}: crease {} deg at the trim line",
        trim.1
    );
    assert!(
        opening.0 <= 2e-3,
        "{label}: gap {} mm to the binder",
        opening.0
    );
    assert!(
        opening.1 <= 0.5,
        "{label}: crease {} deg to the binder",
        opening.1
    );
}

/// Item 7: walls near their drawn draft (8 deg), never an undercut: 7.82 deg on the
/// fender, 7.85 on the door, 7.69 on the hood (before: 5.9, then 7.15 on the fender).
fn drafted(label: &str, sd: &StepDraw) {
    let mut worst = f64::INFINITY;
    for p in &sd.patches {
        let (u0, u1) = p.surface.domain_u();
        let (v0, v1) = p.surface.domain_v();
        for i in 0..=300 {
            for j in 0..=120 {
                let u = u0 + (u1 - u0) * i as f64 / 300.0;
                let v = v0 + (v1 - v0) * j as f64 / 120.0;
                if let Ok(n) = p.surface.normal(u, v) {
                    // Patches face up: a normal pointing down is an undercut, which
                    // shows here as a negative draft.
                    worst = worst.min(n.z.asin().to_degrees());
                }
            }
        }
    }
    eprintln!("{label}: steepest wall {worst:.2} deg from vertical");
    assert!(worst >= 7.6, "{label}: a wall at {worst} deg, drawn 8 deg");
}

#[test]
fn fender_die_face_keeps_its_radii_tangency_and_draft() {
    let (sd, binder, product) = example_step_draw("fender/fender.die");
    radii_as_drawn("fender", &sd);
    tangent_seams("fender", &sd, &binder, &product);
    drafted("fender", &sd);
}

#[test]
fn door_die_face_keeps_its_radii_tangency_and_draft() {
    let (sd, binder, product) = example_step_draw("door_outer/door_outer.die");
    radii_as_drawn("door", &sd);
    tangent_seams("door", &sd, &binder, &product);
    drafted("door", &sd);
}

/// Items 1-3, 6, 7 on the hood, and item 6's sag: no section dips below its end on the
/// punch opening by more than the binder's own fall over the last 20 mm (the flat turns
/// onto the binder there).
#[test]
fn symmetric_hood_keeps_its_radii_tangency_and_draft_without_sag() {
    let (sd, binder, product) = hood_step_draw(0);
    radii_as_drawn("hood", &sd);
    tangent_seams("hood", &sd, &binder, &product);
    drafted("hood", &sd);
    let mut sag: f64 = 0.0;
    for p in &sd.patches {
        for s in &p.sections {
            let opening_z = s.start_point().z;
            let (t0, t1) = s.domain();
            for i in 0..=400 {
                let z = s.point_at(t0 + (t1 - t0) * i as f64 / 400.0).z;
                sag = sag.max(opening_z - z);
            }
        }
    }
    eprintln!("hood: deepest point below the opening {sag:.4} mm");
    assert!(
        sag <= 0.05,
        "hood: a section dips {sag} mm below the opening"
    );
}

/// Item 5: the same trim line started at each of its four corners gives the same step
/// draw (sampled on every patch, the nearest point of the other within 1e-6 mm) and
/// the same patches (no patch split at the sketch's start).
#[test]
fn hood_does_not_depend_on_where_the_trim_sketch_starts() {
    let (base, _, _) = hood_step_draw(0);
    let base_surfaces: Vec<&NurbsSurface> = base.patches.iter().map(|p| &p.surface).collect();
    for start in 1..4 {
        let (other, _, _) = hood_step_draw(start);
        let names = |s: &StepDraw| s.patches.iter().map(|p| p.name.clone()).collect::<Vec<_>>();
        assert_eq!(names(&other), names(&base), "start {start}: other patches");
        let d = farthest(&grid_points(&other, 12), &base_surfaces);
        eprintln!("trim started at corner {start}: farthest {d:.2e} mm");
        assert!(d <= 1e-6, "start {start}: {d} mm from the first build");
    }
}

/// Item 5: mirror-symmetric input, mirror-symmetric output: every point of the hood's
/// step draw mirrored in x = 0 lies on the step draw, within the tolerance the punch
/// edge follows the opening by (before: a hood's right front corner reached z = -61.67
/// mm against its mirror's -58.25 mm).
#[test]
fn symmetric_hood_gives_a_symmetric_step_draw() {
    let (sd, _, _) = hood_step_draw(0);
    let surfaces: Vec<&NurbsSurface> = sd.patches.iter().map(|p| &p.surface).collect();
    let mirrored: Vec<DVec3> = grid_points(&sd, 12)
        .into_iter()
        .map(|p| DVec3::new(-p.x, p.y, p.z))
        .collect();
    let d = farthest(&mirrored, &surfaces);
    eprintln!("hood mirrored: farthest {d:.2e} mm");
    // Each half is built on its own knots (the outline and the opening are not
    // parametrized symmetrically), and the punch edge follows the opening within a
    // tenth of the 0.01 mm tolerance on either side: 2e-3 mm bounds the difference.
    assert!(d <= 2e-3, "the mirror image is {d} mm off the step draw");
}

/// The step draw's area in one of the fuzzer's inputs, which must stay in `range`.
fn step_draw_area(file: &str, text: &str, range: std::ops::Range<f64>) {
    let (sd, _, _) = pick(script::evaluate_clean(file, text));
    let area: f64 = sd.patches.iter().map(|p| p.surface.area()).sum();
    eprintln!("{file}: step draw area {area:.0} mm²");
    assert!(
        range.contains(&area),
        "{file}: the step draw covers {area} mm²"
    );
}

/// A product corner far tighter than the step draw is wide (7 mm under 140 mm walls)
/// is matched by arc length, not along the product's normals, which would fan out over
/// 33 mm of opening per mm of product there and fold the patch: the step draw then
/// covered 8.1e6 mm² (a 242 MB GLB) where it spans about 7.6e5 mm².
#[test]
fn a_tight_product_corner_does_not_fold_the_step_draw() {
    step_draw_area(
        "tight_product_corner.die",
        include_str!("data/tight_product_corner.die"),
        7.0e5..8.0e5,
    );
}

/// Where a product normal meets the opening at a graze, the matched points race along
/// the opening and no knots of the product follow them; that patch is matched by arc
/// length instead of folding (8.6e6 mm² and a 126 MB GLB where it spans about 9.1e5).
#[test]
fn normals_that_graze_the_opening_do_not_fold_the_step_draw() {
    step_draw_area(
        "grazing_normals.die",
        include_str!("data/grazing_normals.die"),
        8.5e5..9.8e5,
    );
}
