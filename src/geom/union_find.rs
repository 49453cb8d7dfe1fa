//! Disjoint sets of indices (union-find): which mesh faces form one connected piece,
//! which grid vertices of a tessellation coincide and are welded into one.

/// Disjoint sets over the indices `0..len`, each set named by its smallest index so
/// that results do not depend on the order of the unions.
///
/// The parent table is allocated at the first union: a tessellation grid with nothing
/// to weld (the usual case) costs nothing.
#[derive(Debug, Clone)]
pub struct UnionFind {
    /// The number of indices.
    len: usize,
    /// The parent of each index (a root is its own parent); empty until the first union.
    /// Stored as `u32` (a mesh's nodes and faces are numbered so): half the memory a
    /// large mesh's sets walk through.
    parent: Vec<u32>,
}

impl UnionFind {
    /// `len` indices, each in a set of its own (at most `u32::MAX + 1`, as a mesh's
    /// numbering allows; an index beyond that is a caller's bug).
    pub fn new(len: usize) -> Self {
        assert!(
            len <= u32::MAX as usize + 1,
            "union-find over {len} indices: more than u32 numbers"
        );
        Self {
            len,
            parent: Vec::new(),
        }
    }

    /// The smallest index of the set holding `x`, halving paths on the way.
    pub fn find(&mut self, x: usize) -> usize {
        if self.parent.is_empty() {
            return x;
        }
        // x < len, checked by `new` to fit a u32.
        let mut x = x as u32;
        loop {
            let parent = self.parent[x as usize];
            if parent == x {
                return x as usize;
            }
            let grand = self.parent[parent as usize];
            self.parent[x as usize] = grand;
            x = grand;
        }
    }

    /// Joins the sets holding `a` and `b`; the smaller root becomes the root of both.
    pub fn union(&mut self, a: usize, b: usize) {
        if self.parent.is_empty() {
            // len fits a u32 (checked by `new`), so every index does.
            self.parent.extend((0..self.len).map(|i| i as u32));
        }
        let (ra, rb) = (self.find(a), self.find(b));
        let (lo, hi) = (ra.min(rb), ra.max(rb));
        self.parent[hi] = lo as u32;
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The defining property: two indices share a root exactly when a chain of unions
    /// joins them, and the root is the set's smallest index.
    #[test]
    fn roots_are_the_smallest_index_of_each_set() {
        let mut sets = UnionFind::new(7);
        assert_eq!(
            (0..7).map(|i| sets.find(i)).collect::<Vec<_>>(),
            [0, 1, 2, 3, 4, 5, 6]
        );
        sets.union(5, 3);
        sets.union(6, 5);
        sets.union(4, 1);
        sets.union(3, 3);
        let roots: Vec<usize> = (0..7).map(|i| sets.find(i)).collect();
        assert_eq!(roots, [0, 1, 2, 3, 1, 3, 3]);
        sets.union(6, 4);
        let roots: Vec<usize> = (0..7).map(|i| sets.find(i)).collect();
        assert_eq!(roots, [0, 1, 2, 1, 1, 1, 1]);
    }
}
