//! The key sections' runs and corners carried along the outline.
//!
//! Every number of the aligned key chains (each run's direction and length, each
//! corner's radius) is interpolated along the product outline's arc length by a
//! monotone piecewise cubic (Fritsch and Carlson): C1 along the outline, so the walls
//! run on smoothly through a key section instead of turning there (a V-shaped wedge in
//! the top view where one key section differs from its neighbours), and never beyond
//! the values of the two neighbouring key sections, so a radius between two key
//! sections is never tighter than the smaller of their two radii. A closed outline
//! wraps round.

use super::chain::{Chain, Run};

/// The key chains at their positions along the outline.
#[derive(Debug, Clone)]
pub struct Along {
    /// Positions (mm of outline length), increasing, the first at 0.
    positions: Vec<f64>,
    /// The aligned key chains.
    chains: Vec<Chain>,
    /// The outline's length, when it is closed (the positions wrap round).
    period: Option<f64>,
}

impl Along {
    /// `chains[k]` at `positions[k]`; `period` is the closed outline's length.
    pub fn new(positions: Vec<f64>, chains: Vec<Chain>, period: Option<f64>) -> Self {
        Self {
            positions,
            chains,
            period,
        }
    }

    /// The chain at outline position `s` (its start is that of the nearest key chain
    /// before it; the caller places it).
    pub fn at(&self, s: f64) -> Chain {
        let k = self.chains[0].corners();
        let runs = (0..=k)
            .map(|r| Run {
                angle: self.value(s, |c| c.runs[r].angle),
                length: self.value(s, |c| c.runs[r].length).max(0.0),
            })
            .collect();
        let radii = (0..k)
            .map(|i| self.value(s, |c| c.radii[i]).max(0.0))
            .collect();
        Chain {
            start: self.chains[0].start,
            runs,
            radii,
            obliquity: (
                self.value(s, |c| c.obliquity.0),
                self.value(s, |c| c.obliquity.1),
            ),
        }
    }

    /// One number of the key chains interpolated at `s`.
    fn value(&self, s: f64, of: impl Fn(&Chain) -> f64) -> f64 {
        let ys: Vec<f64> = self.chains.iter().map(&of).collect();
        let n = ys.len();
        if n == 1 {
            return ys[0];
        }
        // Knots (with one wrapped neighbour on each side when closed).
        let (xs, ys) = match self.period {
            Some(p) => {
                let mut xs = Vec::with_capacity(n + 3);
                let mut vs = Vec::with_capacity(n + 3);
                xs.push(self.positions[n - 1] - p);
                vs.push(ys[n - 1]);
                xs.extend(&self.positions);
                vs.extend(&ys);
                xs.push(self.positions[0] + p);
                vs.push(ys[0]);
                xs.push(self.positions[1] + p);
                vs.push(ys[1]);
                (xs, vs)
            }
            None => (self.positions.clone(), ys),
        };
        let s = match self.period {
            Some(p) => s.rem_euclid(p),
            None => s.clamp(xs[0], xs[xs.len() - 1]),
        };
        let i = xs.partition_point(|&x| x <= s).clamp(1, xs.len() - 1) - 1;
        let (x0, x1) = (xs[i], xs[i + 1]);
        let h = x1 - x0;
        if h <= 0.0 {
            return ys[i];
        }
        let d0 = slope(&xs, &ys, i);
        let d1 = slope(&xs, &ys, i + 1);
        let t = (s - x0) / h;
        let (t2, t3) = (t * t, t * t * t);
        (2.0 * t3 - 3.0 * t2 + 1.0) * ys[i]
            + (t3 - 2.0 * t2 + t) * h * d0
            + (-2.0 * t3 + 3.0 * t2) * ys[i + 1]
            + (t3 - t2) * h * d1
    }
}

/// The Fritsch-Carlson slope at knot `i`: 0 at a local extremum (so the curve never
/// overshoots its neighbours), else the weighted harmonic mean of the secants; one-sided
/// at the ends.
fn slope(xs: &[f64], ys: &[f64], i: usize) -> f64 {
    let n = xs.len();
    let secant = |a: usize| (ys[a + 1] - ys[a]) / (xs[a + 1] - xs[a]).max(1e-300);
    if i == 0 {
        return if n > 1 {
            end_slope(secant(0), if n > 2 { secant(1) } else { secant(0) })
        } else {
            0.0
        };
    }
    if i == n - 1 {
        return end_slope(
            secant(n - 2),
            if n > 2 { secant(n - 3) } else { secant(n - 2) },
        );
    }
    let (a, b) = (secant(i - 1), secant(i));
    if a * b <= 0.0 {
        return 0.0;
    }
    let (h0, h1) = (xs[i] - xs[i - 1], xs[i + 1] - xs[i]);
    let (w1, w2) = (2.0 * h1 + h0, h1 + 2.0 * h0);
    (w1 + w2) / (w1 / a + w2 / b)
}

/// An end slope that keeps the end span monotone: the secant, or 0 where the data turn.
fn end_slope(own: f64, next: f64) -> f64 {
    if own * next <= 0.0 {
        0.0
    } else {
        own
    }
}
