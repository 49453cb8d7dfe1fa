//! Sketches: the drawing commands turned into exact NURBS profiles.

#![allow(clippy::result_large_err)] // Diagnostic is large by design, as in the library

use std::f64::consts::PI;

use dieface::eval::sketch::{build, Command, Sketch, View};
use dieface::syntax::{FileId, Span};
use glam::{DVec2, DVec3};

fn sp(i: usize) -> Span {
    Span::new(FileId(0), 10 * i, 10 * i + 5)
}

const WHOLE: Span = Span {
    file: FileId(0),
    start: 0,
    end: 1000,
};

fn draw(view: View, commands: Vec<Command>) -> Result<Sketch, dieface::diag::Diagnostic> {
    let cmds: Vec<(Command, Span)> = commands
        .into_iter()
        .enumerate()
        .map(|(i, c)| (c, sp(i)))
        .collect();
    build(view, &cmds, WHOLE)
}

fn p(x: f64, y: f64) -> DVec2 {
    DVec2::new(x, y)
}

/// Samples a parameter range.
fn samples(range: (f64, f64), n: usize) -> impl Iterator<Item = f64> {
    (0..=n).map(move |k| range.0 + (range.1 - range.0) * k as f64 / n as f64)
}

#[test]
fn rectangle_with_four_fillets() {
    use Command::*;
    let r = 5.0;
    let s = draw(
        View::Top,
        vec![
            From(p(0.0, 0.0)),
            Fillet(r),
            LineTo(p(100.0, 0.0)),
            Fillet(r),
            LineTo(p(100.0, 60.0)),
            Fillet(r),
            LineTo(p(0.0, 60.0)),
            Fillet(r),
            Close,
        ],
    )
    .unwrap();
    assert!(s.closed);
    let kinds: Vec<&str> = s.segments.iter().map(|g| g.kind).collect();
    assert_eq!(
        kinds,
        ["line", "fillet", "line", "fillet", "line", "fillet", "line", "fillet"]
    );
    assert_eq!(s.curve.domain(), (0.0, 8.0));
    assert_eq!(s.curve.degree(), 2);
    assert!(s.curve.start_point().distance(s.curve.end_point()) < 1e-12);
    // The closing line carries the span of `close`, fillets the span of their command.
    assert_eq!(s.segments[6].span, sp(8));
    assert_eq!(s.segments[7].span, sp(1));
    assert_eq!(s.segments[1].span, sp(3));
    // Every fillet is an exact quarter circle about the corner's inset point.
    let centres = [p(95.0, 5.0), p(95.0, 55.0), p(5.0, 55.0), p(5.0, 5.0)];
    for (k, seg) in s.segments.iter().filter(|g| g.kind == "fillet").enumerate() {
        for t in samples(seg.range, 40) {
            let d = s.curve.point_at(t).distance(centres[k]);
            assert!((d - r).abs() < 1e-12, "fillet {k} at {t}: distance {d}");
        }
    }
    // Lines are straight and on the rectangle's sides.
    let line = &s.segments[0];
    for t in samples(line.range, 10) {
        assert!(s.curve.point_at(t).y.abs() < 1e-12);
    }
    let expected = 2.0 * (100.0 + 60.0) - 8.0 * r + 2.0 * PI * r;
    assert!(
        (s.curve.length() - expected).abs() < 1e-9,
        "length {} vs {expected}",
        s.curve.length()
    );
    // Placed in the top view at z = 0.
    let c3 = s.to_3d();
    assert_eq!(c3.point_at(0.5).z, 0.0);
}

