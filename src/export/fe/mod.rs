//! Finite-element decks of the die face: shell elements a forming simulation reads as
//! its rigid tools (paper 004, issue 18: forming simulation takes the die face as
//! shells, mostly quads).
//!
//! The writers take an [`FeModel`]: plain data (nodes, parts of shells, draw bead lines),
//! never a language value, in millimetres and press coordinates (+Z up, the stroke's
//! direction). Whoever meshes the die face fills it; [`FeModel::check`] says whether the
//! writers can put it in a deck that means what it says.
//!
//! * [`lsdyna`]: an LS-DYNA keyword deck (`.k`): parts, shell sections, a rigid steel
//!   material, nodes, shells, and each draw bead as a node set with a
//!   `*CONTACT_DRAWBEAD` and its restraining force curve.
//! * [`nastran`]: Nastran bulk data (`.bdf`): `PSHELL`, `MAT1`, `GRID*`, `CQUAD4` and
//!   `CTRIA3`; the draw beads as comments (Nastran has no draw bead card).
//!
//! Numbering is the same in both decks, so a result read from one can be found in the
//! other: node `i` of [`FeModel::nodes`] is node id `i + 1`; elements are numbered from
//! 1 through all parts in part order, each part's shells in their order; part `k` is
//! part (and property) id `k + 1`, and its section id is its part id; bead `b` is node
//! set (and curve) id `b + 1`. Units are consistent for an explicit forming solver:
//! mm, tonne, s, N, MPa.
//!
//! Both writers are deterministic (fixed-width, fixed-decimal numbers, `\n` line ends)
//! and never panic: on a model [`FeModel::check`] refuses they still write what they
//! were given, which the solver will then refuse.

pub mod from_model;
pub mod lsdyna;
pub mod nastran;

use glam::DVec3;

pub use lsdyna::encode_lsdyna;
pub use nastran::encode_nastran;

/// Density of the placeholder tool steel (t/mm^3): the die face is a rigid tool, whose
/// mass only sets the contact stiffness scale, so generic steel is right for every part.
pub const STEEL_DENSITY: f64 = 7.85e-9;

/// Young's modulus of the placeholder tool steel (MPa).
pub const STEEL_YOUNGS_MODULUS: f64 = 2.1e5;

/// Poisson's ratio of the placeholder tool steel.
pub const STEEL_POISSON_RATIO: f64 = 0.3;

/// The material id every part uses: the one steel material both decks define.
pub const MATERIAL_ID: u64 = 1;

/// The most nodes or elements a deck may number: ids are written in eight-character
/// fields (LS-DYNA's standard format, Nastran's small fields), so nine digits do not fit.
pub const MAX_ID: usize = 99_999_999;

/// A die face ready for a shell-element deck: nodes shared by every part, the parts'
/// shells, and the draw bead lines. Millimetres, press coordinates (+Z up).
#[derive(Debug, Clone, PartialEq)]
pub struct FeModel {
    /// The deck's title (the LS-DYNA `*TITLE`, the first Nastran comment): which die.
    pub title: String,
    /// Every node's position (mm); a node's index is what shells and beads name.
    pub nodes: Vec<DVec3>,
    /// The tool parts (die face, binder, punch...), each one part and section in a deck.
    pub parts: Vec<FePart>,
    /// The draw beads, each a line of nodes with its restraining force.
    pub beads: Vec<FeBead>,
}

/// One tool part: its shells and the section they share.
#[derive(Debug, Clone, PartialEq)]
pub struct FePart {
    /// The part's name, the LS-DYNA part heading and a comment in Nastran, so the
    /// forming engineer sees which piece of the die it is.
    pub name: String,
    /// What the part is (the die model's kind: `step_draw`, `blankholder`...), written
    /// beside its name.
    pub kind: String,
    /// Shell thickness (mm). A rigid tool's thickness only places its contact surface.
    pub thickness: f64,
    /// The part's elements.
    pub shells: Vec<Shell>,
}

/// A shell element: 0-based indices into [`FeModel::nodes`], counter-clockwise seen from
/// the +Z side of the die face, so its normal (right-hand rule) points up, towards the
/// sheet on a lower tool.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Shell {
    /// A four-node shell.
    Quad([u32; 4]),
    /// A three-node shell (where a quad mesh could not close, or a triangle mesh).
    Triangle([u32; 3]),
}

impl Shell {
    /// The shell's node indices, in order.
    pub fn nodes(&self) -> &[u32] {
        match self {
            Shell::Quad(n) => n,
            Shell::Triangle(n) => n,
        }
    }
}

