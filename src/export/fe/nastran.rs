//! Nastran bulk data (`.bdf`) of the die face as shell elements.
//!
//! `BEGIN BULK`, then per part a `PSHELL` (property id = part id, material 1 for
//! membrane and bending, the part's thickness) after a `$` comment with the part's name
//! and kind, one `MAT1` of steel, every node as a large-field `GRID*` with its
//! continuation (16-character fields, so coordinates keep six decimals, 1e-6 mm), the
//! shells as `CQUAD4` and `CTRIA3` with their part's property id, and `ENDDATA`.
//! Only bulk data, from `BEGIN BULK` on (a few `$` comments before it): the executive
//! and case control (the solution, loads, output) are the analysis setup's, written
//! ahead of this file's text.
//!
//! Nastran has no draw bead card (a draw bead is an explicit forming solver's contact),
//! so each bead is written as a block of `$` comments: its name, its restraining force
//! and its nodes' GRID ids in order along its line. A forming pre-processor that reads
//! Nastran meshes can pick them up from there; a solver ignores them.
//!
//! Small-field cards have eight-character fields, `GRID*` 16-character ones, numbers
//! right-aligned; reals always carry a decimal point. Units: mm, tonne, s, N, MPa.

use std::fmt::Write;

use glam::DVec3;

use super::{
    comment, node_id, numbered_shells, part_id, real, FeBead, FeModel, FePart, Shell, MATERIAL_ID,
    STEEL_DENSITY, STEEL_POISSON_RATIO, STEEL_YOUNGS_MODULUS,
};

/// Decimals of a coordinate: 1e-6 mm, and a value up to 1e7 mm still fits its field.
const COORDINATE_DECIMALS: usize = 6;

/// The die face as Nastran bulk data (ASCII, `\n` line ends, deterministic). Call
/// [`FeModel::check`] first: an unchecked model is written as given.
pub fn encode_nastran(model: &FeModel) -> Vec<u8> {
    let mut out = String::new();
    header(&mut out, model);
    out.push_str("BEGIN BULK\n");
    for (k, part) in model.parts.iter().enumerate() {
        property(&mut out, k, part);
    }
    material(&mut out);
    grids(&mut out, &model.nodes);
    elements(&mut out, model);
    for (b, bead) in model.beads.iter().enumerate() {
        bead_comments(&mut out, b, bead);
    }
    out.push_str("ENDDATA\n");
    out.into_bytes()
}

/// A small field (eight characters): an id right-aligned.
fn int8(id: u64) -> String {
    format!("{id:>8}")
}

/// A small field (eight characters): a real right-aligned.
fn real8(value: f64) -> String {
    real(value, 8, 6)
}

/// The comments before `BEGIN BULK`: what the deck is.
fn header(out: &mut String, model: &FeModel) {
    comment(out, &model.title);
    comment(
        out,
        &format!("dieface {} Nastran bulk data", env!("CARGO_PKG_VERSION")),
    );
    comment(out, "units: mm, t, s, N, MPa; press coordinates, +Z up");
    comment(
        out,
        "draw beads are comments at the end: Nastran has no draw bead card",
    );
}

/// `PSHELL` of the part at index `k`, after a comment with its name and kind.
fn property(out: &mut String, k: usize, part: &FePart) {
    let pid = part_id(k);
    comment(out, &format!("part {pid}: {} ({})", part.name, part.kind));
    let _ = writeln!(
        out,
        "PSHELL  {}{}{}{}",
        int8(pid),
        int8(MATERIAL_ID),
        real8(part.thickness),
        int8(MATERIAL_ID)
    );
}

/// The one `MAT1`: steel (placeholder values of a tool; G from E and NU).
fn material(out: &mut String) {
    comment(out, "material 1: tool steel");
    let _ = writeln!(
        out,
        "MAT1    {}{}{}{}{}",
        int8(MATERIAL_ID),
        real8(STEEL_YOUNGS_MODULUS),
        " ".repeat(8),
        real8(STEEL_POISSON_RATIO),
        real8(STEEL_DENSITY)
    );
}

/// Every node as `GRID*` (id, basic coordinates) and its `*` continuation (z).
fn grids(out: &mut String, nodes: &[DVec3]) {
    comment(out, &format!("{} nodes (mm)", nodes.len()));
    let coordinate = |c: f64| real(c, 16, COORDINATE_DECIMALS);
    for (i, p) in (0u32..).zip(nodes) {
        let _ = writeln!(
            out,
            "GRID*   {:>16}{}{}{}",
            node_id(i),
            " ".repeat(16),
            coordinate(p.x),
            coordinate(p.y)
        );
        let _ = writeln!(out, "*       {}", coordinate(p.z));
    }
}

