//! Gauss-Legendre quadrature tables: the one place the kernel's integrals (arc length,
//! an offset's length and turn, a trimmed face's area) take their nodes and weights.

use std::ops::{Add, Mul};

/// 10-point Gauss-Legendre nodes on [-1, 1], the positive half (the rule is symmetric:
/// each node `x` stands with `-x`); exact for polynomials up to degree 19.
pub const NODES_10: [f64; 5] = [
    0.148_874_338_981_631_21,
    0.433_395_394_129_247_2,
    0.679_409_568_299_024_4,
    0.865_063_366_688_984_5,
    0.973_906_528_517_171_7,
];

/// The weights of [`NODES_10`] (each shared by `x` and `-x`).
pub const WEIGHTS_10: [f64; 5] = [
    0.295_524_224_714_752_9,
    0.269_266_719_309_996_4,
    0.219_086_362_515_982,
    0.149_451_349_150_580_6,
    0.066_671_344_308_688_1,
];

/// 8-point Gauss-Legendre nodes on [-1, 1], all of them in increasing order; exact for
/// polynomials up to degree 15.
pub const NODES_8: [f64; 8] = [
    -0.960_289_856_497_536_3,
    -0.796_666_477_413_626_7,
    -0.525_532_409_916_329,
    -0.183_434_642_495_649_8,
    0.183_434_642_495_649_8,
    0.525_532_409_916_329,
    0.796_666_477_413_626_7,
    0.960_289_856_497_536_3,
];

/// The weights of [`NODES_8`].
pub const WEIGHTS_8: [f64; 8] = [
    0.101_228_536_290_376_3,
    0.222_381_034_453_374_5,
    0.313_706_645_877_887_3,
    0.362_683_783_378_362,
    0.362_683_783_378_362,
    0.313_706_645_877_887_3,
    0.222_381_034_453_374_5,
    0.101_228_536_290_376_3,
];

/// The integral of `f` over `[a, b]` by the 10-point rule. `T` is any value that adds
/// and scales like a number (`f64`, or `DVec2` for two integrals taken at once at the
/// same nodes).
pub fn gauss_legendre_10<T>(f: impl Fn(f64) -> T, a: f64, b: f64) -> T
where
    T: Copy + Default + Add<Output = T> + Mul<f64, Output = T>,
{
    let (half, mid) = (0.5 * (b - a), 0.5 * (a + b));
    let mut s = T::default();
    for (x, w) in NODES_10.iter().zip(WEIGHTS_10) {
        let dx = half * x;
        s = s + (f(mid - dx) + f(mid + dx)) * w;
    }
    s * half
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::DVec2;

    /// The defining property of an n-point rule: exact for every power up to 2n - 1.
    #[test]
    fn ten_points_are_exact_to_degree_19() {
        let (a, b) = (-0.5f64, 2.0f64);
        for k in 0..=19 {
            let exact = (b.powi(k + 1) - a.powi(k + 1)) / f64::from(k + 1);
            let got = gauss_legendre_10(|t| t.powi(k), a, b);
            assert!(
                (got - exact).abs() <= 1e-12 * exact.abs().max(1.0),
                "t^{k}: {got} vs {exact}"
            );
        }
    }

    #[test]
    fn eight_points_are_exact_to_degree_15() {
        for k in 0..=15 {
            let exact = if k % 2 == 0 {
                2.0 / f64::from(k + 1)
            } else {
                0.0
            };
            let got: f64 = NODES_8
                .iter()
                .zip(WEIGHTS_8)
                .map(|(x, w)| w * x.powi(k))
                .sum();
            assert!((got - exact).abs() <= 1e-14, "x^{k}: {got} vs {exact}");
        }
    }

    #[test]
    fn two_integrals_at_once() {
        let v = gauss_legendre_10(|t| DVec2::new(t, t * t), 0.0, 3.0);
        assert!((v - DVec2::new(4.5, 9.0)).length() < 1e-12);
    }
}