#[test]
fn fillet_after_close_rounds_the_start_corner() {
    use Command::*;
    // The order std/sketch's `rectangle` uses: the last fillet comes after `close`.
    let r = 60.0;
    let s = draw(
        View::Top,
        vec![
            From(p(-550.0, -350.0)),
            LineTo(p(550.0, -350.0)),
            Fillet(r),
            LineTo(p(550.0, 350.0)),
            Fillet(r),
            LineTo(p(-550.0, 350.0)),
            Fillet(r),
            Close,
            Fillet(r),
        ],
    )
    .unwrap();
    assert!(s.closed);
    assert_eq!(s.segments.iter().filter(|g| g.kind == "fillet").count(), 4);
    assert_eq!(s.segments.last().unwrap().span, sp(8));
    let expected = 2.0 * (1100.0 + 700.0) - 8.0 * r + 2.0 * PI * r;
    assert!((s.curve.length() - expected).abs() < 1e-8);
    for t in samples(s.segments.last().unwrap().range, 20) {
        assert!((s.curve.point_at(t).distance(p(-490.0, -290.0)) - r).abs() < 1e-10);
    }
    // `fillet 0` anywhere is no fillet.
    let s = draw(
        View::Top,
        vec![
            From(p(0.0, 0.0)),
            LineTo(p(10.0, 0.0)),
            LineTo(p(10.0, 10.0)),
            Close,
            Fillet(0.0),
        ],
    )
    .unwrap();
    assert_eq!(s.segments.len(), 3);
    // Two fillets at the start corner.
    let e = draw(
        View::Top,
        vec![
            From(p(0.0, 0.0)),
            Fillet(1.0),
            LineTo(p(10.0, 0.0)),
            LineTo(p(10.0, 10.0)),
            Close,
            Fillet(1.0),
        ],
    )
    .unwrap_err();
    assert_eq!(e.message, "two fillets at the start corner");
    assert_eq!(e.primary.span, sp(5));
}

#[test]
fn fillets_can_use_up_a_whole_line() {
    use Command::*;
    // A 40 x 20 rectangle with 10 mm fillets: the short sides vanish (a slot).
    let s = draw(
        View::Top,
        vec![
            From(p(0.0, 0.0)),
            Fillet(10.0),
            LineTo(p(40.0, 0.0)),
            Fillet(10.0),
            LineTo(p(40.0, 20.0)),
            Fillet(10.0),
            LineTo(p(0.0, 20.0)),
            Fillet(10.0),
            Close,
        ],
    )
    .unwrap();
    let kinds: Vec<&str> = s.segments.iter().map(|g| g.kind).collect();
    assert_eq!(
        kinds,
        ["line", "fillet", "fillet", "line", "fillet", "fillet"]
    );
    let expected = 2.0 * 20.0 + 2.0 * PI * 10.0;
    assert!((s.curve.length() - expected).abs() < 1e-9);
}

/// A fillet where the lines continue straight on has no corner to round: an error at
/// the fillet naming both lines (it used to be dropped silently, issue 14).
#[test]
fn fillet_at_a_straight_corner_is_an_error() {
    use Command::*;
    let commands = vec![
        From(p(0.0, 0.0)),
        LineTo(p(10.0, 0.0)),
        Fillet(3.0),
        LineTo(p(20.0, 0.0)),
    ];
    let e = dieface::geom::sketch::draw(&commands).unwrap_err();
    assert_eq!(
        e,
        dieface::geom::sketch::SketchError::FilletNoCorner {
            fillet: 2,
            prev: 1,
            next: 3
        }
    );
    // `fillet 0` stays a sharp corner, wherever it is.
    let zero = vec![
        From(p(0.0, 0.0)),
        LineTo(p(10.0, 0.0)),
        Fillet(0.0),
        LineTo(p(20.0, 0.0)),
    ];
    assert!(dieface::geom::sketch::draw(&zero).is_ok());
}

#[test]
fn fillet_on_an_oblique_corner() {
    use Command::*;
    // 60 degree corner: tangent length r / tan(30 deg).
    let r = 4.0;
    let s = draw(
        View::Top,
        vec![
            From(p(0.0, 0.0)),
            LineTo(p(50.0, 0.0)),
            Fillet(r),
            LineTo(p(50.0 - 50.0 * 0.5, 50.0 * 3f64.sqrt() / 2.0)),
        ],
    )
    .unwrap();
    let f = &s.segments[1];
    assert_eq!(f.kind, "fillet");
    let t = r / (PI / 6.0).tan();
    let start = s.curve.point_at(f.range.0);
    assert!(start.distance(p(50.0 - t, 0.0)) < 1e-12);
    // Centre on the bisector at r / sin(30 deg) from the corner.
    let bis = (p(-1.0, 0.0) + p(-0.5, 3f64.sqrt() / 2.0)).normalize();
    let centre = p(50.0, 0.0) + bis * (r / (PI / 6.0).sin());
    for u in samples(f.range, 20) {
        assert!((s.curve.point_at(u).distance(centre) - r).abs() < 1e-12);
    }
    // G1 at both ends of the fillet.
    let d_before = s.curve.derivative_at(f.range.0 - 1e-9).normalize();
    let d_after = s.curve.derivative_at(f.range.0 + 1e-9).normalize();
    assert!(d_before.angle_to(d_after).abs() < 1e-6);
}

