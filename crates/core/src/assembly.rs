//! The global sparsity pattern, built once per run, and the element-to-matrix scatter maps.
//!
//! The stiffness-like matrices of this problem are symmetric; only the upper triangle (`row ≤ col`)
//! is stored, column-compressed (CSC), which is what the Cholesky factorisation reads
//! ([`crate::linsolve`]). The pattern is the union of the element couplings (every degree of freedom
//! of an element with every other) and of any extra entries a term asks for
//! ([`crate::terms::Term::hessian_entries`]). Every term always writes the same entries (zero when
//! inactive), so the pattern and the symbolic factorisation never change during a run.
//!
//! Element matrices are scattered through precomputed positions: for element `e` and local
//! degrees of freedom `i, j` (`0..12`, node-major, x before y), `scatter[e·144 + 12 i + j]` is the
//! index in arrays of [`Pattern::nnz`] values, or [`SKIP`] for the lower-triangle half.

use crate::mesh::Mesh;

/// `n` zeros written into fresh memory, for arrays that are then summed into in scattered order
/// (assembly). `vec![0.0; n]` asks the system for zeroed memory, whose pages it maps to one shared
/// page of zeros on the first read and copies on the first write: with the pool's threads running,
/// each copy also interrupts every other core to flush its address cache. Written first, each page
/// is made once, before the threads sum into it (the mass matrix, the gravity loads and the
/// rigid-body functionals).
pub fn written_zeros(n: usize) -> Vec<f64> {
    let mut v = Vec::with_capacity(n);
    v.resize(n, 0.0);
    v
}

/// Marks a local pair that belongs to the lower triangle (added through its mirror).
pub const SKIP: u32 = u32::MAX;

/// Upper-triangular CSC sparsity pattern of the `2·nodes` degrees of freedom.
#[derive(Clone, Debug)]
pub struct Pattern {
    /// Matrix dimension.
    pub n: usize,
    /// Column pointers (`n + 1`).
    pub col_ptr: Vec<usize>,
    /// Row indices, sorted within each column.
    pub row_idx: Vec<usize>,
    /// Per element, 144 positions (see the module doc).
    pub scatter: Vec<u32>,
}

/// Global degrees of freedom of an element, node-major: `[2a₀, 2a₀+1, 2a₁, …]`.
pub fn element_dofs(nodes: &[usize; 6]) -> [usize; 12] {
    let mut d = [0; 12];
    for (a, &n) in nodes.iter().enumerate() {
        d[2 * a] = 2 * n;
        d[2 * a + 1] = 2 * n + 1;
    }
    d
}

impl Pattern {
    /// Builds the pattern of `mesh` plus `extra` `(row, col)` entries (either order).
    pub fn new(mesh: &Mesh, extra: &[(usize, usize)]) -> Self {
        if extra.is_empty() {
            return Self::of_elements(mesh);
        }
        Self::with_extra(mesh, extra)
    }

