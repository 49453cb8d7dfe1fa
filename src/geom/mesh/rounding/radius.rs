//! The radius of a round along its chain (paper 000, section 2, step 5): constant, or
//! given at some places along the chain and interpolated between them by a cubic
//! spline in arc length, as the paper does. An open chain's spline is natural (no bend
//! at its ends) and holds its end radii beyond the first and last given places; a
//! closed chain's spline is periodic, so the radius runs on smoothly round the start.

use nalgebra::{DMatrix, DVector};

/// The ball's radius as a function of arc length along the chain.
#[derive(Debug, Clone, PartialEq)]
pub struct RadiusLaw {
    /// Where along the chain radii are given (mm of arc length), ascending.
    at: Vec<f64>,
    /// The radii given there (mm).
    radii: Vec<f64>,
    /// The spline's second derivative at each given place.
    second: Vec<f64>,
    /// The chain's length, when it is closed (the spline's period).
    period: Option<f64>,
}

/// Why radii could not be interpolated.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum RadiusError {
    /// No radius given.
    #[error("no radius is given")]
    Empty,
    /// A radius at or below zero, or not finite.
    #[error("radius {} (counting from 1) is {radius} mm: a radius must be above 0 mm", .index + 1)]
    NotPositive { index: usize, radius: f64 },
    /// Two radii given at one place along the chain.
    #[error("radii {} and {} (counting from 1) are given at the same place along the chain", .first + 1, .second + 1)]
    SamePlace { first: usize, second: usize },
    /// The spline through the given radii dips to zero or below between them.
    #[error("the spline through the radii falls to {radius} mm at {at} mm along the chain")]
    Dips { at: f64, radius: f64 },
}

impl RadiusLaw {
    /// The same radius all along.
    pub fn constant(radius: f64) -> RadiusLaw {
        RadiusLaw {
            at: vec![0.0],
            radii: vec![radius],
            second: vec![0.0],
            period: None,
        }
    }

    /// The cubic spline through `given` (arc length along the chain, radius), the
    /// chain `length` long and `closed` or not. Refused when a radius is not above
    /// zero, two are given at one place, or the spline dips to zero between them.
    pub fn through(
        given: &[(f64, f64)],
        length: f64,
        closed: bool,
    ) -> Result<RadiusLaw, RadiusError> {
        if given.is_empty() {
            return Err(RadiusError::Empty);
        }
        for (index, &(_, radius)) in given.iter().enumerate() {
            if !(radius.is_finite() && radius > 0.0) {
                return Err(RadiusError::NotPositive { index, radius });
            }
        }
        let period = (closed && length > 0.0).then_some(length);
        let mut order: Vec<usize> = (0..given.len()).collect();
        let place = |i: usize| match period {
            Some(p) => given[i].0.rem_euclid(p),
            None => given[i].0,
        };
        order.sort_by(|&a, &b| place(a).total_cmp(&place(b)).then(a.cmp(&b)));
        let same = 1e-9 * length.max(1.0);
        for w in order.windows(2) {
            if place(w[1]) - place(w[0]) <= same {
                return Err(RadiusError::SamePlace {
                    first: w[0].min(w[1]),
                    second: w[0].max(w[1]),
                });
            }
        }
        if let (Some(p), Some(&first), Some(&last)) = (period, order.first(), order.last()) {
            if order.len() > 1 && place(first) + p - place(last) <= same {
                return Err(RadiusError::SamePlace {
                    first: first.min(last),
                    second: first.max(last),
                });
            }
        }
        let at: Vec<f64> = order.iter().map(|&i| place(i)).collect();
        let radii: Vec<f64> = order.iter().map(|&i| given[i].1).collect();
        let second = second_derivatives(&at, &radii, period);
        let law = RadiusLaw {
            at,
            radii,
            second,
            period,
        };
        // The spline overshoots between radii that change sharply: sampled finely, it
        // must stay above zero.
        let samples = 400;
        for k in 0..=samples {
            let s = length * k as f64 / samples as f64;
            let radius = law.at(s);
            if radius <= 0.0 {
                return Err(RadiusError::Dips { at: s, radius });
            }
        }
        Ok(law)
    }

    /// The radius at arc length `s` along the chain.
    pub fn at(&self, s: f64) -> f64 {
        let n = self.at.len();
        if n == 1 {
            return self.radii[0];
        }
        match self.period {
            None => {
                if s <= self.at[0] {
                    return self.radii[0];
                }
                if s >= self.at[n - 1] {
                    return self.radii[n - 1];
                }
                let i = self.at.partition_point(|&a| a <= s).clamp(1, n - 1) - 1;
                self.piece(i, i + 1, self.at[i + 1] - self.at[i], s - self.at[i])
            }
            Some(p) => {
                let s = s.rem_euclid(p);
                // The piece holding s: from the last given place at or before it (the
                // last of all, wrapping round, before the first).
                let after = self.at.partition_point(|&a| a <= s);
                let (i, j) = if after == 0 {
                    (n - 1, 0)
                } else {
                    (after - 1, after % n)
                };
                let h = (self.at[j] - self.at[i]).rem_euclid(p);
                let h = if h == 0.0 { p } else { h };
                let t = (s - self.at[i]).rem_euclid(p);
                self.piece(i, j, h, t)
            }
        }
    }

