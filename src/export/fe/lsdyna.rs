//! LS-DYNA keyword deck (`.k`) of the die face as rigid shell tools.
//!
//! Blocks in order, each after a `$` comment naming it: `*KEYWORD`, `*TITLE`, a `*PART`
//! per part (its name as the heading; part id, section id = part id, material 1),
//! a `*SECTION_SHELL` per part (Belytschko-Tsay shells, the part's thickness at all four
//! corners), one `*MAT_RIGID` of steel (a die face is a rigid tool; how it moves and
//! what constrains it is the forming setup's), `*NODE`, `*ELEMENT_SHELL` (a triangle
//! repeats its third node as the fourth, as LS-DYNA takes three-node shells), then per
//! draw bead a `*SET_NODE_LIST` of its line's nodes, its restraining force as a
//! `*DEFINE_CURVE`, and a `*CONTACT_DRAWBEAD` with the bead's nodes as slave and the
//! blank as master, and `*END`.
//!
//! Everything is in LS-DYNA's standard fixed format: ids in eight-character fields on
//! `*NODE` and `*ELEMENT_SHELL` (I8), ten elsewhere (I10); coordinates in 16-character
//! fields with six decimals (1e-6 mm) and a leading space; other reals in 10- or
//! 20-character fields. Units: mm, tonne, s, N, MPa.
//!
//! The blank is not part of the die face, so each bead contact names its master as the
//! part set [`BLANK_PART_SET`], which the forming setup defines (`*SET_PART`) with the
//! blank in it. A bead's nodes that are not nodes of a tool's shells must be attached
//! to that tool by the forming setup (`*CONSTRAINED_EXTRA_NODES_SET`); ones on a tool's
//! shells move with it.
//!
//! Card layout of `*CONTACT_DRAWBEAD`: cards 1 to 3 as every `*CONTACT` (SSID MSID
//! SSTYP MSTYP ..., FS FD DC VC VDC PENCHK BT DT, SFS SFM SST MST SFST SFMT FSF VSF),
//! then card 4: LCIDRF LCIDNF DBDTH DFSCL NUMINT; SSTYP 4 is a node set, MSTYP 2 a part
//! set. Checked field by field against Ansys's pydyna (`ansys/pydyna`,
//! `keyword_classes/auto/contact_drawbead.py`, generated from the Keyword User's
//! Manual's keyword database): the fields, their 10-character columns and defaults,
//! LCIDRF as the bending restraint per unit bead length against displacement, and
//! DBDTH the draw bead depth the solver needs for that displacement. A solver run was
//! not at hand.

use std::fmt::Write;

use glam::DVec3;
use rayon::prelude::*;

use super::{
    comment, node_id, numbered_shells, part_id, plain_line, push_int, push_real, real, FeBead,
    FeModel, FePart, Shell, MATERIAL_ID, STEEL_DENSITY, STEEL_POISSON_RATIO, STEEL_YOUNGS_MODULUS,
};

/// The part set id every bead contact takes as its master: the blank's, which is not in
/// the die face, so the forming setup defines it (`*SET_PART`).
pub const BLANK_PART_SET: u64 = 1;

/// The displacement (mm) a bead's restraining force curve reaches: far past any draw
/// depth, so the solver never extrapolates it.
pub const BEAD_CURVE_REACH: f64 = 1e3;

/// LS-DYNA's shell formulation 2, Belytschko-Tsay: its default, and what forming
/// setups take for rigid tools (the formulation does not change a rigid part's motion).
const ELFORM: u64 = 2;

/// Decimals of a coordinate: 1e-6 mm, and a value up to 1e7 mm still fits its field.
const COORDINATE_DECIMALS: usize = 6;

/// The length of a `*NODE` line (I8, three 16-character reals, `\n`) and of an
/// `*ELEMENT_SHELL` line (six I8, `\n`).
const NODE_LINE: usize = 57;
const SHELL_LINE: usize = 49;

/// The `*NODE` and `*ELEMENT_SHELL` lines are written in pieces of this many, side by
/// side on rayon's pool, and joined in order: the same text on any number of cores.
const LINES_PER_PIECE: usize = 8192;

