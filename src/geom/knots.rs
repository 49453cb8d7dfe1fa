//! Knot vectors and B-spline basis functions.
//!
//! A [`KnotVector`] is always *clamped* (the first and last knots repeated degree + 1
//! times), as OpenCascade's non-periodic B-splines are: the curve then starts and ends at
//! its first and last control points, which every die-face construction relies on.
//! Basis functions follow Piegl & Tiller, *The NURBS Book* (A2.1 span search, A2.2
//! basis functions); derivatives use the recurrence of eq. 2.9 applied order by order.

use super::error::{GeomError, Result};
use super::{MAX_DEGREE, MAX_DERIVATIVE};

/// Basis values of one span: index `r` holds `N_{span-p+r, p}`.
pub(crate) type BasisRow = [f64; MAX_DEGREE + 1];

/// A validated, clamped, non-decreasing knot vector.
#[derive(Debug, Clone, PartialEq)]
pub struct KnotVector {
    knots: Vec<f64>,
}

impl KnotVector {
    /// Validates `knots` for a B-spline of `degree` with `control_count` control points:
    /// length `control_count + degree + 1`, finite, non-decreasing, clamped at both ends,
    /// no interior knot repeated more than `degree` times, and a non-empty domain.
    pub fn new(knots: Vec<f64>, degree: usize, control_count: usize) -> Result<Self> {
        check_degree(degree)?;
        if control_count < degree + 1 {
            return Err(GeomError::TooFewPoints {
                needed: degree + 1,
                given: control_count,
            });
        }
        let expected = control_count + degree + 1;
        if knots.len() != expected {
            return Err(GeomError::KnotVector {
                reason: format!(
                    "{} knots given; degree {degree} with {control_count} control points needs {expected}",
                    knots.len()
                ),
            });
        }
        if let Some(i) = knots.iter().position(|k| !k.is_finite()) {
            return Err(GeomError::KnotVector {
                reason: format!("knot {i} is not finite"),
            });
        }
        if let Some(i) = knots.windows(2).position(|w| w[1] < w[0]) {
            return Err(GeomError::KnotVector {
                reason: format!(
                    "knot {} ({}) is smaller than knot {i} ({})",
                    i + 1,
                    knots[i + 1],
                    knots[i]
                ),
            });
        }
        let (first, last) = (knots[0], knots[expected - 1]);
        if last <= first {
            return Err(GeomError::KnotVector {
                reason: "the parameter domain is empty".into(),
            });
        }
        let clamped_start = knots[..=degree].iter().all(|&k| k == first);
        let clamped_end = knots[expected - degree - 1..].iter().all(|&k| k == last);
        if !clamped_start || !clamped_end {
            return Err(GeomError::KnotVector {
                reason: format!(
                    "the first and last knots must each repeat degree + 1 = {} times",
                    degree + 1
                ),
            });
        }
        let interior = &knots[degree + 1..expected - degree - 1];
        let mut run = 1;
        for i in 0..interior.len() {
            run = if i > 0 && interior[i] == interior[i - 1] {
                run + 1
            } else {
                1
            };
            if run > degree || interior[i] == first || interior[i] == last {
                return Err(GeomError::KnotVector {
                    reason: format!(
                        "interior knot {} is repeated more than degree = {degree} times",
                        interior[i]
                    ),
                });
            }
        }
        Ok(Self { knots })
    }

    /// Wraps knots that the kernel itself produced and knows to be valid.
    pub(crate) fn trusted(knots: Vec<f64>) -> Self {
        Self { knots }
    }

    /// A clamped knot vector with uniformly spaced interior knots on [0, 1].
    pub fn uniform(degree: usize, control_count: usize) -> Result<Self> {
        check_degree(degree)?;
        if control_count < degree + 1 {
            return Err(GeomError::TooFewPoints {
                needed: degree + 1,
                given: control_count,
            });
        }
        let spans = control_count - degree;
        let mut knots = vec![0.0; degree + 1];
        knots.extend((1..spans).map(|i| i as f64 / spans as f64));
        knots.extend(std::iter::repeat_n(1.0, degree + 1));
        Ok(Self { knots })
    }

    /// The Bezier knot vector `[0; p+1] ++ [1; p+1]`.
    pub fn bezier(degree: usize) -> Self {
        let mut knots = vec![0.0; degree + 1];
        knots.extend(std::iter::repeat_n(1.0, degree + 1));
        Self { knots }
    }

    /// The flat knot sequence.
    pub fn as_slice(&self) -> &[f64] {
        &self.knots
    }

    /// Consumes the vector and returns the flat knot sequence.
    pub fn into_vec(self) -> Vec<f64> {
        self.knots
    }

