//! Fast evaluation of a NURBS surface on tensor grids of parameters.
//!
//! A tessellation evaluates the surface at every vertex of a grid and at several
//! verification points per cell, all of which lie on a few lists of u and v parameters.
//! Instead of evaluating each point from scratch (two basis evaluations and a
//! `(p+1)(q+1)` sum), the basis functions are computed once per parameter value
//! ([`BasisTable`]), the control net is contracted once per v parameter into a row of
//! homogeneous points ([`Row`]), and each point then costs a `p + 1` term sum.
//! Nothing is allocated per point.
//!
//! Used by the tessellator (its grid and verification points) and by
//! [`NurbsSurface::grid_points`], the public grid evaluation.

use glam::{DVec3, DVec4};

use crate::geom::knots::KnotVector;
use crate::geom::surface::NurbsSurface;
use crate::geom::{MAX_DEGREE, MAX_DERIVATIVE};

/// Basis functions (and optionally their first derivatives) of one direction at a list
/// of parameters.
pub(crate) struct BasisTable {
    stride: usize,
    /// Index of the first control point each parameter's basis applies to.
    first: Vec<usize>,
    values: Vec<f64>,
    derivs: Vec<f64>,
}

impl BasisTable {
    /// Basis of `degree` over `knots` at each of `params`; with `derivs`, the first
    /// derivatives too. A parameter on a knot uses the span to its right (the last span at
    /// the domain's end), as the surface's own evaluation does.
    pub(crate) fn new(knots: &KnotVector, degree: usize, params: &[f64], derivs: bool) -> Self {
        let stride = degree + 1;
        let mut table = Self {
            stride,
            first: Vec::with_capacity(params.len()),
            values: Vec::with_capacity(params.len() * stride),
            derivs: Vec::with_capacity(if derivs { params.len() * stride } else { 0 }),
        };
        let mut rows = [[0.0; MAX_DEGREE + 1]; MAX_DERIVATIVE + 1];
        for &t in params {
            let span = knots.span(degree, t);
            table.first.push(span - degree);
            knots.basis_derivatives(span, degree, t, usize::from(derivs), &mut rows);
            table.values.extend_from_slice(&rows[0][..stride]);
            if derivs {
                table.derivs.extend_from_slice(&rows[1][..stride]);
            }
        }
        table
    }

    /// Number of parameters in the table.
    pub(crate) fn len(&self) -> usize {
        self.first.len()
    }

    fn values(&self, k: usize) -> &[f64] {
        &self.values[k * self.stride..(k + 1) * self.stride]
    }

    fn derivs(&self, k: usize) -> &[f64] {
        &self.derivs[k * self.stride..(k + 1) * self.stride]
    }
}

/// The surface's control net in homogeneous form `(w x, w y, w z, w)`, row-major.
pub(crate) struct Net {
    points: Vec<DVec4>,
    count_u: usize,
    count_v: usize,
}

impl Net {
    pub(crate) fn new(surface: &NurbsSurface) -> Self {
        let (count_u, count_v) = surface.counts();
        let mut points = Vec::with_capacity(count_u * count_v);
        for i in 0..count_u {
            for j in 0..count_v {
                let w = surface.weight(i, j);
                points.push((surface.control_point(i, j) * w).extend(w));
            }
        }
        Self {
            points,
            count_u,
            count_v,
        }
    }
}

/// The control net contracted along v at one v parameter: one homogeneous point per
/// control row `i`, i.e. the control polygon of the iso-curve at that v (and, when
/// wanted, of its v-derivative).
pub(crate) struct Row {
    pub(crate) h: Vec<DVec4>,
    pub(crate) dv: Vec<DVec4>,
}

impl Row {
    pub(crate) fn new() -> Self {
        Self {
            h: Vec::new(),
            dv: Vec::new(),
        }
    }

    /// Contracts `net` with entry `k` of `table` (the v basis); with `derivs`, also with
    /// its derivative (the table must have been built with derivatives).
    pub(crate) fn fill(&mut self, net: &Net, table: &BasisTable, k: usize, derivs: bool) {
        let j0 = table.first[k];
        let nv = table.values(k);
        self.h.clear();
        self.dv.clear();
        for i in 0..net.count_u {
            let row = &net.points[i * net.count_v + j0..i * net.count_v + j0 + nv.len()];
            let mut acc = DVec4::ZERO;
            for (p, &b) in row.iter().zip(nv) {
                acc += *p * b;
            }
            self.h.push(acc);
        }
        if derivs {
            let dnv = table.derivs(k);
            for i in 0..net.count_u {
                let row = &net.points[i * net.count_v + j0..i * net.count_v + j0 + dnv.len()];
                let mut acc = DVec4::ZERO;
                for (p, &b) in row.iter().zip(dnv) {
                    acc += *p * b;
                }
                self.dv.push(acc);
            }
        }
    }

    /// The surface point at entry `k` of the u table on this row.
    pub(crate) fn point(&self, table: &BasisTable, k: usize) -> DVec3 {
        let i0 = table.first[k];
        let mut acc = DVec4::ZERO;
        for (p, &b) in self.h[i0..].iter().zip(table.values(k)) {
            acc += *p * b;
        }
        acc.truncate() / acc.w
    }

    /// The point and its first partial derivatives `(S, S_u, S_v)` at entry `k` of the u
    /// table (built with derivatives) on this row (filled with derivatives).
    pub(crate) fn point_and_tangents(&self, table: &BasisTable, k: usize) -> (DVec3, DVec3, DVec3) {
        let i0 = table.first[k];
        let (mut a, mut au, mut av) = (DVec4::ZERO, DVec4::ZERO, DVec4::ZERO);
        let rows = self.h[i0..].iter().zip(&self.dv[i0..]);
        for ((p, pv), (&b, &db)) in rows.zip(table.values(k).iter().zip(table.derivs(k))) {
            a += *p * b;
            au += *p * db;
            av += *pv * b;
        }
        let s = a.truncate() / a.w;
        let su = (au.truncate() - s * au.w) / a.w;
        let sv = (av.truncate() - s * av.w) / a.w;
        (s, su, sv)
    }
}
