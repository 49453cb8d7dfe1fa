//! Which point of the opening line each point of the product outline is matched with
//! (step 2 of [`super::build`]): the two ends of every intermediate section.
//!
//! Matching by arc-length fraction (paper 001, section 4) cuts a corner of the outline
//! at a slant wherever the outline and the opening turn over different shares of their
//! lengths, which they nearly always do: the opening's corner is wider and sits farther
//! along its side. A slanted section through a wall that turns round a corner is not
//! the wall's profile, and the die and punch radii came out a fifth tighter than drawn
//! there. So each product point is matched with the opening point on its normal in the
//! top view: every section leaves the product square, as a die designer cuts sections.
//! The two key sections are placed by the designer, not on normals: each patch's lines
//! are the normals turned (about the vertical) by the key sections' own turns from
//! theirs, faded linearly along the patch by the product's arc length, so both key
//! sections stay where they are. Where that does not give a matching that runs forward
//! along the opening (a concave stretch whose normals cross before they reach it), or
//! that spreads a tight product corner over far too much opening ([`MAX_SPREAD`]), or
//! whose opening no knots of the product can follow (a normal that meets the opening at
//! a graze), the patch falls back to arc-length fractions.

use glam::{DVec2, DVec3};

use super::ArcFractions;
use crate::geom::Curve3;

/// Samples along a patch at which the normal matching is checked to run forward.
const CHECKS: usize = 64;

/// The most opening length one unit of product length may be matched with. Round a
/// product corner much tighter than the step draw is wide, the normals fan out over
/// the opening (a 7 mm corner under 140 mm walls spreads 1 mm of product over 33 mm
/// of opening), the sections turn too fast for the rows interpolated between them and
/// the patch folds; such a patch is matched by arc length. The examples stay under
/// 3.5; a spread of 13 still gave a sound patch, one of 20 a folded one.
const MAX_SPREAD: f64 = 12.0;

/// The correspondence between a patch's product piece and its opening piece, and its
/// derivative, worked out exactly from the curves (so the sections' ends move along
/// both guides as smoothly as the curves themselves).
pub(super) struct Matching<'a> {
    product: &'a Curve3,
    opening: &'a Curve3,
    /// The product piece's arc lengths (its sections' positions along the outline).
    pub product_lengths: ArcFractions<'a>,
    opening_lengths: ArcFractions<'a>,
    /// Whether points are matched along the product's normals (else by arc length).
    normals: bool,
    /// How far the key sections turn from the product's normal (radians, about the
    /// vertical), at the patch's two ends; the turn fades linearly between them.
    ends: (f64, f64),
}

impl<'a> Matching<'a> {
    /// The matching along the product's normals where it suits the patch (it runs
    /// forward, within [`MAX_SPREAD`]), else by arc length.
    pub fn new(product: &'a Curve3, opening: &'a Curve3) -> Self {
        let mut m = Self::by_arc_length(product, opening);
        m.normals = true;
        let (v0, v1) = product.domain();
        let (t0, t1) = opening.domain();
        match (m.key_turn(v0, t0), m.key_turn(v1, t1)) {
            (Some(a), Some(b)) => m.ends = (a, b),
            _ => m.normals = false,
        }
        if m.normals && !m.runs_forward() {
            m.normals = false;
        }
        m
    }

    /// The plain arc-length matching (the paper's), for a patch the normals do not
    /// suit.
    pub fn by_arc_length(product: &'a Curve3, opening: &'a Curve3) -> Self {
        Self {
            product,
            opening,
            product_lengths: ArcFractions::new(product),
            opening_lengths: ArcFractions::new(opening),
            normals: false,
            ends: (0.0, 0.0),
        }
    }

    /// Whether points are matched along the product's normals.
    pub fn along_normals(&self) -> bool {
        self.normals
    }

    /// Whether the matching runs forward along the opening over the whole patch, never
    /// spreading a unit of product over more than [`MAX_SPREAD`] of opening.
    fn runs_forward(&self) -> bool {
        let (v0, v1) = self.product.domain();
        let mut last = f64::NEG_INFINITY;
        let mut worst: f64 = 0.0;
        for i in 0..=CHECKS {
            let v = v0 + (v1 - v0) * i as f64 / CHECKS as f64;
            let Some((t, rate)) = self.normal_match(v) else {
                return false;
            };
            if t < last || rate <= 0.0 {
                return false;
            }
            let product_speed = self.product.derivative_at(v).length();
            let spread = rate * self.opening.derivative_at(t).length() / product_speed.max(1e-300);
            worst = worst.max(spread);
            last = t;
        }
        worst <= MAX_SPREAD
    }

    /// The turn about the vertical from the product's tangent at `v` to the square of
    /// the line from the product point to the opening point at `t` (0 where that line
    /// is the product's normal).
    fn key_turn(&self, v: f64, t: f64) -> Option<f64> {
        let tangent = self.product.derivative_at(v).truncate().normalize_or_zero();
        let line = (self.opening.point_at(t) - self.product.point_at(v))
            .truncate()
            .normalize_or_zero();
        if tangent == DVec2::ZERO || line == DVec2::ZERO {
            return None;
        }
        // The square of the line nearer the tangent.
        let square = DVec2::new(line.y, -line.x);
        let square = if square.dot(tangent) < 0.0 {
            -square
        } else {
            square
        };
        Some(tangent.perp_dot(square).atan2(tangent.dot(square)))
    }

