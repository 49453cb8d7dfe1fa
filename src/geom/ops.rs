//! The fundamental B-spline algorithms on raw control arrays: knot insertion (P&T A5.1),
//! knot refinement (A5.4), knot removal (A5.8) and degree elevation (A5.9).
//!
//! They are generic over [`Linear`] so the same code serves 2-D and 3-D curves in
//! homogeneous form (rational curves) and the rows and columns of a surface's net. The
//! inputs are trusted: the callers in `curve` and `surface` validate parameters first.

// The algorithms keep P&T's index arithmetic so that each line can be checked against
// the book; iterator rewrites would hide that correspondence.
#![allow(
    clippy::needless_range_loop,
    clippy::explicit_counter_loop,
    clippy::manual_memcpy
)]

use super::point::Linear;

/// Control arrays of a B-spline: its knots and control points (possibly homogeneous).
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct Spline<T> {
    pub degree: usize,
    pub knots: Vec<f64>,
    pub points: Vec<T>,
}

/// The knot span of `u` (P&T A2.1) on a raw clamped vector.
fn find_span(degree: usize, knots: &[f64], u: f64) -> usize {
    let n = knots.len() - degree - 2;
    if u >= knots[n + 1] {
        return n;
    }
    if u.is_nan() || u <= knots[degree] {
        return degree;
    }
    degree + knots[degree..=n + 1].partition_point(|&k| k <= u) - 1
}

/// Inserts `u` up to `times` times, never beyond multiplicity `degree` (P&T A5.1).
/// `u` must lie strictly inside the domain.
pub(crate) fn insert_knot<T: Linear>(s: &Spline<T>, u: f64, times: usize) -> Spline<T> {
    let p = s.degree;
    let up = &s.knots;
    let pw = &s.points;
    let mult = up.iter().filter(|&&k| k == u).count();
    let r = times.min(p.saturating_sub(mult));
    if r == 0 {
        return s.clone();
    }
    let k = find_span(p, up, u);
    let np = pw.len() - 1;
    let mp = np + p + 1;

    let mut uq = Vec::with_capacity(up.len() + r);
    uq.extend_from_slice(&up[..=k]);
    uq.extend(std::iter::repeat_n(u, r));
    uq.extend_from_slice(&up[k + 1..=mp]);

    let mut qw = vec![T::ZERO; np + 1 + r];
    qw[..=k - p].copy_from_slice(&pw[..=k - p]);
    for i in k - mult..=np {
        qw[i + r] = pw[i];
    }
    let mut rw: Vec<T> = pw[k - p..=k - mult].to_vec();
    let mut l = k - p + 1;
    for j in 1..=r {
        l = k - p + j;
        for i in 0..=p - j - mult {
            let alpha = (u - up[l + i]) / (up[i + k + 1] - up[l + i]);
            rw[i] = rw[i + 1] * alpha + rw[i] * (1.0 - alpha);
        }
        qw[l] = rw[0];
        qw[k + r - j - mult] = rw[p - j - mult];
    }
    for i in l + 1..k - mult {
        qw[i] = rw[i - l];
    }
    Spline {
        degree: p,
        knots: uq,
        points: qw,
    }
}

/// Inserts every knot of the sorted list `x` (P&T A5.4). Values must lie strictly inside
/// the domain and must not raise any multiplicity above the degree.
pub(crate) fn refine<T: Linear>(s: &Spline<T>, x: &[f64]) -> Spline<T> {
    if x.is_empty() {
        return s.clone();
    }
    let p = s.degree;
    let u = &s.knots;
    let pw = &s.points;
    let n = pw.len() - 1;
    let m = n + p + 1;
    let r = x.len() - 1;
    let a = find_span(p, u, x[0]);
    let b = find_span(p, u, x[r]) + 1;

    let mut qw = vec![T::ZERO; n + r + 2];
    let mut ubar = vec![0.0; m + r + 2];
    qw[..=a - p].copy_from_slice(&pw[..=a - p]);
    for j in b - 1..=n {
        qw[j + r + 1] = pw[j];
    }
    ubar[..=a].copy_from_slice(&u[..=a]);
    for j in b + p..=m {
        ubar[j + r + 1] = u[j];
    }
    let mut i = b + p - 1;
    let mut k = b + p + r;
    for j in (0..=r).rev() {
        while x[j] <= u[i] && i > a {
            qw[k - p - 1] = pw[i - p - 1];
            ubar[k] = u[i];
            k -= 1;
            i -= 1;
        }
        qw[k - p - 1] = qw[k - p];
        for l in 1..=p {
            let ind = k - p + l;
            let alfa = ubar[k + l] - x[j];
            if alfa.abs() == 0.0 {
                qw[ind - 1] = qw[ind];
            } else {
                let alfa = alfa / (ubar[k + l] - u[i + l - p]);
                qw[ind - 1] = qw[ind - 1] * alfa + qw[ind] * (1.0 - alfa);
            }
        }
        ubar[k] = x[j];
        k -= 1;
    }
    Spline {
        degree: p,
        knots: ubar,
        points: qw,
    }
}