    /// Number of knots.
    pub fn len(&self) -> usize {
        self.knots.len()
    }

    /// Always false for a validated vector; present for API symmetry with `len`.
    pub fn is_empty(&self) -> bool {
        self.knots.is_empty()
    }

    /// Parameter domain `[first, last]`.
    pub fn domain(&self) -> (f64, f64) {
        (self.knots[0], self.knots[self.knots.len() - 1])
    }

    /// Distinct knot values with their multiplicities, in increasing order.
    pub fn distinct(&self) -> Vec<(f64, usize)> {
        let mut out: Vec<(f64, usize)> = Vec::new();
        for &k in &self.knots {
            match out.last_mut() {
                Some((v, m)) if *v == k => *m += 1,
                _ => out.push((k, 1)),
            }
        }
        out
    }

    /// How many times `u` appears in the vector.
    pub fn multiplicity(&self, u: f64) -> usize {
        self.knots.iter().filter(|&&k| k == u).count()
    }

    /// The knot span index `i` with `u_i <= u < u_{i+1}` for a B-spline of `degree`
    /// (P&T A2.1); `u` at or beyond the end maps to the last non-empty span, and `u`
    /// before the start to the first, so evaluation extends continuously.
    pub fn span(&self, degree: usize, u: f64) -> usize {
        let n = self.knots.len() - degree - 2; // index of the last control point
        if u >= self.knots[n + 1] {
            return n;
        }
        // NaN evaluates (to NaN) in the first span rather than failing the search.
        if u.is_nan() || u <= self.knots[degree] {
            return degree;
        }
        // Binary search on the knots between degree and n + 1.
        let slice = &self.knots[degree..=n + 1];
        let pos = slice.partition_point(|&k| k <= u);
        degree + pos - 1
    }

    /// [`KnotVector::span`] of `u`, trying `hint` first: a span that holds `u` is the
    /// one the search would find, so only when `hint` does not is the search run.
    pub fn span_from(&self, degree: usize, u: f64, hint: usize) -> usize {
        let n = self.knots.len() - degree - 2;
        let k = &self.knots;
        let inside = k[degree] < u && u < k[n + 1];
        if inside && (degree..=n).contains(&hint) && k[hint] <= u && u < k[hint + 1] {
            hint
        } else {
            self.span(degree, u)
        }
    }

    /// Basis functions of `degree` that are non-zero at `u` in `span` (P&T A2.2).
    /// Degrees up to 5, nearly all of die-face geometry, run a copy of the recurrence
    /// sized at compile time, which keeps point evaluation free of work on unused slots.
    pub(crate) fn basis(&self, span: usize, degree: usize, u: f64) -> BasisRow {
        let mut out = [0.0; MAX_DEGREE + 1];
        match degree {
            1 => out[..2].copy_from_slice(&self.basis_fixed::<2>(span, u)),
            2 => out[..3].copy_from_slice(&self.basis_fixed::<3>(span, u)),
            3 => out[..4].copy_from_slice(&self.basis_fixed::<4>(span, u)),
            4 => out[..5].copy_from_slice(&self.basis_fixed::<5>(span, u)),
            5 => out[..6].copy_from_slice(&self.basis_fixed::<6>(span, u)),
            _ => {
                let mut rows = [[0.0; MAX_DEGREE + 1]; 1];
                self.basis_with_lower(span, degree, u, 0, &mut rows);
                out = rows[0];
            }
        }
        out
    }

    /// P&T A2.2 for degree `O - 1`: the `O` basis functions non-zero in `span`.
    fn basis_fixed<const O: usize>(&self, span: usize, u: f64) -> [f64; O] {
        let mut n = [0.0; O];
        let mut left = [0.0; O];
        let mut right = [0.0; O];
        n[0] = 1.0;
        for j in 1..O {
            raise_basis_degree(&self.knots, span, u, j, &mut n, &mut left, &mut right);
        }
        n
    }

    /// Basis functions and their derivatives up to `order` at `u` in `span`:
    /// `out[k][r]` is the k-th derivative of `N_{span-p+r, p}`. Orders above the degree
    /// are zero. Eq. 2.9 of P&T, `N'_{i,q} = q (N_{i,q-1}/(u_{i+q}-u_i) - N_{i+1,q-1}/(u_{i+q+1}-u_{i+1}))`,
    /// is applied to the basis of degrees `p - order ..= p`.
    pub(crate) fn basis_derivatives(
        &self,
        span: usize,
        degree: usize,
        u: f64,
        order: usize,
        out: &mut [BasisRow; MAX_DERIVATIVE + 1],
    ) {
        match degree {
            1 => self.basis_derivatives_fixed::<2>(span, u, order, out),
            2 => self.basis_derivatives_fixed::<3>(span, u, order, out),
            3 => self.basis_derivatives_fixed::<4>(span, u, order, out),
            4 => self.basis_derivatives_fixed::<5>(span, u, order, out),
            5 => self.basis_derivatives_fixed::<6>(span, u, order, out),
            _ => self.basis_derivatives_general(span, degree, u, order, out),
        }
    }