    /// The direction square to the matching line at `v`, where the product's length
    /// fraction is `f` (the product's tangent turned by the faded key turn), and its rate
    /// per unit of `v`.
    fn square_at(&self, v: f64, f: f64) -> Option<(DVec3, DVec2, DVec2)> {
        let [b, d1, d2] = self.product.derivatives::<3>(v);
        let (p1, p2) = (d1.truncate(), d2.truncate());
        let speed = p1.length();
        if speed == 0.0 {
            return None;
        }
        let tangent = p1 / speed;
        let tangent_rate = (p2 - tangent * tangent.dot(p2)) / speed;
        let fraction_rate = if self.product_lengths.total > 0.0 {
            d1.length() / self.product_lengths.total
        } else {
            0.0
        };
        let turn = (1.0 - f) * self.ends.0 + f * self.ends.1;
        let turn_rate = fraction_rate * (self.ends.1 - self.ends.0);
        let rotate = |x: DVec2, a: f64| {
            DVec2::new(x.x * a.cos() - x.y * a.sin(), x.x * a.sin() + x.y * a.cos())
        };
        let square = rotate(tangent, turn);
        let square_rate = rotate(tangent_rate, turn) + square.perp() * turn_rate;
        Some((b, square, square_rate))
    }

    /// The opening parameter on the matching line at `v` (through the product point,
    /// square to [`Matching::square_at`]), found by Newton from the arc-length match,
    /// with its rate `dt/dv`; `None` where it does not settle.
    fn normal_match(&self, v: f64) -> Option<(f64, f64)> {
        // The length fraction is a quadrature: worked out once for the turn and the
        // first guess.
        let f = self.product_lengths.fraction_at(v);
        let (b, square, square_rate) = self.square_at(v, f)?;
        let (lo, hi) = self.opening.domain();
        let (v0, v1) = self.product.domain();
        // The key sections' own points, exactly (they are shared with the neighbours).
        let key = if v <= v0 {
            Some(lo)
        } else if v >= v1 {
            Some(hi)
        } else {
            None
        };
        let mut t = key.unwrap_or_else(|| self.opening_lengths.t_at(f));
        for _ in 0..50 {
            let [o, od] = self.opening.derivatives::<2>(t);
            let value = (o - b).truncate().dot(square);
            let slope = od.truncate().dot(square);
            if slope.abs() <= 1e-12 {
                return None;
            }
            if key.is_some() || value.abs() <= 1e-10 * (1.0 + b.truncate().length()) {
                // By implicit differentiation of g(t, v) = (o(t) - b(v)) . q(v) = 0.
                let b_rate = self.product.derivative_at(v).truncate();
                let g_v = -b_rate.dot(square) + (o - b).truncate().dot(square_rate);
                return Some((t, -g_v / slope));
            }
            t = (t - value / slope).clamp(lo, hi);
        }
        None
    }

    /// The arc-length match of `v`.
    fn arc_length_t(&self, v: f64) -> f64 {
        self.opening_lengths
            .t_at(self.product_lengths.fraction_at(v))
    }

    /// The opening parameter matched with the product parameter `v`.
    pub fn opening_t(&self, v: f64) -> f64 {
        let (lo, hi) = self.opening.domain();
        if self.normals {
            if let Some((t, _)) = self.normal_match(v) {
                return t.clamp(lo, hi);
            }
        }
        self.arc_length_t(v)
    }

    /// The derivative, per unit of the product parameter, of the matched opening point.
    pub fn opening_derivative(&self, product: &Curve3, opening: &Curve3, v: f64) -> DVec3 {
        self.opening_derivative_at_speed(opening, v, product.derivative_at(v).length())
    }

    /// [`Matching::opening_derivative`] for a product parameter whose speed `|G_D'|` is
    /// given (one side of a joint, or a sub-piece's own parameter).
    pub fn opening_derivative_at_speed(
        &self,
        opening: &Curve3,
        v: f64,
        product_speed: f64,
    ) -> DVec3 {
        let own = self.product.derivative_at(v).length();
        if own == 0.0 {
            return DVec3::ZERO;
        }
        if self.normals {
            if let Some((t, rate)) = self.normal_match(v) {
                return opening.derivative_at(t) * rate * product_speed / own;
            }
        }
        // By arc length: the opening's unit tangent times its length per unit of
        // fraction times the fraction's rate along the product.
        let t = self.arc_length_t(v);
        let dop = opening.derivative_at(t);
        let speed = dop.length();
        if speed == 0.0 || self.product_lengths.total == 0.0 {
            return DVec3::ZERO;
        }
        dop / speed * self.opening_lengths.total * product_speed / self.product_lengths.total
    }
}