/// A draw bead as a forming solver takes it: a line of nodes along the bead's centre
/// and the force per unit length the bead holds the sheet back with.
#[derive(Debug, Clone, PartialEq)]
pub struct FeBead {
    /// The bead's name, written with its node set and contact.
    pub name: String,
    /// 0-based indices into [`FeModel::nodes`], in order along the bead's line.
    pub nodes: Vec<u32>,
    /// Restraining force per unit bead length (N/mm), if the design gives one.
    pub force: Option<f64>,
    /// The bead's depth (mm): its height above the binder (LS-DYNA's DBDTH).
    pub depth: f64,
}

/// Why a model cannot be written as a deck that means what it says.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum FeError {
    /// A node's position is not a finite point.
    #[error("node {node} is not a finite point")]
    NotFinite { node: usize },
    /// A part has no shells (a part and section the solver would reject as empty).
    #[error("part {part} `{name}` has no shells")]
    EmptyPart { part: usize, name: String },
    /// A part's thickness is not a positive finite length.
    #[error("part {part} `{name}` has thickness {thickness}; it must be a positive length")]
    Thickness {
        part: usize,
        name: String,
        thickness: f64,
    },
    /// A shell names a node index past the end of the nodes.
    #[error("shell {shell} of part {part} names node {node}, but there are {nodes} nodes")]
    ShellNode {
        part: usize,
        shell: usize,
        node: u32,
        nodes: usize,
    },
    /// A shell names one node twice (a collapsed element).
    #[error("shell {shell} of part {part} names node {node} twice")]
    RepeatedNode {
        part: usize,
        shell: usize,
        node: u32,
    },
    /// A bead names a node index past the end of the nodes.
    #[error("bead {bead} `{name}` names node {node}, but there are {nodes} nodes")]
    BeadNode {
        bead: usize,
        name: String,
        node: u32,
        nodes: usize,
    },
    /// A bead has fewer than two nodes: no line for the solver to lay it along.
    #[error("bead {bead} `{name}` has {count} nodes; a bead line needs at least two")]
    ShortBead {
        bead: usize,
        name: String,
        count: usize,
    },
    /// A bead's force is not a finite number.
    #[error("bead {bead} `{name}` has force {force}; it must be a finite number")]
    Force {
        bead: usize,
        name: String,
        force: f64,
    },
    /// More nodes or elements than the decks' eight-digit id fields can number.
    #[error("{count} {what} are more than the {limit} an eight-digit id field can number")]
    TooMany {
        what: &'static str,
        count: usize,
        limit: usize,
    },
}

impl FeModel {
    /// Checks that the decks will mean what the model says: every node finite, every
    /// part with shells and a positive thickness, every shell's and bead's node index
    /// in range, no shell naming a node twice, every bead a line of at least two nodes
    /// with a finite force, and ids that fit their fields. The first problem found is
    /// returned (indices 0-based, as in the model).
    pub fn check(&self) -> Result<(), FeError> {
        let elements: usize = self.parts.iter().map(|p| p.shells.len()).sum();
        for (what, count) in [("nodes", self.nodes.len()), ("elements", elements)] {
            if count > MAX_ID {
                return Err(FeError::TooMany {
                    what,
                    count,
                    limit: MAX_ID,
                });
            }
        }
        if let Some(node) = self.nodes.iter().position(|p| !p.is_finite()) {
            return Err(FeError::NotFinite { node });
        }
        for (part, p) in self.parts.iter().enumerate() {
            self.check_part(part, p)?;
        }
        for (bead, b) in self.beads.iter().enumerate() {
            self.check_bead(bead, b)?;
        }
        Ok(())
    }

    /// [`FeModel::check`] for one part.
    fn check_part(&self, part: usize, p: &FePart) -> Result<(), FeError> {
        if p.shells.is_empty() {
            return Err(FeError::EmptyPart {
                part,
                name: p.name.clone(),
            });
        }
        if !(p.thickness.is_finite() && p.thickness > 0.0) {
            return Err(FeError::Thickness {
                part,
                name: p.name.clone(),
                thickness: p.thickness,
            });
        }
        for (shell, s) in p.shells.iter().enumerate() {
            let nodes = s.nodes();
            if let Some(&node) = nodes.iter().find(|&&n| n as usize >= self.nodes.len()) {
                return Err(FeError::ShellNode {
                    part,
                    shell,
                    node,
                    nodes: self.nodes.len(),
                });
            }
            let repeated = nodes
                .iter()
                .enumerate()
                .find(|&(i, n)| nodes[..i].contains(n));
            if let Some((_, &node)) = repeated {
                return Err(FeError::RepeatedNode { part, shell, node });
            }
        }
        Ok(())
    }

