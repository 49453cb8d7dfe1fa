//! Disjoint sets of indices (union-find): which mesh faces form one connected piece,
//! which grid vertices of a tessellation coincide and are welded into one.

/// Checks that the indices `0..len` fit a `u32` (a mesh's numbering): more is a
/// caller's bug. Every caller passes a count of a mesh's nodes or faces, or of a
/// tessellation grid's vertices, which `Mesh::new` and the tessellator keep within
/// `u32` ids, so user input never reaches the panic.
fn check_len(len: usize) {
    assert!(
        len <= u32::MAX as usize + 1,
        "union-find over {len} indices: more than u32 numbers"
    );
}

/// The root of `x` in the forest `parent` (a root is its own parent), halving the path
/// on the way: each node passed is hung under its grandparent. A node already hung
/// under its root (most, once the sets have grown) is read, not written.
fn root_halving(parent: &mut [u32], x: usize) -> usize {
    // x indexes parent, whose length was checked to fit a u32.
    let mut x = x as u32;
    loop {
        let up = parent[x as usize];
        if up == x {
            return x as usize;
        }
        let grand = parent[up as usize];
        if grand == up {
            return up as usize;
        }
        parent[x as usize] = grand;
        x = grand;
    }
}

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
        check_len(len);
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
        root_halving(&mut self.parent, x)
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

/// Disjoint sets over the indices `0..len` where only which indices share a set
/// matters, not what the set is called: the smaller set is hung under the larger, so
/// the trees stay shallow and a mesh's faces are joined in fewer steps than by
/// [`UnionFind`], whose roots must be the smallest index. A set's root depends on the
/// order of the unions; that two indices share it does not.
#[derive(Debug, Clone)]
pub struct SetsBySize {
    /// The parent of each index (a root is its own parent).
    parent: Vec<u32>,
    /// The size of each root's set (meaningless for an index that is not a root).
    size: Vec<u32>,
}

impl SetsBySize {
    /// `len` indices, each in a set of its own (at most `u32::MAX + 1`, as a mesh's
    /// numbering allows; an index beyond that is a caller's bug).
    pub fn new(len: usize) -> Self {
        check_len(len);
        Self {
            // len fits a u32 (checked above), so every index does.
            parent: (0..len).map(|i| i as u32).collect(),
            size: vec![1; len],
        }
    }

    /// The root of the set holding `x`, halving paths on the way.
    pub fn find(&mut self, x: usize) -> usize {
        root_halving(&mut self.parent, x)
    }

    /// Joins the sets whose roots are `a` and `b` (as [`SetsBySize::find`] gave them),
    /// and gives the root of the joined set.
    pub fn join_roots(&mut self, a: usize, b: usize) -> usize {
        if a == b {
            return a;
        }
        let (big, small) = if self.size[a] >= self.size[b] {
            (a, b)
        } else {
            (b, a)
        };
        // Both are indices below len, so u32 (checked by `new`).
        self.parent[small] = big as u32;
        // Saturating: a size only guides which set hangs under which.
        self.size[big] = self.size[big].saturating_add(self.size[small]);
        big
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

    /// Joined by size, two indices share a root exactly where a chain of unions joins
    /// them, whatever the order of the unions.
    #[test]
    fn sets_by_size_share_roots_as_unions_join_them() {
        let unions = [(5, 3), (6, 5), (4, 1), (3, 3), (6, 4)];
        for order in [unions.to_vec(), unions.iter().rev().copied().collect()] {
            let mut by_size = SetsBySize::new(7);
            let mut smallest = UnionFind::new(7);
            for &(a, b) in &order {
                let (ra, rb) = (by_size.find(a), by_size.find(b));
                by_size.join_roots(ra, rb);
                smallest.union(a, b);
            }
            for a in 0..7 {
                for b in 0..7 {
                    assert_eq!(
                        by_size.find(a) == by_size.find(b),
                        smallest.find(a) == smallest.find(b),
                        "{a} and {b} after {order:?}"
                    );
                }
            }
        }
    }
}
