//! The banded solve behind interpolation, and the arc-length table behind bead
//! resampling, each checked against an independent computation: nalgebra's dense LU,
//! and the curve's own integrate-from-the-start arc length.

use dieface::geom::banded::BandMatrix;
use dieface::geom::curve::ArcLengths;
use dieface::geom::interpolate::{interpolate, Interpolation};
use glam::DVec3;
use nalgebra::DMatrix;
use proptest::prelude::*;

/// A random band matrix (with entries that need pivoting: the diagonal may be small)
/// and right-hand sides.
fn band_system() -> impl Strategy<Value = (usize, usize, usize, Vec<f64>, Vec<f64>)> {
    (3..40usize, 0..4usize, 0..4usize).prop_flat_map(|(n, lower, upper)| {
        (
            Just(n),
            Just(lower),
            Just(upper),
            prop::collection::vec(-10.0..10.0f64, n * n),
            prop::collection::vec(-100.0..100.0f64, n * 3),
        )
    })
}

proptest! {
    /// The band solve gives the dense LU's solution.
    #[test]
    fn band_solve_matches_dense_lu((n, lower, upper, values, rhs) in band_system()) {
        let mut band = BandMatrix::zeros(n, lower, upper);
        let mut dense = DMatrix::<f64>::zeros(n, n);
        for i in 0..n {
            for j in i.saturating_sub(lower)..=(i + upper).min(n - 1) {
                // A dominant-enough diagonal keeps the system well conditioned while
                // still letting pivoting pick off-diagonal rows.
                let v = values[i * n + j] + if i == j { 5.0 } else { 0.0 };
                prop_assert!(band.set(i, j, v));
                dense[(i, j)] = v;
            }
        }
        let b = DMatrix::from_row_slice(n, 3, &rhs);
        let Some(expected) = dense.clone().lu().solve(&b) else {
            return Ok(());
        };
        let condition = {
            let s = dense.singular_values();
            s.max() / s.min()
        };
        prop_assume!(condition < 1e8);
        let mut x = rhs.clone();
        prop_assert!(band.solve(&mut x, 3).is_some());
        let scale = expected.amax().max(1.0);
        for i in 0..n {
            for c in 0..3 {
                let d = (x[i * 3 + c] - expected[(i, c)]).abs();
                prop_assert!(d <= 1e-12 * condition * scale, "({i}, {c}) off by {d}");
            }
        }
    }

    /// The tabulated arc-length inverse agrees with integrating from the start.
    #[test]
    fn arc_length_table_matches_direct_inverse(
        points in prop::collection::vec((-200.0..200.0f64, -200.0..200.0f64, -50.0..50.0f64), 4..20),
        fractions in prop::collection::vec(0.0..1.0f64, 1..10),
    ) {
        let points: Vec<DVec3> = points.into_iter().map(|(x, y, z)| DVec3::new(x, y, z)).collect();
        prop_assume!(points.windows(2).all(|w| w[0].distance(w[1]) > 1.0));
        let curve = interpolate(&points, &Interpolation::default()).expect("distinct points");
        let table = ArcLengths::new(&curve);
        let total = curve.length();
        prop_assert!((table.total() - total).abs() <= 1e-9 * total);
        for f in fractions {
            let a = table.parameter_at_fraction(f).expect("in range");
            let b = curve.parameter_at_length(f * total).expect("in range");
            let (pa, pb) = (curve.point_at(a), curve.point_at(b));
            prop_assert!(pa.distance(pb) <= 1e-8 * total.max(1.0), "f = {f}: {pa} vs {pb}");
        }
    }
}

/// A singular system (a zero column) is reported, not solved.
#[test]
fn singular_band_is_refused() {
    let mut band = BandMatrix::zeros(3, 1, 1);
    for (i, j, v) in [(0, 0, 1.0), (1, 0, 2.0), (2, 2, 1.0)] {
        assert!(band.set(i, j, v));
    }
    let mut x = vec![1.0, 2.0, 3.0];
    assert!(band.solve(&mut x, 1).is_none());
}

/// A value outside the declared band is refused, not stored.
#[test]
fn band_refuses_entries_outside_it() {
    let mut band = BandMatrix::zeros(5, 1, 1);
    assert!(band.set(2, 1, 1.0));
    assert!(band.set(2, 3, 1.0));
    assert!(!band.set(3, 1, 1.0));
    assert!(!band.set(1, 3, 1.0));
    assert_eq!(band.get(3, 1), 0.0);
}
