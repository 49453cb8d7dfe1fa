//! Bad input gives typed errors, never a panic.

use dieface::geom::arc::circular_arc;
use dieface::geom::construct::{coons, loft, Loft};
use dieface::geom::interpolate::{interpolate, Interpolation, KnotPlacement};
use dieface::geom::{Curve3, GeomError, NurbsSurface, MAX_DEGREE};
use glam::DVec3;
use proptest::prelude::*;

fn pts(n: usize) -> Vec<DVec3> {
    (0..n)
        .map(|i| DVec3::new(i as f64, (i * i) as f64, 0.0))
        .collect()
}

#[test]
fn bad_knot_vectors_are_named() {
    let p = pts(4);
    let bad = |knots: Vec<f64>| Curve3::new(3, knots, p.clone()).unwrap_err();
    assert!(
        matches!(bad(vec![0.0; 7]), GeomError::KnotVector { .. }),
        "wrong length"
    );
    assert!(
        matches!(
            bad(vec![0.0, 0.0, 0.0, 0.0, 1.0, 1.0, 1.0, 0.5]),
            GeomError::KnotVector { .. }
        ),
        "decreasing"
    );
    assert!(
        matches!(
            bad(vec![0.0, 0.0, 0.0, 0.1, 1.0, 1.0, 1.0, 1.0]),
            GeomError::KnotVector { .. }
        ),
        "not clamped"
    );
    assert!(
        matches!(bad(vec![0.0; 8]), GeomError::KnotVector { .. }),
        "empty domain"
    );
    assert!(
        matches!(
            bad(vec![0.0, 0.0, 0.0, 0.0, f64::NAN, 1.0, 1.0, 1.0]),
            GeomError::KnotVector { .. }
        ),
        "NaN"
    );
    let p5 = pts(8);
    let err = Curve3::new(
        3,
        vec![0.0, 0.0, 0.0, 0.0, 0.5, 0.5, 0.5, 0.5, 1.0, 1.0, 1.0, 1.0],
        p5,
    )
    .unwrap_err();
    assert!(
        matches!(err, GeomError::KnotVector { .. }),
        "interior multiplicity above the degree"
    );
    let err = Curve3::new(0, vec![0.0, 1.0], pts(1)).unwrap_err();
    assert_eq!(
        err,
        GeomError::Degree {
            degree: 0,
            max: MAX_DEGREE
        }
    );
    assert!(matches!(
        Curve3::new(3, vec![0.0; 6], pts(2)),
        Err(GeomError::TooFewPoints {
            needed: 4,
            given: 2
        })
    ));
}

#[test]
fn bad_weights_and_points_are_named() {
    let k = vec![0.0, 0.0, 0.0, 1.0, 1.0, 1.0];
    assert_eq!(
        Curve3::new_rational(2, k.clone(), pts(3), vec![1.0, -0.5, 1.0]),
        Err(GeomError::Weight {
            index: 1,
            value: -0.5
        })
    );
    assert!(matches!(
        Curve3::new_rational(2, k.clone(), pts(3), vec![1.0, 1.0]),
        Err(GeomError::LengthMismatch { .. })
    ));
    let mut p = pts(3);
    p[1].y = f64::INFINITY;
    assert_eq!(
        Curve3::new(2, k.clone(), p),
        Err(GeomError::NotFinite {
            what: "control point"
        })
    );
    let ragged = vec![pts(3), pts(2)];
    assert!(matches!(
        NurbsSurface::new(1, 2, vec![0.0, 0.0, 1.0, 1.0], k, ragged),
        Err(GeomError::LengthMismatch { .. })
    ));
}

