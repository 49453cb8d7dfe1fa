//! The budget of one evaluation: the limits in force (`--limit`, [`crate::limits`]) and
//! what the evaluation has used of those that count over a whole build (evaluation
//! steps, list items).
//!
//! The counters are atomic because the declarations of a wave, and the pieces of a
//! feature, are evaluated side by side; each check is one relaxed addition. A check
//! that fails gives the diagnostic of [`exceeded`], at the expression that reached the
//! limit.

use std::sync::atomic::{AtomicBool, AtomicU64, Ordering};

use crate::diag::Diagnostic;
use crate::limits::{Limit, Limits};
use crate::syntax::Span;

/// The limits of one evaluation and what it has used so far.
#[derive(Debug, Default)]
pub struct Budget {
    limits: Limits,
    /// Expressions evaluated and functions called.
    steps: AtomicU64,
    /// Items of every list made.
    items: AtomicU64,
    /// Whether a declaration has already been stopped for running out of steps: the
    /// others that run out after it are not reported again.
    out_of_work: AtomicBool,
}

/// Every how many evaluation steps the heap is looked at: a step makes at most a few
/// small values (lists and strings are bounded on their own), so the heap cannot
/// outrun the check by much, and the look costs nothing measurable.
const MEMORY_CHECK_STEPS: u64 = 1024;

impl Budget {
    /// A fresh budget under `limits`.
    pub fn new(limits: Limits) -> Self {
        Budget {
            limits,
            ..Budget::default()
        }
    }

    /// The limits in force.
    pub fn limits(&self) -> &Limits {
        &self.limits
    }

    /// Counts one evaluation step: the limit passed once the `work` limit is, or once
    /// the heap the process holds passes `memory_mb` (looked at every
    /// [`MEMORY_CHECK_STEPS`] steps).
    pub fn step(&self) -> Result<(), Limit> {
        let done = self.steps.fetch_add(1, Ordering::Relaxed);
        if done >= self.limits.get(Limit::Work) {
            return Err(Limit::Work);
        }
        if done % MEMORY_CHECK_STEPS == 0 && !self.memory_ok() {
            return Err(Limit::MemoryMb);
        }
        Ok(())
    }

    /// Whether the heap the process holds is within the `memory_mb` limit.
    pub fn memory_ok(&self) -> bool {
        let held = u64::try_from(crate::heap::live_bytes()).unwrap_or(u64::MAX);
        held <= self.limits.get(Limit::MemoryMb).saturating_mul(1 << 20)
    }

    /// Counts the items of a list just made; `false` once all lists of the
    /// evaluation together pass the `list_items` limit.
    pub fn add_items(&self, n: usize) -> bool {
        let n = u64::try_from(n).unwrap_or(u64::MAX);
        let before = self.items.fetch_add(n, Ordering::Relaxed);
        before.saturating_add(n) <= self.limits.get(Limit::ListItems)
    }

    /// Whether `n` things fit under `limit` (a per-list, per-string or per-call limit),
    /// asked before they are made.
    pub fn allows(&self, limit: Limit, n: u64) -> bool {
        n <= self.limits.get(limit)
    }

    /// Notes that a declaration ran out of steps; whether it is the first to (the
    /// only one reported).
    pub fn first_out_of_work(&self) -> bool {
        !self.out_of_work.swap(true, Ordering::Relaxed)
    }
}

/// The diagnostic for an expression at `span` that reached `limit`: `message` says
/// what was asked, the label names the limit, the help gives its value and the switch
/// that raises it.
pub fn exceeded(limit: Limit, limits: &Limits, span: Span, message: String) -> Diagnostic {
    Diagnostic::new(
        limit_code(limit),
        message,
        span,
        format!("reaches the `{}` limit", limit.name()),
    )
    .with_help(limit.help(limits))
}

/// The diagnostic code of a limit reached during evaluation (`die::limit::work`).
pub fn limit_code(limit: Limit) -> &'static str {
    match limit {
        Limit::Nesting => "die::limit::nesting",
        Limit::CallDepth => "die::limit::call_depth",
        Limit::Work => "die::limit::work",
        Limit::ListItems => "die::limit::list_items",
        Limit::StringBytes => "die::limit::string_bytes",
        Limit::Samples => "die::limit::samples",
        Limit::MeshVertices => "die::limit::mesh_vertices",
        Limit::FileBytes => "die::limit::file_bytes",
        Limit::MemoryMb => "die::limit::memory_mb",
    }
}