    /// [`FeModel::check`] for one bead.
    fn check_bead(&self, bead: usize, b: &FeBead) -> Result<(), FeError> {
        if let Some(&node) = b.nodes.iter().find(|&&n| n as usize >= self.nodes.len()) {
            return Err(FeError::BeadNode {
                bead,
                name: b.name.clone(),
                node,
                nodes: self.nodes.len(),
            });
        }
        if b.nodes.len() < 2 {
            return Err(FeError::ShortBead {
                bead,
                name: b.name.clone(),
                count: b.nodes.len(),
            });
        }
        match b.force {
            Some(force) if !force.is_finite() => Err(FeError::Force {
                bead,
                name: b.name.clone(),
                force,
            }),
            _ => Ok(()),
        }
    }
}

/// The deck id of the node at `index` (1-based; `u64` so the last `u32` index has one).
fn node_id(index: u32) -> u64 {
    u64::from(index) + 1
}

/// The deck id of the part (its section and property) at `index` (1-based).
fn part_id(index: usize) -> u64 {
    index as u64 + 1
}

/// Every shell with its element id and its part's id, in deck order: elements numbered
/// from 1 through all parts in part order.
fn numbered_shells(model: &FeModel) -> impl Iterator<Item = (u64, u64, &Shell)> {
    model
        .parts
        .iter()
        .enumerate()
        .flat_map(|(k, p)| p.shells.iter().map(move |s| (part_id(k), s)))
        .zip(1u64..)
        .map(|((pid, s), eid)| (eid, pid, s))
}

/// A `$` comment line of at most 80 characters (both decks take `$` as a comment).
fn comment(out: &mut String, text: &str) {
    use std::fmt::Write;
    let _ = writeln!(out, "$ {}", plain_line(text, 78));
}

/// `text` as one line of plain ASCII at most `max` characters long, safe in a heading
/// or a comment: control characters (a line break would end the card) become spaces,
/// other non-ASCII characters `_` (fixed columns count bytes), and a leading `*` or `$`
/// (a keyword or a comment to LS-DYNA) gets a space before it.
fn plain_line(text: &str, max: usize) -> String {
    let mut line: String = text
        .chars()
        .map(|c| match c {
            c if c.is_control() => ' ',
            c if c.is_ascii() => c,
            _ => '_',
        })
        .collect();
    if line.starts_with(['*', '$']) {
        line.insert(0, ' ');
    }
    line.chars().take(max).collect()
}

/// `value` right-aligned in a field of `width` characters, with one leading space kept
/// so free-format readers also see the fields apart: fixed `decimals` where that fits
/// (fewer where it does not), else scientific notation with as many digits as fit.
/// Negative zero is written as zero; the decimal point is always there (Nastran reads a
/// number without one as an integer).
fn real(value: f64, width: usize, decimals: usize) -> String {
    let room = width.saturating_sub(1);
    let value = if value == 0.0 { 0.0 } else { value };
    let fixed = (0..=decimals)
        .rev()
        .map(|d| format!("{value:.d$}"))
        .map(|s| if s.contains('.') { s } else { s + "." })
        .find(|s| s.len() <= room && !is_rounded_away(s, value));
    let text = fixed.unwrap_or_else(|| scientific(value, room));
    format!("{text:>width$}")
}

/// [`real`] written onto the end of `out`, the same characters, without the two
/// strings `real` makes: the common case (the value fits its field with all
/// `decimals`, which is [`real`]'s first choice) formatted in a buffer on the stack,
/// anything else left to [`real`].
fn push_real(out: &mut String, value: f64, width: usize, decimals: usize) {
    let value = if value == 0.0 { 0.0 } else { value };
    let mut text = StackText::default();
    let fits = fixed_by_integers(&mut text, value, decimals)
        || std::fmt::Write::write_fmt(&mut text, format_args!("{value:.decimals$}")).is_ok();
    let text = text.as_str();
    // `real` adds a point where there is none (no decimals), and looks further when
    // the text is too long or reads back as zero: left to it.
    if fits && text.contains('.') && text.len() < width && !is_rounded_away(text, value) {
        out.extend(std::iter::repeat_n(' ', width - text.len()));
        out.push_str(text);
    } else {
        out.push_str(&real(value, width, decimals));
    }
}