#[test]
fn tangent_arc_continues_a_line() {
    use Command::*;
    let s = draw(
        View::Top,
        vec![
            From(p(0.0, 0.0)),
            LineTo(p(30.0, 0.0)),
            TangentArcTo(p(40.0, 10.0)),
        ],
    )
    .unwrap();
    assert_eq!(s.segments[1].kind, "arc");
    // The joint at t = 1 is G1.
    let (d1, d2) = {
        let left = s.curve.derivatives::<2>(1.0 - 1e-12)[1];
        let right = s.curve.derivatives::<2>(1.0 + 1e-12)[1];
        (left, right)
    };
    assert!(d1.angle_to(d2).abs() < 1e-9, "angle {}", d1.angle_to(d2));
    // A quarter circle of radius 10 about (30, 10).
    for t in samples(s.segments[1].range, 30) {
        assert!((s.curve.point_at(t).distance(p(30.0, 10.0)) - 10.0).abs() < 1e-12);
    }
    assert!(s.curve.end_point().distance(p(40.0, 10.0)) == 0.0);

    // A long way round (more than a half turn), turning right.
    let s = draw(
        View::Top,
        vec![
            From(p(0.0, 0.0)),
            LineTo(p(10.0, 0.0)),
            TangentArcTo(p(5.0, -1.0)),
        ],
    )
    .unwrap();
    let seg = &s.segments[1];
    let start_dir = s.curve.derivatives::<2>(seg.range.0 + 1e-12)[1].normalize();
    assert!(start_dir.distance(DVec2::X) < 1e-9);
    assert!(s.curve.end_point() == p(5.0, -1.0));
    // The centre lies below the line: (10, -k) with |(5,-1) - c| = k.
    let k = (25.0 + 1.0) / 2.0;
    for t in samples(seg.range, 30) {
        assert!((s.curve.point_at(t).distance(p(10.0, -k)) - k).abs() < 1e-10);
    }

    // On the tangent line ahead: a straight continuation.
    let s = draw(
        View::Top,
        vec![
            From(p(0.0, 0.0)),
            LineTo(p(10.0, 0.0)),
            TangentArcTo(p(25.0, 0.0)),
        ],
    )
    .unwrap();
    assert_eq!(s.segments[1].kind, "line");
}

#[test]
fn tangent_arc_after_an_arc() {
    use Command::*;
    let s = draw(
        View::SideXZ,
        vec![
            From(p(0.0, 0.0)),
            ArcThrough {
                to: p(20.0, 0.0),
                through: p(10.0, 10.0),
            },
            TangentArcTo(p(30.0, -10.0)),
        ],
    )
    .unwrap();
    let left = s.curve.derivatives::<2>(1.0 - 1e-12)[1];
    let right = s.curve.derivatives::<2>(1.0 + 1e-12)[1];
    assert!(left.angle_to(right).abs() < 1e-9);
    // The side view puts sketch y on press z.
    assert_eq!(s.view.place(p(3.0, 4.0)), DVec3::new(3.0, 0.0, 4.0));
}

#[test]
fn arc_through_three_points() {
    use Command::*;
    let s = draw(
        View::Top,
        vec![
            From(p(10.0, 0.0)),
            ArcThrough {
                to: p(-10.0, 0.0),
                through: p(0.0, 10.0),
            },
        ],
    )
    .unwrap();
    assert_eq!(s.segments[0].kind, "arc");
    assert!(s.curve.is_rational());
    for t in samples((0.0, 1.0), 50) {
        assert!((s.curve.point_at(t).length() - 10.0).abs() < 1e-12);
    }
    // It passes through the middle point and runs counter-clockwise (through y > 0).
    let mid = s.curve.point_at(0.5);
    assert!(mid.distance(p(0.0, 10.0)) < 1e-12, "{mid}");
    assert!((s.curve.length() - PI * 10.0).abs() < 1e-9);
}