/// Binomial coefficient as f64.
fn binomial(n: usize, k: usize) -> f64 {
    (0..k).fold(1.0, |acc, i| acc * (n - i) as f64 / (i + 1) as f64)
}

/// Raises the degree by `t` without changing the curve (P&T A5.9): each Bezier segment is
/// elevated and the interior knots regain their continuity by knot removal.
pub(crate) fn elevate_degree<T: Linear>(s: &Spline<T>, t: usize) -> Spline<T> {
    if t == 0 {
        return s.clone();
    }
    let p = s.degree;
    let uk = &s.knots;
    let pw = &s.points;
    let n = pw.len() - 1;
    let m = n + p + 1;
    let ph = p + t;
    let ph2 = ph / 2;

    // Coefficients that elevate one Bezier segment.
    let mut bezalfs = vec![vec![0.0; p + 1]; ph + 1];
    bezalfs[0][0] = 1.0;
    bezalfs[ph][p] = 1.0;
    for i in 1..=ph2 {
        let inv = 1.0 / binomial(ph, i);
        for j in i.saturating_sub(t)..=p.min(i) {
            bezalfs[i][j] = inv * binomial(p, j) * binomial(t, i - j);
        }
    }
    for i in ph2 + 1..ph {
        for j in i.saturating_sub(t)..=p.min(i) {
            bezalfs[i][j] = bezalfs[ph - i][p - j];
        }
    }

    let segments = s.knots.windows(2).filter(|w| w[1] > w[0]).count();
    let new_count = n + 1 + t * segments;
    let mut qw = vec![T::ZERO; new_count];
    let mut uh = vec![0.0; new_count + ph + 1];
    let mut bpts = vec![T::ZERO; p + 1];
    let mut ebpts = vec![T::ZERO; ph + 1];
    let mut next_bpts = vec![T::ZERO; p.saturating_sub(1).max(1)];
    let mut alfs = vec![0.0; p.saturating_sub(1).max(1)];

    let mut mh = ph;
    let mut kind = ph + 1;
    let mut r: isize = -1;
    let mut a = p;
    let mut b = p + 1;
    let mut cind = 1;
    let mut ua = uk[0];
    qw[0] = pw[0];
    for v in uh.iter_mut().take(ph + 1) {
        *v = ua;
    }
    bpts.copy_from_slice(&pw[..=p]);

    while b < m {
        let i0 = b;
        while b < m && uk[b] == uk[b + 1] {
            b += 1;
        }
        let mul = b - i0 + 1;
        mh += mul + t;
        let ub = uk[b];
        let oldr = r;
        r = p as isize - mul as isize;
        let lbz = if oldr > 0 {
            ((oldr + 2) / 2) as usize
        } else {
            1
        };
        let rbz = if r > 0 {
            ph - (r as usize).div_ceil(2)
        } else {
            ph
        };
        if r > 0 {
            // Insert ub r times into the current Bezier segment.
            let numer = ub - ua;
            for k in (mul + 1..=p).rev() {
                alfs[k - mul - 1] = numer / (uk[a + k] - ua);
            }
            for j in 1..=r as usize {
                let save = r as usize - j;
                let s_ = mul + j;
                for k in (s_..=p).rev() {
                    bpts[k] = bpts[k] * alfs[k - s_] + bpts[k - 1] * (1.0 - alfs[k - s_]);
                }
                next_bpts[save] = bpts[p];
            }
        }
        // Elevate the Bezier segment.
        for i in lbz..=ph {
            let mut acc = T::ZERO;
            for j in i.saturating_sub(t)..=p.min(i) {
                acc = acc + bpts[j] * bezalfs[i][j];
            }
            ebpts[i] = acc;
        }
        if oldr > 1 {
            // Remove knot ua oldr - 1 times to restore continuity.
            let oldr = oldr as usize;
            let mut first = kind - 2;
            let mut last = kind;
            let den = ub - ua;
            let bet = (ub - uh[kind - 1]) / den;
            for tr in 1..oldr {
                let mut i = first;
                let mut j = last;
                let mut kj = j - kind + 1;
                while j - i > tr {
                    if i < cind {
                        let alf = (ub - uh[i]) / (ua - uh[i]);
                        qw[i] = qw[i] * alf + qw[i - 1] * (1.0 - alf);
                    }
                    if j >= lbz {
                        if j - tr <= kind - ph + oldr {
                            let gam = (ub - uh[j - tr]) / den;
                            ebpts[kj] = ebpts[kj] * gam + ebpts[kj + 1] * (1.0 - gam);
                        } else {
                            ebpts[kj] = ebpts[kj] * bet + ebpts[kj + 1] * (1.0 - bet);
                        }
                    }
                    i += 1;
                    j -= 1;
                    kj = kj.wrapping_sub(1);
                }
                first -= 1;
                last += 1;
            }
        }
        if a != p {
            let count = ph as isize - oldr;
            for _ in 0..count.max(0) {
                uh[kind] = ua;
                kind += 1;
            }
        }
        for j in lbz..=rbz {
            qw[cind] = ebpts[j];
            cind += 1;
        }
        if b < m {
            let r_u = r.max(0) as usize;
            bpts[..r_u].copy_from_slice(&next_bpts[..r_u]);
            for j in r_u..=p {
                bpts[j] = pw[b - p + j];
            }
            a = b;
            b += 1;
            ua = ub;
        } else {
            for i in 0..=ph {
                uh[kind + i] = ub;
            }
        }
    }
    let nh = mh - ph - 1;
    qw.truncate(nh + 1);
    uh.truncate(mh + 1);
    Spline {
        degree: ph,
        knots: uh,
        points: qw,
    }
}

