//! The review snapshot of a script (`dieface snapshot`, `FILE.die.snap`): `inspect`'s
//! summary made stable enough to commit beside the script, and the line diff that
//! `--check` prints when it no longer matches.
//!
//! One line per declaration (kind, name, the line that declared it, its summary and
//! area) with a feature's quality figures under it, then one line per piece of a
//! feature or list (`binder/front_nose`: its kind, line, shape, bounds and area or
//! length). Every number is rounded to 7 significant digits and at most 6 decimals
//! ([`coarsen`]), so float noise (a last bit that differs between machines or thread
//! counts) cannot change a line, while any edit a designer would see does. Evaluation
//! times are left out. Pure functions: `cli` writes and compares the text.

use crate::diag::Sources;
use crate::die::model::{DieModel, Part, Shape};
use crate::eval::summary::{
    bbox, bounds, describe, feature_report, sampled_curve, sampled_surface,
};
use crate::eval::Outcome;

/// The first line of every snapshot: what the file is and how to renew it.
pub const HEADER: &str =
    "# dieface snapshot: review with `dieface snapshot FILE --check`, renew with `--update`";

/// The snapshot text of a clean evaluation and its die model: [`HEADER`], the
/// declarations, then the pieces, each line ended by `\n`.
pub fn snapshot_text(outcome: &Outcome, sources: &Sources, model: &DieModel) -> String {
    let mut lines = vec![HEADER.to_string()];
    for d in &outcome.decls {
        let line = sources.line(d.span);
        let mut summary = describe(d.value.as_ref());
        if let Some(a) = d.value.as_ref().and_then(value_area) {
            summary.push_str(&format!(", area {a} mm²"));
        }
        lines.push(format!("{} {} (line {line}): {summary}", d.kind, d.name));
        if let Some(v) = &d.value {
            lines.extend(feature_report(v).into_iter().map(|l| format!("    {l}")));
        }
    }
    for part in &model.parts {
        for piece in part.walk().into_iter().skip(1) {
            lines.push(format!(
                "piece {} ({}, line {}): {}",
                piece.name,
                piece.kind,
                piece.line,
                piece_summary(piece)
            ));
        }
    }
    let mut text = String::new();
    for l in lines {
        text.push_str(&coarsen(&l));
        text.push('\n');
    }
    text
}

/// The area of a value's surface or mesh (mm²).
fn value_area(v: &crate::eval::value::Value) -> Option<f64> {
    use crate::eval::value::Data;
    match &v.data {
        Data::Surface(s) => Some(s.area()),
        Data::Trimmed(t) => Some(t.area()),
        Data::Mesh(m) => Some(m.total_area()),
        _ => None,
    }
}

/// One piece's shape: its type, bounds, and area or length (also what the viewer shows
/// of a picked piece).
pub fn piece_summary(part: &Part) -> String {
    match &part.shape {
        None => format!("group of {}", part.children.len()),
        Some(Shape::Surface(s)) => {
            let (nu, nv) = s.counts();
            let (lo, hi) = bounds(sampled_surface(s));
            format!(
                "surface {}x{}, {nu}x{nv} control points, bounds {}, area {} mm²",
                s.degree_u(),
                s.degree_v(),
                bbox(lo, hi),
                s.area()
            )
        }
        Some(Shape::Trimmed(t)) => {
            let (lo, hi) = bounds(sampled_curve(t.outer().curve()));
            format!(
                "trimmed surface, bounds {}, area {} mm²",
                bbox(lo, hi),
                t.area()
            )
        }
        Some(Shape::Mesh(m)) => {
            let (tri, quads) = m.triangle_and_quad_counts();
            let b = m
                .bounding_box()
                .map_or("empty".to_string(), |(lo, hi)| bbox(lo, hi));
            format!(
                "mesh, {} vertices, {tri} triangles, {quads} quads, bounds {b}, area {} mm²",
                m.vertex_count(),
                m.total_area()
            )
        }
        Some(Shape::Curve(c)) => {
            let (lo, hi) = bounds(sampled_curve(c));
            format!(
                "curve, degree {}, {} control points, bounds {}, length {} mm",
                c.degree(),
                c.control_points().len(),
                bbox(lo, hi),
                c.length()
            )
        }
    }
}

