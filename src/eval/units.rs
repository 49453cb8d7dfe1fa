//! Units: conversion of literals to base units and the per-file defaults.

use crate::diag::Diagnostic;
use crate::syntax::ast::Unit;
use crate::syntax::Span;

use super::value::{Dim, Quantity};

/// A file's default units for bare numbers, as factors to base units.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Units {
    /// Millimetres per default length unit (1 for mm).
    pub length: f64,
    /// Radians per default angle unit (pi/180 for degrees).
    pub angle: f64,
}

impl Default for Units {
    /// Millimetres and degrees, the die designer's units.
    fn default() -> Self {
        Self {
            length: 1.0,
            angle: std::f64::consts::PI / 180.0,
        }
    }
}

/// The quantity a literal `value unit` denotes, in base units.
pub fn quantity(value: f64, unit: Unit) -> Quantity {
    match unit {
        Unit::Mm => Quantity::length(value),
        Unit::Cm => Quantity::length(value * 10.0),
        Unit::M => Quantity::length(value * 1000.0),
        Unit::In => Quantity::length(value * 25.4),
        Unit::Deg => Quantity::angle(value.to_radians()),
        Unit::Rad => Quantity::angle(value),
        Unit::Percent => Quantity::ratio(value / 100.0),
    }
}

/// The quantity of the literal `value unit` written at `span`, or a diagnostic when the
/// conversion to base units overflows or underflows ([`super::finite::conversion`]):
/// `1e306 m` is more millimetres than a number holds.
pub fn literal(value: f64, unit: Unit, span: Span) -> Result<Quantity, Diagnostic> {
    let q = quantity(value, unit);
    let written = format!("{} {}", super::finite::show(value), unit.symbol());
    super::finite::conversion(q.value, &written, span)?;
    Ok(q)
}

/// Base units per one `unit` (for `units` directives).
pub fn factor(unit: Unit) -> (Dim, f64) {
    let q = quantity(1.0, unit);
    (q.dim, q.value)
}

/// Formats a quantity in the designer's units (mm, deg) for messages and summaries.
pub fn display(q: Quantity) -> String {
    match q.dim {
        Dim::LENGTH => format!("{} mm", round(q.value)),
        Dim::ANGLE => format!("{} deg", round(q.value.to_degrees())),
        d if d.is_none() => format!("{}", round(q.value)),
        d => format!("{} ({d}, base units mm and rad)", round(q.value)),
    }
}

/// Rounds to 6 decimals for display, dropping `-0`; numbers of 1e15 and more (whole
/// already, and whose `v * 1e6` could overflow) are kept as they are.
pub fn round(v: f64) -> f64 {
    if v == 0.0 || !v.is_finite() || v.abs() >= 1e15 {
        return if v == 0.0 { 0.0 } else { v };
    }
    let r = (v * 1e6).round() / 1e6;
    if r == 0.0 {
        0.0
    } else {
        r
    }
}