    /// [`Pattern::new`] without extra entries, the same pattern and scatter maps made node by node:
    /// the element couplings are those of the nodes, each node pair a 2×2 block, so column `2b`
    /// holds the rows `2a, 2a + 1` of every node `a < b` coupled to `b` and then `2b`, and column
    /// `2b + 1` those of every `a ≤ b`. The position of `(2a + i, 2b + j)` is then the column's
    /// start plus twice the place of `a` among `b`'s nodes plus `i`: one search per node pair
    /// instead of one per entry (a quarter of the work, and no per-entry lists to sort).
    fn of_elements(mesh: &Mesh) -> Self {
        let nodes = mesh.num_nodes();
        let mut columns: Vec<Vec<usize>> = vec![Vec::new(); nodes];
        for tri in &mesh.triangles {
            for &b in tri {
                columns[b].extend(tri.iter().copied().filter(|&a| a <= b));
            }
        }
        let n = 2 * nodes;
        let mut col_ptr = Vec::with_capacity(n + 1);
        let mut row_idx = Vec::new();
        col_ptr.push(0);
        for (b, col) in columns.iter_mut().enumerate() {
            col.sort_unstable();
            col.dedup();
            for j in 0..2 {
                for &a in col.iter() {
                    row_idx.push(2 * a);
                    if a < b || j == 1 {
                        row_idx.push(2 * a + 1);
                    }
                }
                col_ptr.push(row_idx.len());
            }
        }
        let mut scatter = Vec::with_capacity(mesh.triangles.len() * 144);
        for tri in &mesh.triangles {
            // the place of node a among node b's nodes, for a ≤ b
            let place: [[usize; 6]; 6] = std::array::from_fn(|x| {
                std::array::from_fn(|y| {
                    let (a, b) = (tri[x], tri[y]);
                    match a <= b {
                        true => columns[b].binary_search(&a).expect("an element's nodes are coupled"),
                        false => 0,
                    }
                })
            });
            for (x, &na) in tri.iter().enumerate() {
                for i in 0..2 {
                    for (y, &nb) in tri.iter().enumerate() {
                        for j in 0..2 {
                            let (r, c) = (2 * na + i, 2 * nb + j);
                            scatter.push(if r <= c {
                                (col_ptr[c] + 2 * place[x][y] + i) as u32
                            } else {
                                SKIP
                            });
                        }
                    }
                }
            }
        }
        Self {
            n,
            col_ptr,
            row_idx,
            scatter,
        }
    }

    /// [`Pattern::new`] with extra entries: every entry's row listed in its column, sorted, and
    /// each element entry's position searched.
    fn with_extra(mesh: &Mesh, extra: &[(usize, usize)]) -> Self {
        let n = 2 * mesh.num_nodes();
        let mut cols: Vec<Vec<usize>> = vec![Vec::new(); n];
        for tri in &mesh.triangles {
            let d = element_dofs(tri);
            for &r in &d {
                for &c in &d {
                    if r <= c {
                        cols[c].push(r);
                    }
                }
            }
        }
        for &(r, c) in extra {
            let (r, c) = if r <= c { (r, c) } else { (c, r) };
            cols[c].push(r);
        }
        let mut col_ptr = Vec::with_capacity(n + 1);
        let mut row_idx = Vec::new();
        col_ptr.push(0);
        for col in &mut cols {
            col.sort_unstable();
            col.dedup();
            row_idx.extend_from_slice(col);
            col_ptr.push(row_idx.len());
        }
        let mut p = Self {
            n,
            col_ptr,
            row_idx,
            scatter: Vec::with_capacity(mesh.triangles.len() * 144),
        };
        for tri in &mesh.triangles {
            let d = element_dofs(tri);
            for &r in &d {
                for &c in &d {
                    let pos = if r <= c {
                        p.position(r, c).expect("element entry in pattern") as u32
                    } else {
                        SKIP
                    };
                    p.scatter.push(pos);
                }
            }
        }
        p
    }

    /// Number of stored entries.
    pub fn nnz(&self) -> usize {
        self.row_idx.len()
    }

    /// Index of entry `(r, c)` (either order) in the value array, if it is in the pattern.
    pub fn position(&self, r: usize, c: usize) -> Option<usize> {
        let (r, c) = if r <= c { (r, c) } else { (c, r) };
        let rows = &self.row_idx[self.col_ptr[c]..self.col_ptr[c + 1]];
        rows.binary_search(&r).ok().map(|k| self.col_ptr[c] + k)
    }

    /// Adds a 12×12 element matrix (row-major, symmetric) of element `e` into `values`.
    #[inline]
    pub fn scatter_element(&self, e: usize, ke: &[f64; 144], values: &mut [f64]) {
        let map = &self.scatter[e * 144..(e + 1) * 144];
        for (k, &pos) in map.iter().enumerate() {
            if pos != SKIP {
                values[pos as usize] += ke[k];
            }
        }
    }

