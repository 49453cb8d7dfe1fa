//! Where a file's top-level items stand, and memoized values moved with them.
//!
//! A memoized value remembers spans in the file as it was when the value was computed.
//! When lines are added above a declaration, its value is taken from the memo and its
//! spans are moved by how far the item they fall in moved. One [`Layout`] is made per
//! evaluation of a file and shared (behind an `Arc`) by every memo entry that evaluation
//! makes, so the memo grows with the number of declarations, not with its square; a
//! span finds its item by binary search.

use std::collections::HashMap;
use std::sync::Arc;

use crate::syntax::{FileId, Span};

use super::value::{Data, Record, Value};

/// Where each top-level declaration and function of one file stands.
#[derive(Debug, PartialEq, Eq)]
pub struct Layout {
    /// Each item's byte range and name, by start (items do not overlap).
    items: Vec<(u32, u32, String)>,
    /// Each item's start, by name.
    starts: HashMap<String, u32>,
}

impl Layout {
    /// The layout of items given as (name, span).
    pub fn new<'a>(items: impl IntoIterator<Item = (&'a str, Span)>) -> Self {
        let mut items: Vec<(u32, u32, String)> = items
            .into_iter()
            .map(|(name, s)| (s.start, s.end, name.to_string()))
            .collect();
        items.sort();
        let starts = items
            .iter()
            .map(|(start, _, name)| (name.clone(), *start))
            .collect();
        Layout { items, starts }
    }

    /// The layout of these items, sharing `previous` when it is the same (so values
    /// memoized under it need no moving).
    pub fn shared<'a>(
        items: impl IntoIterator<Item = (&'a str, Span)>,
        previous: Option<&Arc<Layout>>,
    ) -> Arc<Layout> {
        let layout = Layout::new(items);
        match previous {
            Some(p) if **p == layout => p.clone(),
            _ => Arc::new(layout),
        }
    }

    /// The item a byte range lies within: its name and start.
    fn item_at(&self, start: u32, end: u32) -> Option<(&str, u32)> {
        let k = self.items.partition_point(|(s, _, _)| *s <= start);
        let (s, e, name) = self.items.get(k.checked_sub(1)?)?;
        (end <= *e).then_some((name.as_str(), *s))
    }

    /// `s` moved from this layout to `new`: by how far the item it lies in moved
    /// (unchanged when it lies in no item, or the item is gone, or in another file).
    fn moved(&self, new: &Layout, file: FileId, s: Span) -> Span {
        if s.file != file {
            return s;
        }
        let Some((name, start)) = self.item_at(s.start, s.end) else {
            return s;
        };
        let Some(&nstart) = new.starts.get(name) else {
            return s;
        };
        let delta = i64::from(nstart) - i64::from(start);
        let shift = |x: u32| u32::try_from(i64::from(x) + delta).unwrap_or(x);
        Span {
            file,
            start: shift(s.start),
            end: shift(s.end),
        }
    }
}

/// A memoized value with its spans moved from the layout `old` it was computed in to
/// the current one, `new` (of `file`).
pub fn remap(v: &Value, old: &Arc<Layout>, new: &Arc<Layout>, file: FileId) -> Value {
    if Arc::ptr_eq(old, new) {
        return v.clone();
    }
    remap_with(v, &|s| old.moved(new, file, s))
}

/// `v` with `f` applied to every span in it.
fn remap_with(v: &Value, f: &dyn Fn(Span) -> Span) -> Value {
    let data = match &v.data {
        Data::List(items) => Data::List(Arc::new(items.iter().map(|i| remap_with(i, f)).collect())),
        Data::Tuple(items) => {
            Data::Tuple(Arc::new(items.iter().map(|i| remap_with(i, f)).collect()))
        }
        Data::Record(r) => Data::Record(Arc::new(Record {
            kind: r.kind.clone(),
            fields: r
                .fields
                .iter()
                .map(|(n, v)| (n.clone(), remap_with(v, f)))
                .collect(),
            feature: r.feature.clone(),
        })),
        Data::Sketch(s) => {
            let mut s = (**s).clone();
            for seg in &mut s.segments {
                seg.span = f(seg.span);
            }
            Data::Sketch(Arc::new(s))
        }
        other => other.clone(),
    };
    Value::new(data, f(v.span))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn span(start: u32, end: u32) -> Span {
        Span {
            file: FileId(0),
            start,
            end,
        }
    }

    #[test]
    fn a_span_moves_with_its_item() {
        let old = Layout::new([("a", span(0, 10)), ("b", span(10, 20))]);
        let new = Layout::new([("a", span(5, 15)), ("b", span(30, 40))]);
        assert_eq!(old.moved(&new, FileId(0), span(12, 14)), span(32, 34));
        assert_eq!(old.moved(&new, FileId(0), span(0, 10)), span(5, 15));
        // Outside every item, or spanning two: unchanged.
        assert_eq!(old.moved(&new, FileId(0), span(25, 26)), span(25, 26));
        assert_eq!(old.moved(&new, FileId(0), span(5, 15)), span(5, 15));
    }

    #[test]
    fn an_unchanged_layout_is_shared() {
        let first = Layout::shared([("a", span(0, 10))], None);
        let again = Layout::shared([("a", span(0, 10))], Some(&first));
        assert!(Arc::ptr_eq(&first, &again));
        let moved = Layout::shared([("a", span(1, 11))], Some(&first));
        assert!(!Arc::ptr_eq(&first, &moved));
    }
}