#[test]
fn spline_with_tangent_leaves_along_the_line() {
    use Command::*;
    let through = vec![p(30.0, 5.0), p(40.0, 20.0), p(50.0, 22.0)];
    let s = draw(
        View::Top,
        vec![
            From(p(0.0, 0.0)),
            LineTo(p(20.0, 0.0)),
            Spline {
                through: through.clone(),
                tangent: true,
            },
        ],
    )
    .unwrap();
    let seg = &s.segments[1];
    assert_eq!(seg.kind, "spline");
    let d = s.curve.derivatives::<2>(seg.range.0 + 1e-12)[1];
    assert!(d.angle_to(DVec2::X).abs() < 1e-9, "start direction {d}");
    for q in &through {
        let hit = samples(seg.range, 2000)
            .map(|t| s.curve.point_at(t).distance(*q))
            .fold(f64::INFINITY, f64::min);
        assert!(hit < 0.05, "spline misses {q}: {hit}");
    }
    assert_eq!(s.curve.end_point(), p(50.0, 22.0));

    // Without `tangent` the spline starts in its own direction (a corner here).
    let s = draw(
        View::Top,
        vec![
            From(p(0.0, 0.0)),
            LineTo(p(20.0, 0.0)),
            Spline {
                through,
                tangent: false,
            },
        ],
    )
    .unwrap();
    let d = s.curve.derivatives::<2>(1.0 + 1e-12)[1];
    assert!(d.angle_to(DVec2::X).abs() > 1e-3);
}

#[test]
fn section_view_places_points_by_eq_5() {
    use Command::*;
    let a = p(100.0, 50.0);
    let b = p(130.0, 90.0); // direction (0.6, 0.8)
    let view = View::Section { a, b };
    let s = draw(
        view,
        vec![
            From(p(0.0, 0.0)),
            LineTo(p(10.0, 0.0)),
            LineTo(p(10.0, -5.0)),
        ],
    )
    .unwrap();
    let c3 = s.to_3d();
    assert!(c3.start_point().distance(DVec3::new(100.0, 50.0, 0.0)) < 1e-12);
    let corner = c3.point_at(1.0);
    assert!(
        corner.distance(DVec3::new(106.0, 58.0, 0.0)) < 1e-12,
        "{corner}"
    );
    assert!(c3.end_point().distance(DVec3::new(106.0, 58.0, -5.0)) < 1e-12);
    // And in general: (s, z) -> a + s dir + z Z.
    let q = view.place(p(-3.0, 7.0));
    assert!(q.distance(DVec3::new(100.0 - 1.8, 50.0 - 2.4, 7.0)) < 1e-12);
    assert_eq!(View::SideYZ.place(p(3.0, 4.0)), DVec3::new(0.0, 3.0, 4.0));
}

#[test]
fn closing_at_the_start_adds_no_line() {
    use Command::*;
    let s = draw(
        View::Top,
        vec![
            From(p(0.0, 0.0)),
            LineTo(p(10.0, 0.0)),
            ArcThrough {
                to: p(0.0, 0.0),
                through: p(5.0, 5.0),
            },
            Close,
        ],
    )
    .unwrap();
    assert!(s.closed);
    assert_eq!(s.segments.len(), 2);
}

// ---- errors ------------------------------------------------------------------------

fn error(commands: Vec<Command>) -> dieface::diag::Diagnostic {
    draw(View::Top, commands).unwrap_err()
}

#[test]
fn missing_from() {
    use Command::*;
    let e = error(vec![LineTo(p(1.0, 0.0)), LineTo(p(2.0, 0.0))]);
    assert_eq!(e.code, "die::sketch");
    assert_eq!(e.message, "a sketch starts with `from (x, y)`");
    assert_eq!(e.primary.span, sp(0));
    let e = build(View::Top, &[], WHOLE).unwrap_err();
    assert_eq!(e.message, "a sketch starts with `from (x, y)`");
    assert_eq!(e.primary.span, WHOLE);
    let e = error(vec![
        From(p(0.0, 0.0)),
        LineTo(p(1.0, 0.0)),
        From(p(5.0, 5.0)),
    ]);
    assert_eq!(e.primary.span, sp(2));
}