/// The die face as an LS-DYNA keyword deck (ASCII, `\n` line ends, deterministic).
/// Call [`FeModel::check`] first: an unchecked model is written as given.
pub fn encode_lsdyna(model: &FeModel) -> Vec<u8> {
    // About the deck's size (a node's line is 57 bytes, a shell's 49), so the text is
    // not copied as it grows.
    let shells: usize = model.parts.iter().map(|p| p.shells.len()).sum();
    let mut out = String::with_capacity(NODE_LINE * model.nodes.len() + SHELL_LINE * shells + 4096);
    header(&mut out, model);
    for (k, part) in model.parts.iter().enumerate() {
        part_card(&mut out, k, part);
    }
    for (k, part) in model.parts.iter().enumerate() {
        section(&mut out, k, part);
    }
    material(&mut out);
    nodes(&mut out, &model.nodes);
    elements(&mut out, model);
    for (b, bead) in model.beads.iter().enumerate() {
        bead_cards(&mut out, b, bead);
    }
    out.push_str("*END\n");
    out.into_bytes()
}

/// An id right-aligned in a field of `width` characters.
fn int(id: u64, width: usize) -> String {
    format!("{id:>width$}")
}

/// A real in a ten-character field.
fn real10(value: f64) -> String {
    real(value, 10, 6)
}

/// `*KEYWORD`, `*TITLE` and the comments saying what the deck is.
fn header(out: &mut String, model: &FeModel) {
    out.push_str("*KEYWORD\n");
    comment(
        out,
        &format!("dieface {} LS-DYNA deck", env!("CARGO_PKG_VERSION")),
    );
    comment(out, "units: mm, t, s, N, MPa; press coordinates, +Z up");
    comment(out, "the die face as rigid shell tools (*MAT_RIGID)");
    out.push_str("*TITLE\n");
    let title = plain_line(&model.title, 80);
    let title = if title.trim().is_empty() {
        "die face".to_string()
    } else {
        title
    };
    let _ = writeln!(out, "{title}");
}

/// `*PART` of the part at index `k`: its name as the heading, its id, section and
/// material.
fn part_card(out: &mut String, k: usize, part: &FePart) {
    let pid = part_id(k);
    comment(out, &format!("part {pid}: {} ({})", part.name, part.kind));
    out.push_str("*PART\n");
    let heading = plain_line(&part.name, 70);
    if heading.trim().is_empty() {
        let _ = writeln!(out, "part {pid}");
    } else {
        let _ = writeln!(out, "{heading}");
    }
    out.push_str("$#     pid     secid       mid\n");
    let _ = writeln!(
        out,
        "{}{}{}",
        int(pid, 10),
        int(pid, 10),
        int(MATERIAL_ID, 10)
    );
}

/// `*SECTION_SHELL` of the part at index `k`: section id = part id, Belytschko-Tsay,
/// the part's thickness at the four corners.
fn section(out: &mut String, k: usize, part: &FePart) {
    let secid = part_id(k);
    comment(
        out,
        &format!("section {secid}: {} mm shells", part.thickness),
    );
    out.push_str("*SECTION_SHELL\n");
    out.push_str("$#   secid    elform      shrf       nip\n");
    let _ = writeln!(
        out,
        "{}{}{}{}",
        int(secid, 10),
        int(ELFORM, 10),
        real10(1.0),
        real10(2.0)
    );
    out.push_str("$#      t1        t2        t3        t4\n");
    let t = real10(part.thickness);
    let _ = writeln!(out, "{t}{t}{t}{t}");
}

/// The one `*MAT_RIGID`: steel, placeholder values of a rigid tool (its mass and
/// stiffness only scale the contact); no constraints (`CMO` 0), which the forming
/// setup gives with the tool's motion.
fn material(out: &mut String) {
    comment(
        out,
        "material 1: rigid tool steel (constraints: the forming setup's)",
    );
    out.push_str("*MAT_RIGID\n");
    out.push_str("$#     mid        ro         e        pr\n");
    let _ = writeln!(
        out,
        "{}{}{}{}",
        int(MATERIAL_ID, 10),
        real10(STEEL_DENSITY),
        real10(STEEL_YOUNGS_MODULUS),
        real10(STEEL_POISSON_RATIO)
    );
    out.push_str("$#     cmo      con1      con2\n");
    let _ = writeln!(out, "{}", real10(0.0).repeat(3));
    out.push_str("$#lco or a1        a2        a3        v1        v2        v3\n");
    let zero = real10(0.0);
    let _ = writeln!(out, "{}", zero.repeat(6));
}