/// `10^d` for the decimals [`fixed_by_integers`] writes.
const POWERS_OF_TEN: [f64; 10] = [1.0, 1e1, 1e2, 1e3, 1e4, 1e5, 1e6, 1e7, 1e8, 1e9];

/// Writes into the empty `text` what `format!("{value:.decimals$}")` writes, by
/// integer arithmetic, and returns true; or writes nothing and returns false where
/// that is not certain to give the same characters, for the standard formatter to do.
///
/// The standard formatter rounds the value's exact decimal expansion, which is slow
/// (a third of a 13.9 MB deck's writing). `|value| 10^decimals` computed in floating
/// point lies within half a unit in its last place of the exact product, so its
/// nearest whole number is the exact one unless its fraction is that close to one
/// half (a tie such as 1/128 to six decimals, or a near one): those, values whose
/// product passes 10^15 (whole numbers no longer exact), and values that round to
/// zero (whose sign the formatter keeps) are left to the formatter.
fn fixed_by_integers(text: &mut StackText, value: f64, decimals: usize) -> bool {
    let Some(&scale) = POWERS_OF_TEN.get(decimals) else {
        return false;
    };
    let scaled = value.abs() * scale;
    // NaN is not below either.
    if scaled.is_nan() || scaled >= 1e15 {
        return false;
    }
    let whole = scaled.floor();
    let fraction = scaled - whole;
    if (fraction - 0.5).abs() <= scaled * f64::EPSILON {
        return false;
    }
    // Below 10^15: a whole number the cast keeps exactly.
    let rounded = whole as u64 + u64::from(fraction > 0.5);
    if rounded == 0 {
        return false;
    }
    let unit = 10u64.pow(decimals as u32);
    // Filled from the end: the decimals, the point, the whole part, the sign.
    let mut digits = [0u8; 24];
    let mut at = digits.len();
    let (int, mut frac) = (rounded / unit, rounded % unit);
    for _ in 0..decimals {
        at -= 1;
        digits[at] = b'0' + (frac % 10) as u8;
        frac /= 10;
    }
    if decimals > 0 {
        at -= 1;
        digits[at] = b'.';
    }
    at = put_digits(&mut digits, at, int);
    if value < 0.0 {
        at -= 1;
        digits[at] = b'-';
    }
    // ASCII digits, a point and a sign: UTF-8, and at most 24 bytes.
    let written = std::str::from_utf8(&digits[at..]).unwrap_or("");
    std::fmt::Write::write_str(text, written).is_ok()
}

/// `value` right-aligned in a field of `width` characters, as `format!("{value:>width$}")`
/// writes it (a wider number is written whole), without the formatter.
fn push_int(out: &mut String, value: u64, width: usize) {
    let mut digits = [0u8; 20];
    let at = put_digits(&mut digits, 20, value);
    let len = digits.len() - at;
    out.extend(std::iter::repeat_n(' ', width.saturating_sub(len)));
    // ASCII digits: UTF-8.
    out.push_str(std::str::from_utf8(&digits[at..]).unwrap_or(""));
}

/// Writes the decimal digits of `value` into `digits` to end before `end` (room for
/// 20, `u64`'s most), and returns where they start.
fn put_digits(digits: &mut [u8], end: usize, value: u64) -> usize {
    let (mut at, mut rest) = (end, value);
    loop {
        at -= 1;
        digits[at] = b'0' + (rest % 10) as u8;
        rest /= 10;
        if rest == 0 {
            return at;
        }
    }
}

/// A short text formatted on the stack ([`push_real`]); writing more than it holds is
/// an error.
struct StackText {
    bytes: [u8; 40],
    len: usize,
}

impl Default for StackText {
    fn default() -> Self {
        StackText {
            bytes: [0; 40],
            len: 0,
        }
    }
}

impl StackText {
    /// What was written.
    fn as_str(&self) -> &str {
        // Only whole `&str`s are ever copied in, so the bytes are UTF-8.
        std::str::from_utf8(&self.bytes[..self.len]).unwrap_or("")
    }
}

impl std::fmt::Write for StackText {
    fn write_str(&mut self, s: &str) -> std::fmt::Result {
        let end = self.len + s.len();
        let slot = self.bytes.get_mut(self.len..end).ok_or(std::fmt::Error)?;
        slot.copy_from_slice(s.as_bytes());
        self.len = end;
        Ok(())
    }
}