/// `text` with every decimal number in it rounded to 7 significant digits and at most 6
/// decimals (`-0` written `0`): the snapshot's guard against float noise. A number is a
/// run of digits with an optional fraction that does not follow a letter, digit, `_` or
/// `.` (so `patch_2.draft` and `3x3` keep their digits); a whole number is kept as it is.
pub fn coarsen(text: &str) -> String {
    let bytes = text.as_bytes();
    let mut out = String::with_capacity(text.len());
    let mut i = 0;
    while i < bytes.len() {
        let c = bytes[i];
        let after_word = i > 0 && {
            let p = bytes[i - 1];
            p.is_ascii_alphanumeric() || p == b'_' || p == b'.'
        };
        if !c.is_ascii_digit() || after_word {
            // Copy one whole character (the text is UTF-8: `²`, `°`).
            let len = text[i..].chars().next().map_or(1, char::len_utf8);
            out.push_str(&text[i..i + len]);
            i += len;
            continue;
        }
        let start = i;
        while i < bytes.len() && bytes[i].is_ascii_digit() {
            i += 1;
        }
        let has_fraction = i + 1 < bytes.len() && bytes[i] == b'.' && bytes[i + 1].is_ascii_digit();
        if !has_fraction {
            out.push_str(&text[start..i]);
            continue;
        }
        i += 1;
        while i < bytes.len() && bytes[i].is_ascii_digit() {
            i += 1;
        }
        let digits = &text[start..i];
        match digits.parse::<f64>() {
            Ok(v) => {
                let negative = out.ends_with('-');
                let rounded = round_significant(v);
                if rounded == 0.0 && negative {
                    out.pop();
                }
                out.push_str(&format!("{rounded}"));
            }
            Err(_) => out.push_str(digits),
        }
    }
    out
}

/// `v` (not negative) rounded to 7 significant digits and at most 6 decimals.
fn round_significant(v: f64) -> f64 {
    if v == 0.0 || !v.is_finite() || v >= 1e15 {
        return v;
    }
    let magnitude = v.log10().floor() as i32;
    let decimals = (6 - magnitude).clamp(0, 6);
    let scale = 10f64.powi(decimals);
    (v * scale).round() / scale
}

/// The lines of `old` and `new` that differ, as a unified diff: `@@ -a,b +c,d @@` hunks
/// of `-` (only in `old`) and `+` (only in `new`) lines with up to `context` unchanged
/// lines round them. Empty when the texts have the same lines.
pub fn line_diff(old: &str, new: &str, context: usize) -> Vec<String> {
    let a: Vec<&str> = old.lines().collect();
    let b: Vec<&str> = new.lines().collect();
    let ops = diff_ops(&a, &b);
    if ops.iter().all(|op| matches!(op, Op::Same(..))) {
        return Vec::new();
    }
    // Hunks: runs of changes with their context, joined when their contexts meet.
    let changed: Vec<usize> = (0..ops.len())
        .filter(|&k| !matches!(ops[k], Op::Same(..)))
        .collect();
    let mut ranges: Vec<(usize, usize)> = Vec::new();
    for &k in &changed {
        let (lo, hi) = (k.saturating_sub(context), (k + context + 1).min(ops.len()));
        match ranges.last_mut() {
            Some(r) if lo <= r.1 => r.1 = r.1.max(hi),
            _ => ranges.push((lo, hi)),
        }
    }
    let mut out = Vec::new();
    for (lo, hi) in ranges {
        let (mut a0, mut b0) = (None, None);
        let (mut na, mut nb) = (0, 0);
        let mut body = Vec::new();
        for op in &ops[lo..hi] {
            match *op {
                Op::Same(i, j) => {
                    a0.get_or_insert(i);
                    b0.get_or_insert(j);
                    na += 1;
                    nb += 1;
                    body.push(format!(" {}", a[i]));
                }
                Op::Removed(i, j) => {
                    a0.get_or_insert(i);
                    b0.get_or_insert(j);
                    na += 1;
                    body.push(format!("-{}", a[i]));
                }
                Op::Added(i, j) => {
                    a0.get_or_insert(i);
                    b0.get_or_insert(j);
                    nb += 1;
                    body.push(format!("+{}", b[j]));
                }
            }
        }
        out.push(format!(
            "@@ -{},{na} +{},{nb} @@",
            a0.unwrap_or(0) + 1,
            b0.unwrap_or(0) + 1
        ));
        out.extend(body);
    }
    out
}