    /// [`KnotVector::basis_derivatives`] for degree `O - 1` with its work arrays sized at
    /// compile time: the same arithmetic in the same order (so the same numbers), without
    /// clearing and copying rows of [`MAX_DEGREE`] + 1 entries at every step, which took
    /// most of the time of a surface's derivatives (a binder look-up, a curvature).
    fn basis_derivatives_fixed<const O: usize>(
        &self,
        span: usize,
        u: f64,
        order: usize,
        out: &mut [BasisRow; MAX_DERIVATIVE + 1],
    ) {
        let rows = self.basis_rows::<O, { MAX_DERIVATIVE + 1 }>(span, u, order);
        *out = [[0.0; MAX_DEGREE + 1]; MAX_DERIVATIVE + 1];
        for (row, r) in out.iter_mut().zip(&rows) {
            row[..O].copy_from_slice(r);
        }
    }

    /// The basis functions of degree `O - 1` non-zero in `span` and their derivatives
    /// up to `min(order, N - 1)` at `u`, `rows[k][r]` as in
    /// [`KnotVector::basis_derivatives`] (rows above the order are zero), in arrays sized
    /// at compile time: what a curve's point and first derivatives take (arc lengths
    /// evaluate millions), without clearing rows of [`MAX_DEGREE`] + 1 entries.
    #[inline(always)]
    pub(crate) fn basis_rows<const O: usize, const N: usize>(
        &self,
        span: usize,
        u: f64,
        order: usize,
    ) -> [[f64; O]; N] {
        let degree = O - 1;
        let d = order.min(N - 1).min(MAX_DERIVATIVE).min(degree);
        // lower[k]: the basis of degree p - k, as in basis_with_lower.
        let mut lower = [[0.0; O]; N];
        let mut n = [0.0; O];
        let mut left = [0.0; O];
        let mut right = [0.0; O];
        n[0] = 1.0;
        if degree <= d {
            lower[degree] = n;
        }
        for j in 1..=degree {
            raise_basis_degree(&self.knots, span, u, j, &mut n, &mut left, &mut right);
            if degree - j <= d {
                lower[degree - j] = n;
            }
        }
        let mut out = [[0.0; O]; N];
        out[0] = lower[0];
        let k = &self.knots;
        for j in 1..=d {
            let mut cur = lower[j];
            for step in 0..j {
                cur = raise_differentiated(k, span, degree - j + step + 1, &cur);
            }
            out[j] = cur;
        }
        out
    }

    /// [`KnotVector::basis_derivatives`] for any degree (up to [`MAX_DEGREE`]).
    fn basis_derivatives_general(
        &self,
        span: usize,
        degree: usize,
        u: f64,
        order: usize,
        out: &mut [BasisRow; MAX_DERIVATIVE + 1],
    ) {
        let order = order.min(MAX_DERIVATIVE);
        let d = order.min(degree);
        // lower[k] holds the basis of degree p - k (k = 0..=d), index r -> N_{span-(p-k)+r, p-k}.
        let mut lower = [[0.0; MAX_DEGREE + 1]; MAX_DERIVATIVE + 1];
        self.basis_with_lower(span, degree, u, d, &mut lower[..=d]);
        for row in out.iter_mut() {
            *row = [0.0; MAX_DEGREE + 1];
        }
        out[0] = lower[0];
        let k = &self.knots;
        // For derivative order j, start from degree q0 = p - j (plain basis) and raise
        // the degree j times, each time differentiating once.
        for j in 1..=d {
            let mut cur = lower[j];
            for step in 0..j {
                cur = raise_differentiated(k, span, degree - j + step + 1, &cur);
            }
            out[j] = cur;
        }
    }

    /// Runs the triangular recurrence of P&T A2.2 up to `degree`, saving the rows of
    /// degrees `degree - k` for `k < rows.len()` into `rows[k]`.
    fn basis_with_lower(
        &self,
        span: usize,
        degree: usize,
        u: f64,
        keep: usize,
        rows: &mut [BasisRow],
    ) {
        let mut n = [0.0; MAX_DEGREE + 1];
        let mut left = [0.0; MAX_DEGREE + 1];
        let mut right = [0.0; MAX_DEGREE + 1];
        n[0] = 1.0;
        if degree <= keep {
            rows[degree] = n;
        }
        for j in 1..=degree {
            raise_basis_degree(&self.knots, span, u, j, &mut n, &mut left, &mut right);
            if degree - j <= keep {
                rows[degree - j] = n;
            }
        }
    }
}

