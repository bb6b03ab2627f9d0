//! The triangular solves of a simplicial factor in two halves of its elimination tree, side by
//! side.
//!
//! In `L y = b` column `j` of `L` updates only the rows of its ancestors in the elimination tree
//! (the structure of column `j` lies on the path from `j` to the root), and in `Lᵀ x = y` it reads
//! only those. So the columns of two disjoint sets of subtrees, `A` and `B`, are solved
//! independently, apart from the rows of their common ancestors `T` (the top of the tree, the
//! separator of a nested dissection):
//!
//! ```text
//! forward:   A and B side by side, each adding its updates of T's rows into a buffer of its own;
//!            y_T = b_T − (updates from A) − (updates from B), then T's columns
//! backward:  T's columns, then A and B side by side (they read T's final values)
//! ```
//!
//! The split is chosen once per symbolic analysis: starting from the roots, the subtree with the
//! most entries of `L` is replaced by its children (its column joins `T`), and of these steps the
//! one that minimises `entries(T) + max(largest subtree, half the rest)`, an estimate of the
//! entries one thread streams, is kept; its subtrees are packed into the two parts, largest first
//! into the lighter one. For the tutorial's pendulum (5,454 unknowns, 161,597 entries, AMD
//! ordering) one thread streams 55 % of the entries. Choosing it is one pass over the factor's
//! structure per symbolic analysis (the entries' indices in the parts' buffers, made once), not
//! per solve.
//!
//! The arithmetic of each column is that of the sequential solve; only the updates of `T`'s rows
//! are summed in another order (A's, then B's). The result does not depend on the number of
//! threads: with one, the two parts run one after the other, in the same arithmetic.

use std::collections::BinaryHeap;
use std::sync::Arc;

/// Splits whose one-thread path streams more than this fraction of the factor's entries are not
/// worth the hand-over: the plain solve serves.
const WORTH_IT: f64 = 0.75;

/// Expansion of the tree stops once `T` holds this fraction of the entries (the best split of the
/// tutorial's tree has 7.5 % in `T`).
const TOP_AT_MOST: f64 = 0.3;

/// Two halves of the elimination tree and their common ancestors (see the module doc).
#[derive(Debug)]
pub(super) struct TreeSplit {
    /// The columns of the two parts and of the top, each ascending.
    parts: [Vec<u32>; 2],
    top: Vec<u32>,
    /// Per entry of `L`, its row's index in the buffer of its column's part: a part's own columns
    /// first, then the top's rows; in the top's buffer, the top's position.
    local: Vec<u32>,
    /// The fill-reducing permutation: position `i` of the permuted system is unknown `forward[i]`.
    forward: Vec<u32>,
    /// The factor's column pointers.
    col_ptr: Arc<[u32]>,
}

/// The solve's work vectors: each part's, and the top's.
#[derive(Debug, Default)]
pub(super) struct Buffers {
    parts: [Vec<f64>; 2],
    top: Vec<f64>,
}

impl TreeSplit {
    /// The split of the simplicial factor with column pointers `col_ptr` and sorted row indices
    /// `row_idx` (the diagonal first in each column) under the permutation `forward` (identity when
    /// `None`), or `None` where no split is worth it.
    pub(super) fn new(col_ptr: &[u32], row_idx: &[u32], forward: Option<&[u32]>) -> Option<Self> {
        let n = col_ptr.len() - 1;
        let entries = |j: usize| (col_ptr[j + 1] - col_ptr[j]) as usize;
        // the parent of column j: its first row below the diagonal
        let parent: Vec<Option<usize>> = (0..n)
            .map(|j| (entries(j) > 1).then(|| row_idx[col_ptr[j] as usize + 1] as usize))
            .collect();
        let mut children = vec![Vec::new(); n];
        let mut subtree: Vec<usize> = (0..n).map(entries).collect();
        let mut roots = Vec::new();
        for j in 0..n {
            match parent[j] {
                // a parent comes after its children: the subtree sums are complete in order
                Some(p) => {
                    subtree[p] += subtree[j];
                    children[p].push(j);
                }
                None => roots.push(j),
            }
        }
        let total: usize = roots.iter().map(|&r| subtree[r]).sum();
        // Expansions in order, the largest subtree of the frontier first, with the entries one
        // thread streams at each: the top's plus the larger part's, estimated as the larger of
        // the largest subtree and half the rest (the greedy packing below comes close to it).
        let mut frontier: BinaryHeap<(usize, usize)> = roots.iter().map(|&r| (subtree[r], r)).collect();
        let (mut expanded, mut top_work) = (Vec::new(), 0usize);
        // (estimated entries of one thread, expansions made)
        let mut best = (usize::MAX, 0);
        while let Some(&(largest, j)) = frontier.peek() {
            if (top_work as f64) > TOP_AT_MOST * total as f64 {
                break;
            }
            let estimate = top_work + largest.max((total - top_work).div_ceil(2));
            if estimate < best.0 {
                best = (estimate, expanded.len());
            }
            frontier.pop();
            top_work += entries(j);
            expanded.push(j);
            frontier.extend(children[j].iter().map(|&c| (subtree[c], c)));
        }
        let expanded = &expanded[..best.1];
        let mut is_top = vec![false; n];
        expanded.iter().for_each(|&j| is_top[j] = true);
        // the frontier after the best number of expansions: the roots and the children of the
        // expanded columns that are not expanded themselves, packed largest first into the
        // lighter part
        let mut subtrees: Vec<usize> = roots
            .iter()
            .chain(expanded.iter().flat_map(|&j| &children[j]))
            .copied()
            .filter(|&j| !is_top[j])
            .collect();
        subtrees.sort_by_key(|&j| (std::cmp::Reverse(subtree[j]), j));
        let (mut a, mut b, mut in_a) = (0, 0, Vec::new());
        for &j in &subtrees {
            if a <= b {
                a += subtree[j];
                in_a.push(j);
            } else {
                b += subtree[j];
            }
        }
        let top_work: usize = expanded.iter().map(|&j| entries(j)).sum();
        if (top_work + a.max(b)) as f64 > WORTH_IT * total as f64 {
            return None;
        }
        // 0: part A, 1: part B, 2: top
        let mut owner = vec![1u8; n];
        for &j in expanded {
            owner[j] = 2;
        }
        let mut stack = in_a;
        while let Some(j) = stack.pop() {
            owner[j] = 0;
            stack.extend(&children[j]);
        }
        let columns = |p: u8| {
            (0..n)
                .filter(|&j| owner[j] == p)
                .map(|j| j as u32)
                .collect::<Vec<u32>>()
        };
        let (parts, top) = ([columns(0), columns(1)], columns(2));
        let mut position = vec![0u32; n];
        for list in parts.iter().chain([&top]) {
            for (l, &j) in list.iter().enumerate() {
                position[j as usize] = l as u32;
            }
        }
        let mut local = Vec::with_capacity(row_idx.len());
        for j in 0..n {
            let own = match owner[j] {
                2 => 0,
                p => parts[p as usize].len() as u32,
            };
            for &i in &row_idx[col_ptr[j] as usize..col_ptr[j + 1] as usize] {
                let i = i as usize;
                local.push(position[i] + if owner[i] == 2 { own } else { 0 });
            }
        }
        Some(Self {
            parts,
            top,
            local,
            forward: forward.map_or_else(|| (0..n as u32).collect(), <[u32]>::to_vec),
            col_ptr: col_ptr.into(),
        })
    }

