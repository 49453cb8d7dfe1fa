//! The banded solve behind interpolation, and the arc-length table behind bead
//! resampling, each checked against an independent computation: nalgebra's dense LU,
//! and the curve's own integrate-from-the-start arc length.

use dieface::geom::banded::{BandMatrix, SymmetricBand};
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

    /// The symmetric band solve (banded Cholesky) gives nalgebra's dense Cholesky
    /// solution on a positive definite band matrix B Bᵀ + I (B banded), and refuses a
    /// singular one.
    #[test]
    fn symmetric_band_solve_matches_dense_cholesky(
        (n, band, values, rhs) in (2..40usize, 0..5usize).prop_flat_map(|(n, band)| (
            Just(n),
            Just(band),
            prop::collection::vec(-3.0..3.0f64, n * n),
            prop::collection::vec(-100.0..100.0f64, n),
        ))
    ) {
        // B with `band / 2` sub-diagonals and `band - band / 2` super-diagonals, so
        // B Bᵀ has `band` on either side.
        let mut b = DMatrix::<f64>::zeros(n, n);
        for i in 0..n {
            for j in i.saturating_sub(band / 2)..=(i + band - band / 2).min(n - 1) {
                b[(i, j)] = values[i * n + j];
            }
        }
        let dense = &b * b.transpose() + DMatrix::<f64>::identity(n, n);
        let mut sym = SymmetricBand::zeros(n, band);
        for i in 0..n {
            for j in 0..=i {
                if dense[(i, j)] != 0.0 {
                    prop_assert!(sym.add(i, j, dense[(i, j)]), "({i}, {j}) inside the band");
                }
            }
        }
        for i in 0..n {
            for j in 0..n {
                prop_assert_eq!(sym.get(i, j), dense[(i, j)]);
            }
        }
        let expected = dense.clone().cholesky().expect("B Bᵀ + I is positive definite")
            .solve(&DMatrix::from_column_slice(n, 1, &rhs));
        let mut x = rhs.clone();
        prop_assert!(sym.solve(&mut x).is_some());
        let scale = expected.amax().max(1.0);
        for i in 0..n {
            let d = (x[i] - expected[(i, 0)]).abs();
            prop_assert!(d <= 1e-10 * scale, "{i} off by {d}");
        }
        // A zero row makes it singular: refused, not divided by zero.
        let mut singular = SymmetricBand::zeros(n, band);
        for i in 1..n {
            singular.add(i, i, 1.0);
        }
        prop_assert!(singular.solve(&mut rhs.clone()).is_none());
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
