//! A feature's problems told as data, and one way of turning them into diagnostics.
//!
//! The kernel features of [`crate::die`] report what went wrong as plain values (a side
//! that folds, a section out of order, with the piece's index), knowing nothing of the
//! language. Each feature kind says, per problem, what a designer reads and which of
//! its inputs is to blame as an [`Explanation`]: the message, the help, and a
//! [`Blame`] per label, a path into the block (`Field("taper")`, a side's station, a
//! section's profile) rather than a place in the source. [`diagnostic`] then does what
//! every kind did by hand: it finds where each blamed input was written, falls back to
//! the block's head, drops labels whose input was not written or that repeat a place,
//! and adds the kind's code and the help. A kind supplies only how its own parts of
//! the block map to places, one short `resolve` function.

use crate::diag::Diagnostic;
use crate::syntax::Span;

use super::kind::FeatureKind;
use super::Block;

/// An input of a feature block a problem is blamed on: a path into the block, which
/// [`diagnostic`] resolves to where it was written.
#[derive(Debug, Clone, PartialEq)]
pub enum Blame<P> {
    /// The block as a whole: its head, the kind word.
    Block,
    /// The value of a one-word field (`taper = 30 mm`), when it was written.
    Field(&'static str),
    /// A part of the block only its kind knows how to find: a side's station, a key
    /// section's profile, a top-view segment.
    Part(P),
}

/// What a designer reads about one problem, with the inputs it blames.
#[derive(Debug, Clone)]
pub struct Explanation<P> {
    /// One sentence saying what is wrong.
    pub message: String,
    /// The inputs to point at, in order of preference, each with its label: the first
    /// one that was written is the primary label; the block's head when none was.
    pub blame: Vec<(Blame<P>, String)>,
    /// Other inputs that matter, each with its label; those not written, or written
    /// where another label already points, are left out.
    pub also: Vec<(Blame<P>, String)>,
    /// How to fix it.
    pub help: String,
}

/// A kind's own part is blamed as `Blame::Part`.
impl<P> From<P> for Blame<P> {
    fn from(part: P) -> Self {
        Blame::Part(part)
    }
}

impl<P> Explanation<P> {
    /// A problem blamed on `input`, labelled `label`.
    pub fn new(
        message: impl Into<String>,
        input: impl Into<Blame<P>>,
        label: impl Into<String>,
        help: impl Into<String>,
    ) -> Self {
        Explanation {
            message: message.into(),
            blame: vec![(input.into(), label.into())],
            also: Vec::new(),
            help: help.into(),
        }
    }

    /// Blames `input` (with the same label) when the inputs blamed so far were not written.
    pub fn or(mut self, input: impl Into<Blame<P>>) -> Self {
        let label = self.blame.last().map_or(String::new(), |(_, l)| l.clone());
        self.blame.push((input.into(), label));
        self
    }

    /// Blames `input` with its own label when the inputs blamed so far were not written.
    pub fn or_labelled(mut self, input: impl Into<Blame<P>>, label: impl Into<String>) -> Self {
        self.blame.push((input.into(), label.into()));
        self
    }

    /// Adds a secondary label at `input`, when it was written.
    pub fn also(mut self, input: impl Into<Blame<P>>, label: impl Into<String>) -> Self {
        self.also.push((input.into(), label.into()));
        self
    }
}

/// The diagnostic of `explanation` for a block of `kind`: each blamed input resolved
/// to where it was written (the kind's own parts by `part`), the primary label at the
/// first written one or the block's head, secondary labels at written places not yet
/// labelled, the kind's code and the help.
pub fn diagnostic<P>(
    kind: &dyn FeatureKind,
    block: &Block,
    explanation: Explanation<P>,
    part: impl Fn(&P) -> Option<Span>,
) -> Diagnostic {
    let resolve = |input: &Blame<P>| match input {
        Blame::Block => Some(block.head()),
        Blame::Field(name) => block.get(name).map(|f| f.value.span),
        Blame::Part(p) => part(p),
    };
    let Explanation {
        message,
        blame,
        also,
        help,
    } = explanation;
    let (primary, label) = blame
        .iter()
        .find_map(|(input, label)| Some((resolve(input)?, label.clone())))
        .unwrap_or_else(|| {
            let label = blame.first().map_or(String::new(), |(_, l)| l.clone());
            (block.head(), label)
        });
    let mut seen = vec![primary];
    let mut d = Diagnostic::new(kind.code(), message, primary, label);
    for (input, label) in also {
        let Some(span) = resolve(&input) else {
            continue;
        };
        if !seen.contains(&span) {
            seen.push(span);
            d = d.with_label(span, label);
        }
    }
    d.with_help(help)
}