    /// Work vectors for this split.
    pub(super) fn buffers(&self) -> Buffers {
        Buffers {
            parts: self.parts.each_ref().map(|p| vec![0.0; p.len() + self.top.len()]),
            top: vec![0.0; self.top.len()],
        }
    }

    /// Solves `L Lᵀ x = b` in place (`b` in the unknowns' order; `values` the factor's entries).
    pub(super) fn solve(&self, values: &[f64], b: &mut [f64], work: &mut Buffers) {
        let (cp, local) = (&self.col_ptr[..], &self.local[..]);
        let Buffers { parts, top: xt } = work;
        let [xa, xb] = parts;
        let gather = |cols: &[u32], x: &mut [f64]| {
            for (xl, &j) in x.iter_mut().zip(cols) {
                *xl = b[self.forward[j as usize] as usize];
            }
            x[cols.len()..].fill(0.0);
        };
        gather(&self.parts[0], xa);
        gather(&self.parts[1], xb);
        for (t, &j) in self.top.iter().enumerate() {
            xt[t] = b[self.forward[j as usize] as usize];
        }
        let [a, bcols] = &self.parts;
        both(
            || forward(a, cp, local, values, xa),
            || forward(bcols, cp, local, values, xb),
        );
        let (na, nb) = (a.len(), bcols.len());
        // the parts' buffers hold minus their updates of the top's rows
        for t in 0..xt.len() {
            xt[t] += xa[na + t] + xb[nb + t];
        }
        forward(&self.top, cp, local, values, xt);
        backward(&self.top, cp, local, values, xt);
        xa[na..].copy_from_slice(xt);
        xb[nb..].copy_from_slice(xt);
        both(
            || backward(a, cp, local, values, xa),
            || backward(bcols, cp, local, values, xb),
        );
        for (cols, x) in [(&self.parts[0], &*xa), (&self.parts[1], &*xb), (&self.top, &*xt)] {
            for (&j, &v) in cols.iter().zip(x.iter()) {
                b[self.forward[j as usize] as usize] = v;
            }
        }
    }
}

/// Runs both closures, side by side on the pool when called from one of its threads (from
/// elsewhere each hand-over would wake the pool and put the caller to sleep: one after the other
/// costs less there).
fn both(a: impl FnOnce() + Send, b: impl FnOnce() + Send) {
    if rayon::current_thread_index().is_some() {
        rayon::join(a, b);
    } else {
        a();
        b();
    }
}

/// `L y = x` over the columns `cols` (ascending), in the part's buffer `x`.
fn forward(cols: &[u32], col_ptr: &[u32], local: &[u32], values: &[f64], x: &mut [f64]) {
    for (jl, &j) in cols.iter().enumerate() {
        let (s, e) = (col_ptr[j as usize] as usize, col_ptr[j as usize + 1] as usize);
        let v = x[jl] / values[s];
        x[jl] = v;
        for (l, &i) in values[s + 1..e].iter().zip(&local[s + 1..e]) {
            x[i as usize] -= l * v;
        }
    }
}

/// `Lᵀ x = y` over the columns `cols` (descending), in the part's buffer `x`.
fn backward(cols: &[u32], col_ptr: &[u32], local: &[u32], values: &[f64], x: &mut [f64]) {
    for (jl, &j) in cols.iter().enumerate().rev() {
        let (s, e) = (col_ptr[j as usize] as usize, col_ptr[j as usize + 1] as usize);
        let mut v = x[jl];
        for (l, &i) in values[s + 1..e].iter().zip(&local[s + 1..e]) {
            v -= l * x[i as usize];
        }
        x[jl] = v / values[s];
    }
}
