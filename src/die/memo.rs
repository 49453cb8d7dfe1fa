//! Pieces of features kept between builds, by their inputs: so an edit re-runs only the
//! pieces whose inputs changed (one side of a punch opening when its binder wrap is
//! edited, not the other three).
//!
//! The engine owns one [`PieceMemo`] for its lifetime (what `watch` keeps) and hands
//! each feature a [`Pieces`] handle named after the declaration that builds (an owner
//! name unique in the engine: its file and its name). A piece is
//! found by a 64-bit fingerprint of its inputs and reused only when the kept inputs are
//! equal to the new ones, so a collision rebuilds and never returns a wrong piece. The
//! pieces are pure functions of their inputs, so a reused piece is the very value a
//! rebuild would make, and outputs stay byte-identical.
//!
//! After a build, the pieces that a declaration which ran did not use are dropped
//! ([`PieceMemo::finish`]); a declaration that did not run keeps its pieces for the next
//! edit that touches it.

use std::any::Any;
use std::collections::{HashMap, HashSet};
use std::sync::{Arc, Mutex};

/// The pieces kept, by owner (declaration), kind of piece and input fingerprint.
#[derive(Default)]
pub struct PieceMemo {
    state: Mutex<State>,
}

#[derive(Default)]
struct State {
    entries: HashMap<(String, &'static str, u64), Entry>,
    /// The owners that built in this build (asked for a handle).
    ran: HashSet<String>,
    built: usize,
    reused: usize,
}

struct Entry {
    inputs: Arc<dyn Any + Send + Sync>,
    value: Arc<dyn Any + Send + Sync>,
    used: bool,
}

impl PieceMemo {
    /// Starts a build: nothing is marked used, the counters start at zero.
    pub fn begin(&self) {
        let mut s = self.lock();
        for e in s.entries.values_mut() {
            e.used = false;
        }
        s.ran.clear();
        s.built = 0;
        s.reused = 0;
    }

    /// Ends a build: the pieces of the owners that built in it but did not use them
    /// are dropped (their inputs changed); owners that did not build keep theirs.
    pub fn finish(&self) {
        let mut s = self.lock();
        let State { entries, ran, .. } = &mut *s;
        entries.retain(|(owner, _, _), e| e.used || !ran.contains(owner));
    }

    /// How many pieces the last build made, and how many it reused.
    pub fn counts(&self) -> (usize, usize) {
        let s = self.lock();
        (s.built, s.reused)
    }

    /// The handle a declaration's feature builds its pieces through; `owner` names
    /// the declaration uniquely in the engine, and counts as having built.
    pub fn for_owner(&self, owner: String) -> Pieces<'_> {
        self.lock().ran.insert(owner.clone());
        Pieces {
            memo: Some(self),
            owner,
        }
    }

    fn lock(&self) -> std::sync::MutexGuard<'_, State> {
        // A panic while the lock is held cannot leave an entry half-written (each
        // update is one insert or flag), so a poisoned lock is still consistent.
        self.state.lock().unwrap_or_else(|p| p.into_inner())
    }
}

/// A feature's access to the memo: its pieces are kept under its declaration's name.
#[derive(Clone)]
pub struct Pieces<'a> {
    memo: Option<&'a PieceMemo>,
    owner: String,
}

impl Pieces<'_> {
    /// No memo: every piece is built (a feature built outside an engine, in a test).
    pub fn none() -> Pieces<'static> {
        Pieces {
            memo: None,
            owner: String::new(),
        }
    }

    /// The piece `what` for `inputs` (whose fingerprint is `key`): the kept one when the
    /// same inputs built it before, else `build`'s, kept when it succeeds.
    pub fn piece<K, V, E>(
        &self,
        what: &'static str,
        key: u64,
        inputs: &K,
        build: impl FnOnce() -> Result<V, E>,
    ) -> Result<V, E>
    where
        K: PartialEq + Clone + Send + Sync + 'static,
        V: Clone + Send + Sync + 'static,
    {
        let Some(memo) = self.memo else {
            return build();
        };
        let id = (self.owner.clone(), what, key);
        {
            let mut s = memo.lock();
            let found = s.entries.get_mut(&id).and_then(|e| {
                let same = e.inputs.downcast_ref::<K>() == Some(inputs);
                let value = e.value.downcast_ref::<V>().cloned();
                e.used |= same && value.is_some();
                value.filter(|_| same)
            });
            if let Some(v) = found {
                s.reused += 1;
                return Ok(v);
            }
        }
        let value = build()?;
        let mut s = memo.lock();
        s.built += 1;
        s.entries.insert(
            id,
            Entry {
                inputs: Arc::new(inputs.clone()),
                value: Arc::new(value.clone()),
                used: true,
            },
        );
        Ok(value)
    }
}