/// One step of a line diff: the line numbers (0-based) in the old and the new text
/// where it stands.
#[derive(Debug, Clone, Copy)]
enum Op {
    /// The same line in both.
    Same(usize, usize),
    /// Old line `.0`, gone before new line `.1`.
    Removed(usize, usize),
    /// New line `.1`, added after old line `.0`.
    Added(usize, usize),
}

/// The most table cells the longest-common-subsequence table may have; beyond it the
/// middle (after the common head and tail) is told as all removed then all added.
const MAX_TABLE: usize = 16_000_000;

/// The edit steps from `a` to `b`: the common head and tail kept, the middle aligned by
/// the longest common subsequence of lines.
fn diff_ops(a: &[&str], b: &[&str]) -> Vec<Op> {
    let head = a.iter().zip(b).take_while(|(x, y)| x == y).count();
    let tail = a[head..]
        .iter()
        .rev()
        .zip(b[head..].iter().rev())
        .take_while(|(x, y)| x == y)
        .count();
    let (ma, mb) = (&a[head..a.len() - tail], &b[head..b.len() - tail]);
    let mut ops: Vec<Op> = (0..head).map(|k| Op::Same(k, k)).collect();
    let (n, m) = (ma.len(), mb.len());
    if (n + 1).saturating_mul(m + 1) > MAX_TABLE {
        ops.extend((0..n).map(|i| Op::Removed(head + i, head)));
        ops.extend((0..m).map(|j| Op::Added(head + n, head + j)));
    } else {
        // lcs[i][j]: the longest common subsequence of ma[i..] and mb[j..].
        let w = m + 1;
        let mut lcs = vec![0u32; (n + 1) * w];
        for i in (0..n).rev() {
            for j in (0..m).rev() {
                lcs[i * w + j] = if ma[i] == mb[j] {
                    lcs[(i + 1) * w + j + 1] + 1
                } else {
                    lcs[(i + 1) * w + j].max(lcs[i * w + j + 1])
                };
            }
        }
        let (mut i, mut j) = (0, 0);
        while i < n || j < m {
            if i < n && j < m && ma[i] == mb[j] {
                ops.push(Op::Same(head + i, head + j));
                i += 1;
                j += 1;
            } else if j == m || (i < n && lcs[(i + 1) * w + j] >= lcs[i * w + j + 1]) {
                ops.push(Op::Removed(head + i, head + j));
                i += 1;
            } else {
                ops.push(Op::Added(head + i, head + j));
                j += 1;
            }
        }
    }
    let (ta, tb) = (a.len() - tail, b.len() - tail);
    ops.extend((0..tail).map(|k| Op::Same(ta + k, tb + k)));
    ops
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn coarsen_rounds_numbers_but_not_names() {
        assert_eq!(
            coarsen("patch_2.draft 1234.56789012 mm, (0.000000, -0.0000001, 3x3) 12.5"),
            "patch_2.draft 1234.568 mm, (0, 0, 3x3) 12.5"
        );
        assert_eq!(coarsen("area 712345.123456 mm²"), "area 712345.1 mm²");
    }

    #[test]
    fn line_diff_names_the_changed_line_with_context() {
        let old = "a\nb\nc\nd\ne\n";
        let new = "a\nb\nC\nd\ne\nf\n";
        let d = line_diff(old, new, 1);
        assert_eq!(d, ["@@ -2,4 +2,5 @@", " b", "-c", "+C", " d", " e", "+f"]);
        assert!(line_diff(old, old, 1).is_empty());
    }
}