/// The shells: `CQUAD4` or `CTRIA3`, element id, property id (its part's), nodes.
fn elements(out: &mut String, model: &FeModel) {
    let count: usize = model.parts.iter().map(|p| p.shells.len()).sum();
    comment(out, &format!("{count} shells, numbered through the parts"));
    for (eid, pid, shell) in numbered_shells(model) {
        let card = match shell {
            Shell::Quad(_) => "CQUAD4  ",
            Shell::Triangle(_) => "CTRIA3  ",
        };
        let _ = write!(out, "{card}{}{}", int8(eid), int8(pid));
        for &n in shell.nodes() {
            out.push_str(&int8(node_id(n)));
        }
        out.push('\n');
    }
}

/// The bead at index `b` as comments: name, force, its nodes' GRID ids in order.
fn bead_comments(out: &mut String, b: usize, bead: &FeBead) {
    comment(out, &format!("draw bead {}: {}", b + 1, bead.name));
    match bead.force {
        Some(force) => comment(out, &format!("restraining force: {force} N/mm")),
        None => comment(out, "no restraining force was given"),
    }
    comment(out, "nodes along the bead (GRID ids):");
    for line in bead.nodes.chunks(8) {
        let ids: String = line.iter().map(|&n| int8(node_id(n))).collect();
        let _ = writeln!(out, "$ {ids}");
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::export::fe::tests::one_quad;

    /// The deck's lines.
    fn lines(model: &FeModel) -> Vec<String> {
        String::from_utf8(encode_nastran(model))
            .expect("ASCII")
            .lines()
            .map(str::to_string)
            .collect()
    }

    /// The lines that start with `card`.
    fn cards(lines: &[String], card: &str) -> Vec<String> {
        lines
            .iter()
            .filter(|l| l.starts_with(card))
            .cloned()
            .collect()
    }

    /// Field 1 (the card name, eight characters) and then `width`-character fields.
    fn fields(line: &str, width: usize) -> Vec<String> {
        let (name, rest) = line.split_at(8.min(line.len()));
        std::iter::once(name.trim().to_string())
            .chain(
                rest.as_bytes()
                    .chunks(width)
                    .map(|c| String::from_utf8_lossy(c).trim().to_string()),
            )
            .collect()
    }

    #[test]
    fn the_one_quad_deck_card_by_card() {
        let l = lines(&one_quad());
        let begin = l
            .iter()
            .position(|l| l == "BEGIN BULK")
            .expect("BEGIN BULK");
        assert!(l[..begin].iter().all(|l| l.starts_with('$')));
        assert_eq!(l.last().map(String::as_str), Some("ENDDATA"));
        assert!(l.contains(&"$ part 1: binder (blankholder)".into()));
        let pshell = cards(&l, "PSHELL");
        assert_eq!(fields(&pshell[0], 8), ["PSHELL", "1", "1", "1.00000", "1"]);
        let mat = cards(&l, "MAT1");
        assert_eq!(
            fields(&mat[0], 8),
            ["MAT1", "1", "210000.", "", "0.30000", "7.85E-9"]
        );
        let grid = l
            .iter()
            .position(|l| l.starts_with("GRID*"))
            .expect("GRID*");
        assert_eq!(
            l[grid + 4],
            "GRID*                  3                        1.000000        1.000000"
        );
        assert_eq!(l[grid + 5], "*               0.000000");
        assert_eq!(
            fields(&l[grid + 4], 16),
            ["GRID*", "3", "", "1.000000", "1.000000"]
        );
        assert_eq!(cards(&l, "GRID*").len(), 4);
        assert_eq!(cards(&l, "*").len(), 4);
        assert_eq!(
            fields(&cards(&l, "CQUAD4")[0], 8),
            ["CQUAD4", "1", "1", "1", "2", "3", "4"]
        );
        let bead = l
            .iter()
            .position(|l| l == "$ draw bead 1: bead")
            .expect("bead");
        assert_eq!(l[bead + 1], "$ restraining force: 150 N/mm");
        assert_eq!(l[bead + 3], "$        1       2");
        for line in &l {
            assert!(line.len() <= 80, "{line:?} is over 80 columns");
        }
    }

    #[test]
    fn triangles_are_ctria3_with_their_parts_property() {
        let mut m = one_quad();
        m.parts.push(FePart {
            name: "die".into(),
            kind: "step_draw".into(),
            thickness: 0.75,
            shells: vec![Shell::Triangle([1, 2, 3])],
        });
        m.beads[0].force = None;
        let l = lines(&m);
        assert_eq!(
            fields(&cards(&l, "CTRIA3")[0], 8),
            ["CTRIA3", "2", "2", "2", "3", "4"]
        );
        assert_eq!(fields(&cards(&l, "PSHELL")[1], 8)[3], "0.75000");
        assert!(l.contains(&"$ no restraining force was given".into()));
    }

    #[test]
    fn the_same_model_gives_the_same_bytes() {
        let m = one_quad();
        assert_eq!(encode_nastran(&m), encode_nastran(&m.clone()));
    }
}