    /// The spline's piece from given place `i` to `j`, `h` long, at `t` into it.
    fn piece(&self, i: usize, j: usize, h: f64, t: f64) -> f64 {
        let (a, b) = ((h - t) / h, t / h);
        let (mi, mj) = (self.second[i], self.second[j]);
        a * self.radii[i]
            + b * self.radii[j]
            + ((a * a * a - a) * mi + (b * b * b - b) * mj) * h * h / 6.0
    }

    /// The mean radius over a chain `length` long: the radius the base meshes are
    /// reached for and the spine found at.
    pub fn mean(&self, length: f64) -> f64 {
        let samples = 256;
        if self.at.len() == 1 || length <= 0.0 {
            return self.radii[0];
        }
        (0..samples)
            .map(|k| self.at(length * (k as f64 + 0.5) / samples as f64))
            .sum::<f64>()
            / samples as f64
    }

    /// The smallest and largest radius over a chain `length` long.
    pub fn range(&self, length: f64) -> (f64, f64) {
        let samples = 256;
        (0..=samples)
            .map(|k| self.at(length * k as f64 / samples as f64))
            .chain(self.radii.iter().copied())
            .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), r| {
                (lo.min(r), hi.max(r))
            })
    }

    /// Whether the radius is the same all along.
    pub fn is_constant(&self) -> bool {
        self.radii.iter().all(|&r| r == self.radii[0])
    }
}

/// The second derivatives of the cubic spline through `(at, radii)`: natural (zero at
/// the ends) when open, periodic over `period` when closed. Two places alone give a
/// straight line when open.
fn second_derivatives(at: &[f64], radii: &[f64], period: Option<f64>) -> Vec<f64> {
    let n = at.len();
    if n < 2 || (period.is_none() && n < 3) {
        return vec![0.0; n];
    }
    let mut a = DMatrix::<f64>::zeros(n, n);
    let mut b = DVector::<f64>::zeros(n);
    match period {
        None => {
            a[(0, 0)] = 1.0;
            a[(n - 1, n - 1)] = 1.0;
            for i in 1..n - 1 {
                let (h0, h1) = (at[i] - at[i - 1], at[i + 1] - at[i]);
                a[(i, i - 1)] += h0;
                a[(i, i)] += 2.0 * (h0 + h1);
                a[(i, i + 1)] += h1;
                b[i] = 6.0 * ((radii[i + 1] - radii[i]) / h1 - (radii[i] - radii[i - 1]) / h0);
            }
        }
        Some(p) => {
            let gap = |i: usize| {
                let j = (i + 1) % n;
                let h = (at[j] - at[i]).rem_euclid(p);
                if h == 0.0 {
                    p
                } else {
                    h
                }
            };
            for i in 0..n {
                let prev = (i + n - 1) % n;
                let next = (i + 1) % n;
                let (h0, h1) = (gap(prev), gap(i));
                a[(i, prev)] += h0;
                a[(i, i)] += 2.0 * (h0 + h1);
                a[(i, next)] += h1;
                b[i] = 6.0 * ((radii[next] - radii[i]) / h1 - (radii[i] - radii[prev]) / h0);
            }
        }
    }
    // The system is strictly diagonally dominant (each row's diagonal is twice the sum
    // of the rest, or 1 alone), so it is never singular.
    a.lu()
        .solve(&b)
        .map_or_else(|| vec![0.0; n], |m| m.iter().copied().collect())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn passes_through_its_radii_and_holds_its_ends() {
        let law = RadiusLaw::through(&[(0.0, 7.5), (50.0, 15.0), (100.0, 7.5)], 120.0, false)
            .expect("positive radii");
        for (s, r) in [(0.0, 7.5), (50.0, 15.0), (100.0, 7.5), (110.0, 7.5)] {
            assert!((law.at(s) - r).abs() < 1e-12, "{s}: {}", law.at(s));
        }
        // Symmetric radii give a symmetric spline.
        assert!((law.at(30.0) - law.at(70.0)).abs() < 1e-12);
    }

    #[test]
    fn a_closed_chain_runs_on_round_its_start() {
        let law = RadiusLaw::through(&[(10.0, 5.0), (60.0, 9.0)], 100.0, true).expect("positive");
        let (before, after) = (law.at(99.999_999), law.at(100.000_001));
        assert!((before - after).abs() < 1e-6, "{before} {after}");
        assert!((law.at(10.0) - 5.0).abs() < 1e-12 && (law.at(60.0) - 9.0).abs() < 1e-12);
    }

    #[test]
    fn refuses_radii_that_are_not_radii() {
        assert_eq!(
            RadiusLaw::through(&[(0.0, 5.0), (10.0, 0.0)], 20.0, false),
            Err(RadiusError::NotPositive {
                index: 1,
                radius: 0.0
            })
        );
        assert!(matches!(
            RadiusLaw::through(&[(0.0, 5.0), (0.0, 6.0)], 20.0, false),
            Err(RadiusError::SamePlace {
                first: 0,
                second: 1
            })
        ));
        // A steep rise and fall overshoots below zero between them.
        assert!(matches!(
            RadiusLaw::through(
                &[(0.0, 0.1), (1.0, 50.0), (2.0, 0.1), (3.0, 0.1)],
                3.0,
                false
            ),
            Err(RadiusError::Dips { .. })
        ));
    }
}