/// `*NODE`: id (I8) and x, y, z (3 x 16 characters, six decimals).
fn nodes(out: &mut String, nodes: &[DVec3]) {
    comment(out, &format!("{} nodes (mm)", nodes.len()));
    out.push_str("*NODE\n");
    out.push_str("$#   nid               x               y               z\n");
    let lines = nodes
        .par_chunks(LINES_PER_PIECE)
        .enumerate()
        .map(|(piece, chunk)| {
            let mut text = String::with_capacity(NODE_LINE * chunk.len());
            for (i, p) in (piece * LINES_PER_PIECE..).zip(chunk) {
                // `check` keeps the node count within `MAX_ID`, and `u32` holds it.
                push_int(&mut text, node_id(i as u32), 8);
                for c in [p.x, p.y, p.z] {
                    push_real(&mut text, c, 16, COORDINATE_DECIMALS);
                }
                text.push('\n');
            }
            text
        })
        .collect::<Vec<String>>();
    lines.iter().for_each(|piece| out.push_str(piece));
}

/// `*ELEMENT_SHELL`: element id, part id and four nodes (I8 each); a triangle repeats
/// its third node.
fn elements(out: &mut String, model: &FeModel) {
    let count: usize = model.parts.iter().map(|p| p.shells.len()).sum();
    comment(out, &format!("{count} shells, numbered through the parts"));
    out.push_str("*ELEMENT_SHELL\n");
    out.push_str("$#   eid     pid      n1      n2      n3      n4\n");
    let shells: Vec<(u64, u64, &Shell)> = numbered_shells(model).collect();
    let lines = shells
        .par_chunks(LINES_PER_PIECE)
        .map(|chunk| {
            let mut text = String::with_capacity(SHELL_LINE * chunk.len());
            for &(eid, pid, shell) in chunk {
                let [a, b, c, d] = match *shell {
                    Shell::Quad(n) => n,
                    Shell::Triangle([a, b, c]) => [a, b, c, c],
                };
                for id in [eid, pid, node_id(a), node_id(b), node_id(c), node_id(d)] {
                    push_int(&mut text, id, 8);
                }
                text.push('\n');
            }
            text
        })
        .collect::<Vec<String>>();
    lines.iter().for_each(|piece| out.push_str(piece));
}

/// The bead at index `b`: its node set, its force curve (or a comment that there is
/// none) and its contact. Set, curve and bead share the id `b + 1`.
fn bead_cards(out: &mut String, b: usize, bead: &FeBead) {
    let id = b as u64 + 1;
    comment(out, &format!("draw bead {id}: {}", bead.name));
    node_set(out, id, bead);
    match bead.force {
        Some(force) => force_curve(out, id, force),
        None => comment(
            out,
            &format!("no restraining force was given for bead {id}: no curve, LCIDRF 0"),
        ),
    }
    contact(out, id, bead.force.map(|_| id), bead.depth);
}

/// `*SET_NODE_LIST` `id`: the bead's nodes in order along its line, eight to a card.
fn node_set(out: &mut String, id: u64, bead: &FeBead) {
    out.push_str("*SET_NODE_LIST\n");
    out.push_str("$#     sid\n");
    let _ = writeln!(out, "{}", int(id, 10));
    out.push_str(
        "$#    nid1      nid2      nid3      nid4      nid5      nid6      nid7      nid8\n",
    );
    for card in bead.nodes.chunks(8) {
        for &n in card {
            out.push_str(&int(node_id(n), 10));
        }
        out.push('\n');
    }
}