    /// `y = A x` for the symmetric matrix whose upper triangle is `values`.
    pub fn sym_matvec(&self, values: &[f64], x: &[f64], y: &mut [f64]) {
        y.iter_mut().for_each(|v| *v = 0.0);
        for c in 0..self.n {
            for k in self.col_ptr[c]..self.col_ptr[c + 1] {
                let r = self.row_idx[k];
                let v = values[k];
                y[r] += v * x[c];
                if r != c {
                    y[c] += v * x[r];
                }
            }
        }
    }
}

/// Degrees of freedom held at zero (the fixed edges of a body), imposed on an assembled system
/// without touching the sparsity pattern: their gradient entries are zeroed, and their rows and
/// columns of the matrix are zeroed with a unit diagonal. A Newton update is then zero there, so
/// a state that starts at zero stays there; the symbolic factorisation is unchanged.
#[derive(Clone, Debug, Default)]
pub struct Dirichlet {
    /// The fixed degrees of freedom, sorted.
    pub dofs: Vec<usize>,
    /// Positions in the pattern's values of the off-diagonal entries in a fixed row or column.
    off_diagonal: Vec<usize>,
    /// Positions of the fixed diagonal entries.
    diagonal: Vec<usize>,
}

impl Dirichlet {
    /// The fixed `dofs` of a system with pattern `pattern`.
    pub fn new(pattern: &Pattern, mut dofs: Vec<usize>) -> Self {
        dofs.sort_unstable();
        dofs.dedup();
        let (mut off_diagonal, mut diagonal) = (Vec::new(), Vec::new());
        if dofs.is_empty() {
            // the pendulum alone, held by its hinge: no entry to find
            return Self {
                dofs,
                off_diagonal,
                diagonal,
            };
        }
        let mut fixed = vec![false; pattern.n];
        dofs.iter().for_each(|&d| fixed[d] = true);
        for c in 0..pattern.n {
            for k in pattern.col_ptr[c]..pattern.col_ptr[c + 1] {
                let r = pattern.row_idx[k];
                if r == c && fixed[c] {
                    diagonal.push(k);
                } else if r != c && (fixed[r] || fixed[c]) {
                    off_diagonal.push(k);
                }
            }
        }
        Self {
            dofs,
            off_diagonal,
            diagonal,
        }
    }

    /// Whether nothing is fixed.
    pub fn is_empty(&self) -> bool {
        self.dofs.is_empty()
    }

    /// Zeroes the fixed rows and columns of the matrix `values` and sets a unit diagonal.
    pub fn apply_matrix(&self, values: &mut [f64]) {
        self.off_diagonal.iter().for_each(|&k| values[k] = 0.0);
        self.diagonal.iter().for_each(|&k| values[k] = 1.0);
    }

    /// Zeroes the fixed entries of a gradient or right-hand side.
    pub fn apply_vector(&self, g: &mut [f64]) {
        self.dofs.iter().for_each(|&d| g[d] = 0.0);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The node-by-node pattern ([`Pattern::of_elements`]) is the entry-by-entry one
    /// ([`Pattern::with_extra`] with nothing extra) exactly: the same columns, rows and scatter maps,
    /// on the tutorial's mesh and on one refined twice.
    #[test]
    fn the_node_by_node_pattern_is_the_entry_by_entry_one() {
        for refine in [1.0, 2.0] {
            let mut cfg = crate::config::Config::default();
            cfg.mesh.refine = refine;
            let mesh = crate::mesh::generate_with_stats(&cfg).expect("mesh").0;
            let (fast, general) = (Pattern::of_elements(&mesh), Pattern::with_extra(&mesh, &[]));
            assert_eq!(fast.n, general.n);
            assert_eq!(fast.col_ptr, general.col_ptr);
            assert_eq!(fast.row_idx, general.row_idx);
            assert_eq!(fast.scatter, general.scatter);
        }
    }
}