/// Removes the interior knot `u` up to `times` times (P&T A5.8), stopping at the first
/// removal that would move the control structure by more than `tol`. Returns the new
/// spline and how many times the knot was removed.
///
/// Each removal is checked as in A5.8: the control point computed from the left and the
/// one computed from the right must agree within the removal's error, measured by
/// `dist`. P&T's bound (eq. 5.29) makes the curve move by at most that error at each
/// removal; since successive removals add up, the errors are summed and the removals
/// stop before the sum exceeds `tol` (A5.8 checks each one against `tol` alone).
/// `u` must be an interior knot of `s`.
pub(crate) fn remove_knot<T: Linear>(
    s: &Spline<T>,
    u: f64,
    times: usize,
    tol: f64,
    dist: impl Fn(T, T) -> f64,
) -> (Spline<T>, usize) {
    let p = s.degree as isize;
    let knots = &s.knots;
    let mut pw = s.points.clone();
    let n = pw.len() as isize - 1;
    let m = n + p + 1;
    let mult = knots.iter().filter(|&&k| k == u).count();
    // r: the index of the last occurrence of u.
    let Some(r) = knots.iter().rposition(|&k| k == u) else {
        return (s.clone(), 0);
    };
    let r = r as isize;
    let s_ = mult as isize;
    let num = times.min(mult) as isize;
    let ord = p + 1;
    let fout = (2 * r - s_ - p) / 2;
    let mut last = r - s_;
    let mut first = r - p;
    let uk = |i: isize| knots[i as usize];
    let mut temp = vec![T::ZERO; (2 * p + 1) as usize];
    let mut spent = 0.0;
    let mut t = 0;
    while t < num {
        let off = first - 1;
        temp[0] = pw[off as usize];
        temp[(last + 1 - off) as usize] = pw[(last + 1) as usize];
        let (mut i, mut j) = (first, last);
        let (mut ii, mut jj) = (1, last - off);
        while j - i > t {
            let alfi = (u - uk(i)) / (uk(i + ord + t) - uk(i));
            let alfj = (u - uk(j - t)) / (uk(j + ord) - uk(j - t));
            temp[ii as usize] =
                (pw[i as usize] - temp[(ii - 1) as usize] * (1.0 - alfi)) * (1.0 / alfi);
            temp[jj as usize] =
                (pw[j as usize] - temp[(jj + 1) as usize] * alfj) * (1.0 / (1.0 - alfj));
            i += 1;
            ii += 1;
            j -= 1;
            jj -= 1;
        }
        let error = if j - i < t {
            dist(temp[(ii - 1) as usize], temp[(jj + 1) as usize])
        } else {
            let alfi = (u - uk(i)) / (uk(i + ord + t) - uk(i));
            dist(
                pw[i as usize],
                temp[(ii + t + 1) as usize] * alfi + temp[(ii - 1) as usize] * (1.0 - alfi),
            )
        };
        // A NaN error (a degenerate knot span) refuses the removal too.
        if error.is_nan() || spent + error > tol {
            break;
        }
        spent += error;
        let (mut i, mut j) = (first, last);
        while j - i > t {
            pw[i as usize] = temp[(i - off) as usize];
            pw[j as usize] = temp[(j - off) as usize];
            i += 1;
            j -= 1;
        }
        first -= 1;
        last += 1;
        t += 1;
    }
    if t == 0 {
        return (s.clone(), 0);
    }
    let mut uq = knots.clone();
    for k in r + 1..=m {
        uq[(k - t) as usize] = knots[k as usize];
    }
    uq.truncate((m + 1 - t) as usize);
    let mut j = fout;
    let mut i = j;
    for k in 1..t {
        if k % 2 == 1 {
            i += 1;
        } else {
            j -= 1;
        }
    }
    for k in i + 1..=n {
        pw[j as usize] = pw[k as usize];
        j += 1;
    }
    pw.truncate((n + 1 - t) as usize);
    (
        Spline {
            degree: s.degree,
            knots: uq,
            points: pw,
        },
        t as usize,
    )
}