/// `*DEFINE_CURVE` `id`: the restraining force per unit length (N/mm), the same over
/// displacements from 0 to [`BEAD_CURVE_REACH`].
fn force_curve(out: &mut String, id: u64, force: f64) {
    comment(
        out,
        &format!("restraining force of bead {id}: {force} N/mm at any displacement (mm)"),
    );
    out.push_str("*DEFINE_CURVE\n");
    out.push_str("$#    lcid\n");
    let _ = writeln!(out, "{}", int(id, 10));
    out.push_str("$#                a1                  o1\n");
    for a in [0.0, BEAD_CURVE_REACH] {
        let _ = writeln!(out, "{}{}", real(a, 20, 6), real(force, 20, 6));
    }
}

/// `*CONTACT_DRAWBEAD`: node set `id` (SSTYP 4) as slave, the blank's part set
/// [`BLANK_PART_SET`] (MSTYP 2) as master, no friction (the bead's force is the whole
/// restraint), default stiffness, the restraining force curve `curve` (0: none), and
/// the bead's depth (DBDTH, mm), from which the solver measures how far into the bead
/// the blank has gone.
fn contact(out: &mut String, id: u64, curve: Option<u64>, depth: f64) {
    out.push_str("*CONTACT_DRAWBEAD\n");
    comment(
        out,
        "master: the blank's part set, defined by the forming setup",
    );
    out.push_str("$#    ssid      msid     sstyp     mstyp\n");
    let _ = writeln!(
        out,
        "{}{}{}{}",
        int(id, 10),
        int(BLANK_PART_SET, 10),
        int(4, 10),
        int(2, 10)
    );
    out.push_str(
        "$#      fs        fd        dc        vc       vdc    penchk        bt        dt\n",
    );
    let _ = writeln!(
        out,
        "{}{}{}{}",
        real10(0.0).repeat(5),
        int(0, 10),
        real10(0.0),
        real10(1e20)
    );
    out.push_str(
        "$#     sfs       sfm       sst       mst      sfst      sfmt       fsf       vsf\n",
    );
    let _ = writeln!(
        out,
        "{}{}{}",
        real10(1.0).repeat(2),
        real10(0.0).repeat(2),
        real10(1.0).repeat(4)
    );
    out.push_str("$#  lcidrf    lcidnf     dbdth     dfscl    numint\n");
    let _ = writeln!(
        out,
        "{}{}{}{}{}",
        int(curve.unwrap_or(0), 10),
        int(0, 10),
        real10(depth),
        real10(1.0),
        int(0, 10)
    );
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::export::fe::tests::one_quad;

    /// The deck's lines.
    fn lines(model: &FeModel) -> Vec<String> {
        String::from_utf8(encode_lsdyna(model))
            .expect("ASCII")
            .lines()
            .map(str::to_string)
            .collect()
    }

    /// The lines of the block opened by `keyword` (its `n`-th), comments left out.
    fn block(lines: &[String], keyword: &str, n: usize) -> Vec<String> {
        let start = lines
            .iter()
            .enumerate()
            .filter(|(_, l)| l.as_str() == keyword)
            .nth(n)
            .map(|(i, _)| i)
            .unwrap_or_else(|| panic!("no {keyword} number {n}"));
        lines[start + 1..]
            .iter()
            .take_while(|l| !l.starts_with('*'))
            .filter(|l| !l.starts_with('$'))
            .cloned()
            .collect()
    }

    /// The fixed-width fields of a card line.
    fn fields(line: &str, width: usize) -> Vec<String> {
        line.as_bytes()
            .chunks(width)
            .map(|c| String::from_utf8_lossy(c).trim().to_string())
            .collect()
    }

    #[test]
    fn the_one_quad_deck_card_by_card() {
        let l = lines(&one_quad());
        assert_eq!(l[0], "*KEYWORD");
        assert_eq!(l.last().map(String::as_str), Some("*END"));
        assert_eq!(block(&l, "*TITLE", 0), ["one quad"]);
        let part = block(&l, "*PART", 0);
        assert_eq!(part[0], "binder");
        assert_eq!(fields(&part[1], 10), ["1", "1", "1"]);
        let section = block(&l, "*SECTION_SHELL", 0);
        assert_eq!(fields(&section[0], 10), ["1", "2", "1.000000", "2.000000"]);
        assert_eq!(fields(&section[1], 10), ["1.000000"; 4]);
        let mat = block(&l, "*MAT_RIGID", 0);
        assert_eq!(
            fields(&mat[0], 10),
            ["1", "7.85E-9", "210000.00", "0.300000"]
        );
        assert_eq!(mat.len(), 3, "three cards: {mat:?}");
        let nodes = block(&l, "*NODE", 0);
        assert_eq!(nodes.len(), 4);
        assert_eq!(
            nodes[2],
            "       3        1.000000        1.000000        0.000000"
        );
        let shells = block(&l, "*ELEMENT_SHELL", 0);
        assert_eq!(shells, ["       1       1       1       2       3       4"]);
        let set = block(&l, "*SET_NODE_LIST", 0);
        assert_eq!(fields(&set[0], 10), ["1"]);
        assert_eq!(fields(&set[1], 10), ["1", "2"]);
        let curve = block(&l, "*DEFINE_CURVE", 0);
        assert_eq!(fields(&curve[0], 10), ["1"]);
        assert_eq!(fields(&curve[1], 20), ["0.000000", "150.000000"]);
        assert_eq!(fields(&curve[2], 20), ["1000.000000", "150.000000"]);
        let contact = block(&l, "*CONTACT_DRAWBEAD", 0);
        assert_eq!(contact.len(), 4, "cards 1 to 4: {contact:?}");
        assert_eq!(fields(&contact[0], 10), ["1", "1", "4", "2"]);
        assert_eq!(fields(&contact[1], 10)[7], "1.E20");
        assert_eq!(
            fields(&contact[3], 10),
            ["1", "0", "6.000000", "1.000000", "0"]
        );
        assert!(l.contains(&"$ master: the blank's part set, defined by the forming setup".into()));
        for line in &l {
            assert!(line.len() <= 80, "{line:?} is over 80 columns");
        }
    }

    #[test]
    fn a_triangle_repeats_its_third_node_and_ids_run_through_parts() {
        let mut m = one_quad();
        m.parts.push(FePart {
            name: "die".into(),
            kind: "step_draw".into(),
            thickness: 0.75,
            shells: vec![Shell::Triangle([1, 2, 3])],
        });
        let l = lines(&m);
        let shells = block(&l, "*ELEMENT_SHELL", 0);
        assert_eq!(
            shells[1],
            "       2       2       2       3       4       4"
        );
        assert_eq!(block(&l, "*PART", 1)[0], "die");
        assert_eq!(
            fields(&block(&l, "*SECTION_SHELL", 1)[1], 10),
            ["0.750000"; 4]
        );
    }

    #[test]
    fn a_bead_without_force_has_no_curve() {
        let mut m = one_quad();
        m.beads[0].force = None;
        m.beads[0].nodes = (0..4).chain(0..6).collect();
        let l = lines(&m);
        assert!(!l.iter().any(|l| l == "*DEFINE_CURVE"));
        assert!(l
            .iter()
            .any(|l| l.contains("no restraining force was given")));
        let set = block(&l, "*SET_NODE_LIST", 0);
        assert_eq!(set.len(), 3, "ten nodes: eight and two: {set:?}");
        assert_eq!(fields(&set[2], 10), ["5", "6"]);
        assert_eq!(fields(&block(&l, "*CONTACT_DRAWBEAD", 0)[3], 10)[0], "0");
    }

    #[test]
    fn the_same_model_gives_the_same_bytes() {
        let m = one_quad();
        assert_eq!(encode_lsdyna(&m), encode_lsdyna(&m.clone()));
    }

    #[test]
    fn names_cannot_break_the_deck() {
        let mut m = one_quad();
        m.title = "*END\nx".into();
        m.parts[0].name = "*NODE".into();
        let l = lines(&m);
        assert_eq!(block(&l, "*TITLE", 0), [" *END x"]);
        assert_eq!(l.iter().filter(|l| l.as_str() == "*NODE").count(), 1);
        assert_eq!(l.iter().filter(|l| l.as_str() == "*END").count(), 1);
    }
}