#[test]
fn fillet_too_large() {
    use Command::*;
    let e = error(vec![
        From(p(0.0, 0.0)),
        LineTo(p(40.0, 0.0)),
        Fillet(90.0),
        LineTo(p(40.0, 60.0)),
    ]);
    assert_eq!(e.code, "die::sketch");
    assert_eq!(
        e.message,
        "fillet 90 mm does not fit: the lines are 40 mm and 60 mm long"
    );
    assert_eq!(e.primary.span, sp(2));
    assert_eq!(e.secondary[0].span, sp(1));
    assert_eq!(e.secondary[1].span, sp(3));
    let help = e.help.unwrap();
    assert!(help.contains("the largest that fits is 40 mm"), "{help}");
    assert!(help.contains("90 deg corner"), "{help}");
}

#[test]
fn fillet_needs_lines_and_a_next_segment() {
    use Command::*;
    let e = error(vec![
        From(p(0.0, 0.0)),
        LineTo(p(10.0, 0.0)),
        Fillet(1.0),
        ArcThrough {
            to: p(20.0, 10.0),
            through: p(17.0, 3.0),
        },
    ]);
    assert_eq!(e.message, "a fillet rounds the corner between two lines");
    assert_eq!(e.primary.span, sp(2));
    assert_eq!(e.secondary[0].span, sp(3));

    let e = error(vec![From(p(0.0, 0.0)), LineTo(p(10.0, 0.0)), Fillet(1.0)]);
    assert_eq!(e.message, "this fillet has no second segment to round to");
    assert_eq!(e.primary.span, sp(2));

    let e = error(vec![
        From(p(0.0, 0.0)),
        Fillet(1.0),
        LineTo(p(10.0, 0.0)),
        LineTo(p(10.0, 10.0)),
    ]);
    assert!(
        e.message.contains("only a closed sketch has"),
        "{}",
        e.message
    );
    assert_eq!(e.primary.span, sp(1));

    let e = error(vec![
        From(p(0.0, 0.0)),
        LineTo(p(10.0, 0.0)),
        Fillet(-1.0),
        LineTo(p(10.0, 10.0)),
    ]);
    assert!(e.message.contains("must be positive"));
}

#[test]
fn zero_length_line() {
    use Command::*;
    let e = error(vec![From(p(3.0, 4.0)), LineTo(p(3.0, 4.0))]);
    assert_eq!(e.code, "die::sketch");
    assert_eq!(
        e.message,
        "this line ends where it starts, at (3, 4): a zero-length line"
    );
    assert_eq!(e.primary.span, sp(1));
}

#[test]
fn repeated_spline_point() {
    use Command::*;
    let e = error(vec![
        From(p(0.0, 0.0)),
        Spline {
            through: vec![p(10.0, 0.0), p(20.0, 5.0), p(20.0, 5.0), p(30.0, 0.0)],
            tangent: false,
        },
    ]);
    assert_eq!(
        e.message,
        "the spline passes through (20, 5) twice in a row (items 2 and 3 of the list, counting from 1)"
    );
    assert_eq!(e.primary.span, sp(1));
    let e = error(vec![
        From(p(0.0, 0.0)),
        Spline {
            through: vec![p(0.0, 0.0), p(20.0, 5.0)],
            tangent: false,
        },
    ]);
    assert!(
        e.message.starts_with("point 1 of the spline"),
        "{}",
        e.message
    );
}

#[test]
fn other_degenerate_input() {
    use Command::*;
    let e = error(vec![
        From(p(0.0, 0.0)),
        ArcThrough {
            to: p(20.0, 0.0),
            through: p(10.0, 0.0),
        },
    ]);
    assert!(e.message.contains("lie on one line"), "{}", e.message);
    assert_eq!(e.primary.span, sp(1));
    let e = error(vec![From(p(0.0, 0.0)), TangentArcTo(p(20.0, 0.0))]);
    assert!(e.message.contains("there is none"), "{}", e.message);
    let e = error(vec![
        From(p(0.0, 0.0)),
        LineTo(p(10.0, 0.0)),
        TangentArcTo(p(-5.0, 0.0)),
    ]);
    assert!(e.message.contains("behind"), "{}", e.message);
    let e = error(vec![
        From(p(0.0, 0.0)),
        LineTo(p(10.0, 0.0)),
        Close,
        LineTo(p(1.0, 1.0)),
    ]);
    assert_eq!(e.message, "the sketch is already closed");
    assert_eq!(e.primary.span, sp(3));
    let e = error(vec![From(p(0.0, 0.0))]);
    assert_eq!(
        e.message,
        "a sketch needs at least one segment after `from`"
    );
    let e = error(vec![
        From(p(0.0, 0.0)),
        LineTo(p(10.0, 0.0)),
        Fillet(1.0),
        LineTo(p(0.0, 0.0)),
    ]);
    assert!(e.message.contains("double back"), "{}", e.message);
}