/// Whether a fixed-decimal `text` lost all of a non-zero `value` (a tiny value written
/// with too few decimals reads back as zero): then scientific notation keeps it.
fn is_rounded_away(text: &str, value: f64) -> bool {
    value != 0.0
        && text
            .trim_start_matches('-')
            .chars()
            .all(|c| c == '0' || c == '.')
}

/// `value` in scientific notation (`1.234567E9`) in at most `room` characters, as many
/// mantissa digits as fit (at least one, trailing zeros left out), always with a
/// decimal point (`8.E-9`).
fn scientific(value: f64, room: usize) -> String {
    let with_point = |s: String| match s.split_once('E') {
        Some((mantissa, exponent)) if mantissa.contains('.') => {
            format!("{}E{exponent}", mantissa.trim_end_matches('0'))
        }
        Some((mantissa, exponent)) => format!("{mantissa}.E{exponent}"),
        None => s,
    };
    (0..=15)
        .rev()
        .map(|d| with_point(format!("{value:.d$E}")))
        .find(|s| s.len() <= room)
        .unwrap_or_else(|| with_point(format!("{value:.0E}")))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A one-quad model over the unit square, with one bead.
    pub(super) fn one_quad() -> FeModel {
        FeModel {
            title: "one quad".into(),
            nodes: vec![
                DVec3::new(0.0, 0.0, 0.0),
                DVec3::new(1.0, 0.0, 0.0),
                DVec3::new(1.0, 1.0, 0.0),
                DVec3::new(0.0, 1.0, 0.0),
            ],
            parts: vec![FePart {
                name: "binder".into(),
                kind: "blankholder".into(),
                thickness: 1.0,
                shells: vec![Shell::Quad([0, 1, 2, 3])],
            }],
            beads: vec![FeBead {
                name: "bead".into(),
                nodes: vec![0, 1],
                force: Some(150.0),
                depth: 6.0,
            }],
        }
    }

    #[test]
    fn a_sound_model_passes() {
        assert_eq!(one_quad().check(), Ok(()));
    }

    #[test]
    fn a_node_past_the_end_is_refused() {
        let mut m = one_quad();
        m.parts[0].shells[0] = Shell::Quad([0, 1, 2, 4]);
        assert_eq!(
            m.check(),
            Err(FeError::ShellNode {
                part: 0,
                shell: 0,
                node: 4,
                nodes: 4
            })
        );
        let mut m = one_quad();
        m.beads[0].nodes = vec![0, 7];
        assert!(matches!(m.check(), Err(FeError::BeadNode { node: 7, .. })));
    }

    #[test]
    fn a_point_not_finite_is_refused() {
        let mut m = one_quad();
        m.nodes[2].y = f64::NAN;
        assert_eq!(m.check(), Err(FeError::NotFinite { node: 2 }));
        m.nodes[2].y = f64::INFINITY;
        assert_eq!(m.check(), Err(FeError::NotFinite { node: 2 }));
    }

    #[test]
    fn a_part_without_shells_is_refused() {
        let mut m = one_quad();
        m.parts[0].shells.clear();
        assert_eq!(
            m.check(),
            Err(FeError::EmptyPart {
                part: 0,
                name: "binder".into()
            })
        );
    }

    #[test]
    fn a_shell_naming_a_node_twice_is_refused() {
        let mut m = one_quad();
        m.parts[0].shells.push(Shell::Triangle([1, 2, 1]));
        assert_eq!(
            m.check(),
            Err(FeError::RepeatedNode {
                part: 0,
                shell: 1,
                node: 1
            })
        );
    }

    #[test]
    fn bad_thickness_short_beads_and_bad_forces_are_refused() {
        for t in [0.0, -1.0, f64::NAN] {
            let mut m = one_quad();
            m.parts[0].thickness = t;
            assert!(matches!(m.check(), Err(FeError::Thickness { .. })), "{t}");
        }
        let mut m = one_quad();
        m.beads[0].nodes.truncate(1);
        assert!(matches!(
            m.check(),
            Err(FeError::ShortBead { count: 1, .. })
        ));
        let mut m = one_quad();
        m.beads[0].force = Some(f64::NAN);
        assert!(matches!(m.check(), Err(FeError::Force { .. })));
        m.beads[0].force = None;
        assert_eq!(m.check(), Ok(()));
    }

    #[test]
    fn errors_read_as_sentences() {
        let e = FeError::ShellNode {
            part: 1,
            shell: 3,
            node: 9,
            nodes: 9,
        };
        assert_eq!(
            e.to_string(),
            "shell 3 of part 1 names node 9, but there are 9 nodes"
        );
    }

    #[test]
    fn shells_are_numbered_through_the_parts() {
        let mut m = one_quad();
        m.parts.push(FePart {
            name: "die".into(),
            kind: "step_draw".into(),
            thickness: 2.0,
            shells: vec![Shell::Triangle([0, 1, 2]), Shell::Triangle([0, 2, 3])],
        });
        let ids: Vec<(u64, u64)> = numbered_shells(&m).map(|(e, p, _)| (e, p)).collect();
        assert_eq!(ids, [(1, 1), (2, 2), (3, 2)]);
        assert_eq!(node_id(u32::MAX), 4_294_967_296);
    }

    #[test]
    fn reals_fit_their_fields_and_keep_their_digits() {
        assert_eq!(real(1234.567891, 16, 6), "     1234.567891");
        assert_eq!(real(-0.000123, 16, 6), "       -0.000123");
        assert_eq!(real(-0.0, 16, 6), "        0.000000");
        assert_eq!(real(-999_999.999_999, 16, 6), "  -999999.999999");
        // Too wide for six decimals: fewer.
        assert_eq!(real(123_456_789.25, 16, 6), " 123456789.25000");
        // Too wide for any fixed form: scientific.
        assert_eq!(real(1.5e30, 16, 6), "          1.5E30");
        assert_eq!(real(-7.123456789e-12, 8, 6), " -7.E-12");
        assert_eq!(real(1.2, 8, 6), " 1.20000");
        assert_eq!(real(7.85e-9, 8, 6), " 7.85E-9");
        assert_eq!(real(1.0, 8, 0), "      1.");
        for v in [1.0, -3.25, 1e-9, 4.4e20, -7.123456789e-12] {
            for w in [8usize, 10, 16, 20] {
                let s = real(v, w, 6);
                assert_eq!(s.len(), w, "{v} in {w}: {s:?}");
                assert!(s.starts_with(' '), "{v} in {w}: {s:?}");
                let back: f64 = s.trim().parse().expect("a number");
                // Eight characters hold two digits of a negative tiny value.
                let tol = if w == 8 { 0.05 } else { 1e-3 };
                assert!((back - v).abs() <= tol * v.abs(), "{v} in {w}: {s:?}");
            }
        }
    }

    #[test]
    fn reals_by_integers_are_what_the_formatter_writes() {
        // Ties (k/128 to six decimals), near ties, the ends of the fast range, signs,
        // tiny values and a spread of coordinates.
        let mut values = vec![
            1.0 / 128.0,
            -3.0 / 128.0,
            0.5,
            2.5,
            0.0000005,
            0.0000015,
            1e-7,
            -1e-7,
            999_999_999.999_999_5,
            1e9,
            123_456_789.25,
            0.1 + 0.2,
            f64::NAN,
            f64::INFINITY,
        ];
        let mut x: u64 = 0x9e37_79b9_7f4a_7c15;
        for k in 0..200_000 {
            x ^= x << 13;
            x ^= x >> 7;
            x ^= x << 17;
            let unit = (x >> 11) as f64 / (1u64 << 53) as f64;
            let magnitude = 10f64.powi(k % 14 - 4);
            values.push((unit - 0.5) * magnitude);
            values.push(((unit - 0.5) * 2e6).round() / 1e6 + 5e-7);
        }
        for &v in &values {
            for decimals in [0usize, 1, 5, 6, 9] {
                let mut text = StackText::default();
                if fixed_by_integers(&mut text, v, decimals) {
                    assert_eq!(
                        text.as_str(),
                        format!("{v:.decimals$}"),
                        "{v:e}, {decimals}"
                    );
                }
            }
        }
        for (v, w) in [
            (0u64, 8usize),
            (7, 8),
            (12_345_678, 8),
            (123_456_789, 8),
            (42, 0),
        ] {
            let mut out = String::new();
            push_int(&mut out, v, w);
            assert_eq!(out, format!("{v:>w$}"));
        }
    }

    #[test]
    fn headings_stay_one_plain_line() {
        assert_eq!(plain_line("die\nface é", 80), "die face _");
        assert_eq!(plain_line("*END", 80), " *END");
        assert_eq!(plain_line("$x", 80), " $x");
        assert_eq!(plain_line("abcdef", 3), "abc");
    }
}