#[test]
fn interpolation_failures_are_named() {
    let opts = Interpolation::<DVec3>::default();
    assert!(matches!(
        interpolate(&pts(1), &opts),
        Err(GeomError::TooFewPoints { .. })
    ));
    assert!(matches!(
        interpolate(&pts(3), &opts),
        Err(GeomError::TooFewPoints {
            needed: 4,
            given: 3
        })
    ));
    let mut p = pts(5);
    p[3] = p[2];
    assert_eq!(
        interpolate(&p, &opts),
        Err(GeomError::CoincidentPoints {
            first: 2,
            second: 3
        })
    );
    let zero = Interpolation {
        start_tangent: Some(DVec3::ZERO),
        ..opts
    };
    assert_eq!(
        interpolate(&pts(5), &zero),
        Err(GeomError::ZeroVector {
            what: "end tangent"
        })
    );
    let at_params = Interpolation {
        knots: KnotPlacement::AtParameters,
        ..opts
    };
    assert!(matches!(
        interpolate(&pts(5), &at_params),
        Err(GeomError::KnotVector { .. })
    ));
}

#[test]
fn construction_failures_are_named() {
    assert!(matches!(
        circular_arc(DVec3::ZERO, DVec3::X, DVec3::Y, 0.0, 0.0, 1.0),
        Err(GeomError::NotPositive { .. })
    ));
    assert!(matches!(
        circular_arc(DVec3::ZERO, DVec3::ZERO, DVec3::Y, 1.0, 0.0, 1.0),
        Err(GeomError::ZeroVector { .. })
    ));
    let line = |a: DVec3, b: DVec3| Curve3::line(a, b).unwrap();
    let (p00, p10, p01, p11) = (DVec3::ZERO, DVec3::X, DVec3::Y, DVec3::new(1.0, 1.0, 0.0));
    let gap = coons(
        &line(p00, p10),
        &line(p01, p11),
        &line(p00, p01),
        &line(p10, p11 + DVec3::Z),
    );
    assert!(matches!(
        gap,
        Err(GeomError::CornersDoNotMeet { corner: 2, .. })
    ));
    assert!(matches!(
        loft(&[line(p00, p10)], &Loft::default()),
        Err(GeomError::TooFewPoints { .. })
    ));
    let c = line(p00, p10);
    assert!(matches!(
        c.insert_knot(1.5, 1),
        Err(GeomError::ParameterOutOfRange { .. })
    ));
    assert!(matches!(
        c.insert_knot(f64::NAN, 1),
        Err(GeomError::ParameterOutOfRange { .. })
    ));
    assert!(matches!(
        c.elevate_degree(MAX_DEGREE),
        Err(GeomError::Degree { .. })
    ));
}

fn any_f64() -> impl Strategy<Value = f64> {
    prop_oneof![
        4 => -10.0..10.0f64,
        1 => Just(0.0),
        1 => Just(f64::NAN),
        1 => Just(f64::INFINITY),
        1 => Just(-1.0),
        1 => prop::num::f64::ANY,
    ]
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(500))]

    /// Arbitrary numbers for knots, points and weights: construction succeeds or fails
    /// with an error, and whatever constructs evaluates, measures and refines without
    /// panicking, at any parameter, NaN included.
    #[test]
    fn arbitrary_input_never_panics(
        degree in 0..7usize,
        knots in prop::collection::vec(any_f64(), 0..14),
        coords in prop::collection::vec(any_f64(), 0..30),
        weights in prop::collection::vec(any_f64(), 0..10),
        t in any_f64(),
    ) {
        let points: Vec<DVec3> = coords.chunks_exact(3).map(|c| DVec3::new(c[0], c[1], c[2])).collect();
        let mut sorted = knots.clone();
        sorted.sort_by(f64::total_cmp);
        for k in [knots, sorted] {
            for c in [
                Curve3::new(degree, k.clone(), points.clone()),
                Curve3::new_rational(degree, k.clone(), points.clone(), weights.clone()),
            ].into_iter().flatten() {
                let _ = c.point_at(t);
                let _ = c.derivatives::<3>(t);
                let _ = c.curvature(t);
                let _ = c.insert_knot(t, 2);
                let _ = c.split_at(t);
                let _ = c.elevate_degree(1);
                let _ = c.parameter_at_length(t);
                let _ = c.unit_tangent(t);
            }
        }
        let _ = interpolate(&points, &Interpolation::default());
        let _ = interpolate(&points, &Interpolation { degree, start_tangent: points.first().copied(), ..Interpolation::default() });
    }
}