struct Rng(u64);

impl Rng {
    fn below(&mut self, n: usize) -> usize {
        self.0 ^= self.0 << 13;
        self.0 ^= self.0 >> 7;
        self.0 ^= self.0 << 17;
        (self.0 % n as u64) as usize
    }
}

#[test]
fn random_command_sequences_never_panic() {
    use Command::*;
    let mut rng = Rng(0x9E37_79B9_7F4A_7C15);
    let coords = [0.0, 10.0, -10.0, 5.0, 1e-12, 1e300, f64::NAN];
    let pt = |rng: &mut Rng| p(coords[rng.below(5)], coords[rng.below(coords.len())]);
    let mut ok = 0;
    for _ in 0..5000 {
        let n = 1 + rng.below(8);
        let mut cmds = vec![From(pt(&mut rng))];
        for _ in 0..n {
            let c = match rng.below(8) {
                0 | 1 => LineTo(pt(&mut rng)),
                2 => ArcThrough {
                    to: pt(&mut rng),
                    through: pt(&mut rng),
                },
                3 => TangentArcTo(pt(&mut rng)),
                4 => {
                    let k = rng.below(4);
                    Spline {
                        through: (0..k).map(|_| pt(&mut rng)).collect(),
                        tangent: rng.below(2) == 0,
                    }
                }
                5 | 6 => Fillet([0.0, 1.0, 3.0, 100.0, -1.0][rng.below(5)]),
                _ => Close,
            };
            cmds.push(c);
        }
        if rng.below(10) == 0 {
            cmds.remove(0);
        }
        if let Ok(s) = draw(View::Top, cmds) {
            ok += 1;
            assert_eq!(s.curve.domain(), (0.0, s.segments.len() as f64));
            if s.closed {
                assert!(s.curve.start_point().distance(s.curve.end_point()) < 1e-6);
            }
        }
    }
    assert!(ok > 100, "only {ok} sketches built");
}

/// The kernel's drawing on its own: segments name the command that drew them, and a
/// fillet that does not fit says which commands and what would fit.
#[test]
fn the_kernel_draws_a_profile_and_names_commands() {
    use dieface::geom::sketch::{draw as kernel_draw, SketchError};
    let commands = [
        Command::From(p(0.0, 0.0)),
        Command::LineTo(p(100.0, 0.0)),
        Command::Fillet(10.0),
        Command::LineTo(p(100.0, 50.0)),
        Command::Close,
    ];
    let profile = kernel_draw(&commands).unwrap();
    assert!(profile.closed);
    let drawn: Vec<(&str, usize)> = profile
        .segments
        .iter()
        .map(|s| (s.kind, s.command))
        .collect();
    assert_eq!(
        drawn,
        [("line", 1), ("fillet", 2), ("line", 3), ("line", 4)]
    );
    // The fillet is tangent to both lines, 10 mm from the corner (a right angle).
    let (a, b) = profile.segments[1].range;
    assert!(profile.curve.point_at(a).distance(p(90.0, 0.0)) < 1e-9);
    assert!(profile.curve.point_at(b).distance(p(100.0, 10.0)) < 1e-9);
    let centre = p(90.0, 10.0);
    for t in samples((a, b), 16) {
        assert!((profile.curve.point_at(t).distance(centre) - 10.0).abs() < 1e-9);
    }

    let too_big = [
        Command::From(p(0.0, 0.0)),
        Command::LineTo(p(10.0, 0.0)),
        Command::Fillet(400.0),
        Command::LineTo(p(10.0, 8.0)),
    ];
    match kernel_draw(&too_big) {
        Err(SketchError::FilletDoesNotFit {
            fillet: 2,
            prev: 1,
            next: 3,
            largest,
            ..
        }) => assert!((largest - 8.0).abs() < 1e-9),
        other => panic!("expected a fillet that does not fit, got {other:?}"),
    }
}