/// One step of the triangular recurrence of P&T A2.2: `n[..j]` holds the basis of degree
/// `j - 1` at `u` in `span` and becomes the basis of degree `j` in `n[..=j]`; `left` and
/// `right` carry the knot differences between steps.
#[inline(always)]
fn raise_basis_degree(
    knots: &[f64],
    span: usize,
    u: f64,
    j: usize,
    n: &mut [f64],
    left: &mut [f64],
    right: &mut [f64],
) {
    left[j] = u - knots[span + 1 - j];
    right[j] = knots[span + j] - u;
    let mut saved = 0.0;
    for r in 0..j {
        let den = right[r + 1] + left[j - r];
        let temp = if den != 0.0 { n[r] / den } else { 0.0 };
        n[r] = saved + right[r + 1] * temp;
        saved = left[j - r] * temp;
    }
    n[j] = saved;
}

/// Rejects degree 0 and degrees above [`MAX_DEGREE`].
pub(crate) fn check_degree(degree: usize) -> Result<()> {
    if degree == 0 || degree > MAX_DEGREE {
        return Err(GeomError::Degree {
            degree,
            max: MAX_DEGREE,
        });
    }
    Ok(())
}

/// One step of the derivative recurrence (P&T eq. 2.9): from the `q - 1`-degree values
/// `cur` (already differentiated some times) at `span`, the values of degree `q`
/// differentiated once more. Shared by the fixed-size and the general basis
/// derivatives, so both do the same arithmetic in the same order.
fn raise_differentiated<const W: usize>(
    k: &[f64],
    span: usize,
    q: usize,
    cur: &[f64; W],
) -> [f64; W] {
    let mut next = [0.0; W];
    for r in 0..=q {
        let i = span + r - q; // global index of N_{i,q}
        let left = if r >= 1 {
            let den = k[i + q] - k[i];
            if den != 0.0 {
                cur[r - 1] / den
            } else {
                0.0
            }
        } else {
            0.0
        };
        let right = if r < q {
            let den = k[i + q + 1] - k[i + 1];
            if den != 0.0 {
                cur[r] / den
            } else {
                0.0
            }
        } else {
            0.0
        };
        next[r] = q as f64 * (left - right);
    }
    next
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn span_from_any_hint_is_the_span() {
        let knots = vec![0.0, 0.0, 0.0, 0.3, 0.3, 0.71, 1.9, 2.0, 3.5, 3.5, 3.5];
        let kv = KnotVector::new(knots, 2, 8).expect("a valid clamped knot vector");
        let ts = [
            -1.0,
            0.0,
            0.1,
            0.3,
            0.5,
            0.71,
            1.0,
            1.9,
            1.95,
            2.0,
            3.0,
            3.5,
            4.0,
            f64::NAN,
        ];
        for t in ts {
            for hint in 0..=8 {
                assert_eq!(
                    kv.span_from(2, t, hint),
                    kv.span(2, t),
                    "t = {t}, hint {hint}"
                );
            }
        }
    }

    #[test]
    fn fixed_size_basis_derivatives_are_the_general_ones_bit_for_bit() {
        for degree in 1..=5 {
            // Clamped, uneven, with a double interior knot from degree 2.
            let mut knots = vec![0.0; degree + 1];
            knots.extend([0.3, 0.71, 1.9, 2.0]);
            if degree > 1 {
                knots.push(2.0);
            }
            knots.extend(vec![3.5; degree + 1]);
            let count = knots.len() - degree - 1;
            let kv = KnotVector::new(knots, degree, count).expect("a valid clamped knot vector");
            for i in 0..=200 {
                let u = 3.5 * i as f64 / 200.0;
                let span = kv.span(degree, u);
                for order in 0..=4 {
                    let mut fixed = [[f64::NAN; MAX_DEGREE + 1]; MAX_DERIVATIVE + 1];
                    let mut general = [[f64::NAN; MAX_DEGREE + 1]; MAX_DERIVATIVE + 1];
                    kv.basis_derivatives(span, degree, u, order, &mut fixed);
                    kv.basis_derivatives_general(span, degree, u, order, &mut general);
                    let bits = |rows: &[BasisRow]| -> Vec<u64> {
                        rows.iter().flatten().map(|x| x.to_bits()).collect()
                    };
                    assert_eq!(
                        bits(&fixed),
                        bits(&general),
                        "degree {degree} u {u} order {order}"
                    );
                }
            }
        }
    }
}
