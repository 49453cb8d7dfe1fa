//! Skinned (lofted) surfaces through sections (P&T section 10.3).

use glam::DVec4;
use rayon::prelude::*;

use crate::geom::compat::make_compatible;
use crate::geom::curve::Curve3;
use crate::geom::error::{GeomError, Result};
use crate::geom::interpolate::{interpolate_at, Interpolation, Parametrization};
use crate::geom::surface::NurbsSurface;

/// Control points of a net from which [`loft`] interpolates its columns in parallel.
const PARALLEL_POINTS: usize = 2048;

/// Options of [`loft`].
#[derive(Debug, Clone, Default)]
pub struct Loft {
    /// Degree across the sections; lowered to what the section count allows (two
    /// sections without tangents give a ruled surface). 0 means the default, cubic.
    pub degree: usize,
    /// How the sections are spaced in v (from the distances between corresponding
    /// control points, averaged over the net, P&T eq. 10.8).
    pub parametrization: Parametrization,
    /// Cross-boundary derivative `S_v` along the first section, as a vector-valued
    /// polynomial curve over the same parameter as the sections.
    pub start_tangent: Option<Curve3>,
    /// Cross-boundary derivative along the last section.
    pub end_tangent: Option<Curve3>,
}

/// The surface through `sections` (each becomes an iso-curve `v = v_k`, u along the
/// sections). Sections are made compatible first; the surface is interpolated column by
/// column in homogeneous space, so rational sections are reproduced exactly.
///
/// Tangents: the tangent curves are made compatible with the sections, and their
/// control points `T_i` become the homogeneous end derivatives `(w_i T_i, 0)` of each
/// column. For polynomial sections that makes `S_v(u, v0)` equal the tangent curve
/// exactly; for rational ones it is the tangent curve's control points blended with
/// the section's rational basis. That is what a C1 join needs: the blankholder and step
/// draw compute the `T_i` control point by control point from eq. 4.
pub fn loft(sections: &[Curve3], opts: &Loft) -> Result<NurbsSurface> {
    if sections.len() < 2 {
        return Err(GeomError::TooFewPoints {
            needed: 2,
            given: sections.len(),
        });
    }
    for tangent in [&opts.start_tangent, &opts.end_tangent]
        .into_iter()
        .flatten()
    {
        if tangent.is_rational() {
            return Err(GeomError::RationalNotSupported {
                what: "a loft tangent curve",
            });
        }
    }
    let mut all: Vec<Curve3> = sections.to_vec();
    all.extend(opts.start_tangent.iter().cloned());
    all.extend(opts.end_tangent.iter().cloned());
    let all = make_compatible(&all)?;
    let (secs, rest) = all.split_at(sections.len());
    let mut rest = rest.iter();
    let start = opts.start_tangent.as_ref().and_then(|_| rest.next());
    let end = opts.end_tangent.as_ref().and_then(|_| rest.next());

    let rational = secs.iter().any(Curve3::is_rational);
    let count_u = secs[0].control_points().len();
    let lift = |c: &Curve3, i: usize| {
        let w = c.weight(i);
        (c.control_points()[i] * w).extend(w)
    };
    let params = section_parameters(secs, opts.parametrization)?;
    let conditions = usize::from(start.is_some()) + usize::from(end.is_some());
    let wanted = if opts.degree == 0 { 3 } else { opts.degree };
    let degree_v = wanted.min(secs.len() + conditions - 1);

    // Each column on its own, in parallel; the first failing column's error, as a loop
    // would meet it.
    let column = |i: usize| {
        let column: Vec<DVec4> = secs.iter().map(|c| lift(c, i)).collect();
        let weight_start = secs[0].weight(i);
        let weight_end = secs[secs.len() - 1].weight(i);
        let interp = Interpolation {
            degree: degree_v,
            parametrization: opts.parametrization,
            knots: Default::default(),
            start_tangent: start.map(|t| (t.control_points()[i] * weight_start).extend(0.0)),
            end_tangent: end.map(|t| (t.control_points()[i] * weight_end).extend(0.0)),
        };
        interpolate_at(&column, &params, &interp).map_err(|e| match e {
            GeomError::ZeroVector { .. } => GeomError::ZeroVector {
                what: "loft tangent at a control point",
            },
            other => other,
        })
    };
    // A small net is lofted faster than the thread pool is asked.
    let columns: Vec<Result<_>> = if count_u * secs.len() >= PARALLEL_POINTS {
        (0..count_u).into_par_iter().map(column).collect()
    } else {
        (0..count_u).map(column).collect()
    };
    let columns = columns.into_iter().collect::<Result<Vec<_>>>()?;
    let count_v = columns[0].control_points().len();
    let mut points = Vec::with_capacity(count_u * count_v);
    let mut weights = Vec::with_capacity(count_u * count_v);
    for col in &columns {
        for h in col.control_points() {
            points.push(h.truncate() / h.w);
            weights.push(h.w);
        }
    }
    if weights.iter().any(|w| !(w.is_finite() && *w > 0.0)) {
        return Err(GeomError::Singular {
            what: "the loft's interpolated weights are not positive",
        });
    }
    Ok(NurbsSurface::from_parts(
        (secs[0].degree(), degree_v),
        (
            secs[0].knots().as_slice().to_vec(),
            columns[0].knots().as_slice().to_vec(),
        ),
        (count_u, count_v),
        points,
        rational.then_some(weights),
    ))
}

/// Section parameters on [0, 1]: for every control-point column the chord-length (or
/// centripetal) parameters, averaged over the columns (P&T eq. 10.8). [`loft`]
/// interpolates compatible sections at exactly these `v`; callers that build the
/// cross-boundary tangents or check between sections use them too.
pub fn section_parameters(secs: &[Curve3], method: Parametrization) -> Result<Vec<f64>> {
    let k = secs.len();
    if method == Parametrization::Uniform {
        return Ok((0..k).map(|j| j as f64 / (k - 1) as f64).collect());
    }
    let n = secs[0].control_points().len();
    let mut params = vec![0.0; k];
    let mut columns = 0usize;
    for i in 0..n {
        let steps: Vec<f64> = secs
            .windows(2)
            .map(|w| {
                let d = w[0].control_points()[i].distance(w[1].control_points()[i]);
                if method == Parametrization::Centripetal {
                    d.sqrt()
                } else {
                    d
                }
            })
            .collect();
        let total: f64 = steps.iter().sum();
        if total <= 0.0 {
            continue; // a column where all sections share a point (a collapsed edge)
        }
        let mut acc = 0.0;
        for (j, s) in steps.iter().enumerate() {
            acc += s;
            params[j + 1] += acc / total;
        }
        columns += 1;
    }
    if columns == 0 {
        return Err(GeomError::CoincidentPoints {
            first: 0,
            second: 1,
        });
    }
    for p in params.iter_mut() {
        *p /= columns as f64;
    }
    params[k - 1] = 1.0;
    if let Some(j) = params.windows(2).position(|w| w[1] <= w[0]) {
        return Err(GeomError::CoincidentPoints {
            first: j,
            second: j + 1,
        });
    }
    Ok(params)
}
