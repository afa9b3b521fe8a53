//! Matrix-free storage of a symmetric operator on a structured box mesh: every element of the
//! box is the same, so the assembled matrix `A = Σ_e P_eᵀ A_e P_e` is a constant-coefficient
//! stencil away from the faces. Row block `i` (node `i`, `d` dofs) is
//! ```text
//! (A x)_i = Σ_{o ∈ {−1,0,1}^d} B_{c(i)}(o) x_{i+o},   B_c(o) = Σ_{e ∋ i, i+o} A_e[a_e(i), a_e(i+o)]
//! ```
//! where the `d × d` blocks `B_c` depend only on the node's *class* `c(i)`: which of the `2^d`
//! elements around it exist (and enter the integral) and whether its neighbours above are on the
//! eliminated Dirichlet face. A 3D box has at most a few dozen classes of 27 blocks, so the
//! operator costs `O(n)` memory for the class of each node and nothing per entry, and a product
//! reads only the two vectors: at 1 M unknowns the assembled matrix (81 entries per row) would
//! take 1.3 GB and be read whole at every product.
//!
//! The blocks are sums of one element matrix (element 0's: the elements are translates of each
//! other), so the stencil equals the assembled matrix to round-off, not bit for bit: the
//! assembled one sums each element's own matrix in another order.

use std::ops::Range;

use rayon::prelude::*;

use super::separable::SeparablePart;

/// The most nodes in a parallel task of a product. The partial sums of a reduction are added
/// in task order, so results do not depend on the number of threads.
const NODES_PER_TASK: usize = 2048;

/// Nodes per task for `n_nodes`: the fewest tasks of at most [`NODES_PER_TASK`], made equal (at
/// 3D level 80, 6 480 nodes, four tasks of 1 620 instead of three of 2 048 and one of 336, which
/// left one of two threads idle for a fifth of each product).
fn nodes_per_task(n_nodes: usize) -> usize {
    n_nodes
        .div_ceil(n_nodes.div_ceil(NODES_PER_TASK).max(1))
        .max(1)
}

/// The blocks of one node class: `(node offset, block)` for every neighbour with a non-zero
/// block, the block `d × d` row-major in the first `d²` entries, and the same blocks by
/// columns for the product ([`NodeClass::columns`]).
#[derive(Debug, Clone, PartialEq)]
struct NodeClass {
    blocks: Vec<(isize, [f64; 9])>,
    /// The node offsets of `blocks`, in order, kept apart from them so that the product reads
    /// them contiguously instead of striding over the row-major blocks.
    offsets: Vec<isize>,
    /// Column `c` of block `b` at `[(b·d + c)·LANES ..][.. LANES]`, zero below row `d`.
    columns: Vec<f64>,
}

/// The entries a block column is padded to: one 256-bit vector, so that a column times one
/// entry of `x` is one vector multiply and add (`d ≤ 3`).
const LANES: usize = 4;

impl NodeClass {
    /// The class of `blocks` (sorted by offset), with their columns.
    fn new(dim: usize, blocks: Vec<(isize, [f64; 9])>) -> Self {
        let offsets = blocks.iter().map(|(o, _)| *o).collect();
        let mut columns = vec![0.0; blocks.len() * dim * LANES];
        for ((_, block), per_block) in blocks.iter().zip(columns.chunks_exact_mut(dim * LANES)) {
            for (c, column) in per_block.chunks_exact_mut(LANES).enumerate() {
                for (r, entry) in column.iter_mut().take(dim).enumerate() {
                    *entry = block[r * dim + c];
                }
            }
        }
        Self {
            blocks,
            offsets,
            columns,
        }
    }
}

/// A symmetric operator on the dofs of a [`BoxMesh`] (node-major, `d` components per node, the
/// Dirichlet layer eliminated), stored as the blocks of each node class.
#[derive(Debug, Clone, PartialEq)]
pub struct Stencil {
    dim: usize,
    /// Kept nodes per axis: `n_k + 1`, and `n_d` along the last (the face `x_d = L_d` is
    /// eliminated).
    nodes_per_axis: [usize; 3],
    class_of: Vec<u16>,
    classes: Vec<NodeClass>,
    /// The separable part of this operator ([`Stencil::with_separable_part`]).
    separable: Option<SeparablePart>,
}

/// The local corner index of an element corner given by its bits (bit `k` set: the corner's
/// coordinate `k` is the element's upper one), in the corner order of the element matrices.
fn corner_of_bits(dim: usize, bits: usize) -> usize {
    let order: &[usize] = if dim == 2 {
        &[0b00, 0b01, 0b11, 0b10]
    } else {
        &[0b000, 0b001, 0b011, 0b010, 0b100, 0b101, 0b111, 0b110]
    };
    order
        .iter()
        .position(|&b| b == bits)
        .expect("bits below 2^d")
}

impl Stencil {
    /// The operator `Σ_e P_eᵀ A_e P_e` over the elements of a box mesh with `counts[k]`
    /// elements along axis `k` (a [`BoxMesh`](super::BoxMesh)'s numbering, its last layer of
    /// nodes eliminated), where `entry(p, q)` is the entry of the (common) element matrix at
    /// local dofs `p = a·d + r`, `q = b·d + c`, and the first element layer (the elements
    /// touching `Γ_Sig`) is left out when `without_first_layer` (the note's `M^mod`, eq. 7).
    pub fn from_element(
        counts: &[usize],
        entry: impl Fn(usize, usize) -> f64,
        without_first_layer: bool,
    ) -> Self {
        let dim = counts.len();
        let mut nodes_per_axis = [1usize; 3];
        for k in 0..dim {
            nodes_per_axis[k] = counts[k] + usize::from(k + 1 < dim);
        }
        let n_nodes: usize = nodes_per_axis.iter().product();
        let mut keys: Vec<u16> = Vec::new();
        let mut classes = Vec::new();
        let mut class_of = Vec::with_capacity(n_nodes);
        for node in 0..n_nodes {
            let index = unflatten(node, &nodes_per_axis);
            let key = class_key(dim, counts, &index);
            let class = match keys.iter().position(|&k| k == key) {
                Some(c) => c,
                None => {
                    keys.push(key);
                    classes.push(node_class(
                        dim,
                        counts,
                        &nodes_per_axis,
                        &index,
                        &entry,
                        without_first_layer,
                    ));
                    keys.len() - 1
                }
            };
            class_of.push(u16::try_from(class).expect("at most 4^6 classes"));
        }
        Self {
            dim,
            nodes_per_axis,
            class_of,
            classes,
            separable: None,
        }
    }

    /// The operator carrying `part`, its separable part (the mass, or the stiffness's
    /// component-diagonal blocks), from which CG's preconditioner is built.
    pub fn with_separable_part(mut self, part: SeparablePart) -> Self {
        self.separable = Some(part);
        self
    }

    /// The separable part this operator carries, if any.
    pub fn separable_part(&self) -> Option<&SeparablePart> {
        self.separable.as_ref()
    }

    /// The number of unknowns.
    pub fn dim(&self) -> usize {
        self.class_of.len() * self.dim
    }

    /// The principal submatrix on the nodes off the first layer along the last axis (off
    /// `Γ_Sig`: a suffix of the numbering), matrix-free: the nodes of the second layer lose
    /// their blocks with the first, the others keep theirs, and the separable part loses the
    /// last axis's first node ([`SeparablePart::without_first_layer`]). What `M^mod`'s dofs
    /// with mass need for the initial acceleration without assembling the mass. `None` for a
    /// box of fewer than two layers.
    pub fn without_first_layer(&self) -> Option<Stencil> {
        let axis = self.dim - 1;
        let all = self.nodes_per_axis[axis];
        if all < 2 {
            return None;
        }
        let per_layer: usize = self.nodes_per_axis[..axis].iter().product();
        let mut classes = self.classes.clone();
        let mut cut_class: Vec<Option<u16>> = vec![None; self.classes.len()];
        let mut class_of = self.class_of[per_layer..].to_vec();
        for (node, class) in class_of.iter_mut().take(per_layer).enumerate() {
            let original = usize::from(*class);
            let cut = *cut_class[original].get_or_insert_with(|| {
                let blocks = self.classes[original]
                    .blocks
                    .iter()
                    .filter(|(offset, _)| node as isize + offset >= 0)
                    .copied()
                    .collect();
                classes.push(NodeClass::new(self.dim, blocks));
                u16::try_from(classes.len() - 1).expect("at most 4^6 classes")
            });
            *class = cut;
        }
        let mut nodes_per_axis = self.nodes_per_axis;
        nodes_per_axis[axis] = all - 1;
        Some(Stencil {
            dim: self.dim,
            nodes_per_axis,
            class_of,
            classes,
            separable: self
                .separable
                .as_ref()
                .map(SeparablePart::without_first_layer),
        })
    }

    /// The principal submatrix on the first `layers` node layers along the last axis (the
    /// nodes next to `Γ_Sig` first, a prefix of the numbering): the operator of the same box
    /// cut after `layers` layers, with zero displacement beyond the cut. Every kept node keeps
    /// its blocks but the last layer's, which lose their couplings beyond the cut: those are
    /// the blocks of the box's last layer (next to its eliminated face), whose elements are the
    /// same. `None` unless `3 ≤ layers <` the box's layers (the first two layers have blocks
    /// of their own).
    pub fn first_layers(&self, layers: usize) -> Option<Stencil> {
        let axis = self.dim - 1;
        let all = self.nodes_per_axis[axis];
        if layers < 3 || layers >= all {
            return None;
        }
        let per_layer: usize = self.nodes_per_axis[..axis].iter().product();
        let kept = (layers - 1) * per_layer;
        let last = (all - 1) * per_layer;
        let mut class_of = self.class_of[..kept].to_vec();
        class_of.extend_from_slice(&self.class_of[last..last + per_layer]);
        let mut nodes_per_axis = self.nodes_per_axis;
        nodes_per_axis[axis] = layers;
        Some(Stencil {
            dim: self.dim,
            nodes_per_axis,
            class_of,
            classes: self.classes.clone(),
            separable: self.separable.as_ref().map(|p| p.first_layers(layers)),
        })
    }

    /// The rows of the node layers `layers` along the last axis (a range of the numbering),
    /// matrix-free, without a separable part: a slab's share of the operator, whose product
    /// reads the layers next to it ([`Stencil::mul_dot_with_halo`]). `None` for an empty range
    /// or one past the box's layers.
    pub fn layers(&self, layers: Range<usize>) -> Option<Stencil> {
        let axis = self.dim - 1;
        if layers.is_empty() || layers.end > self.nodes_per_axis[axis] {
            return None;
        }
        let per_layer = self.nodes_per_layer();
        let mut nodes_per_axis = self.nodes_per_axis;
        nodes_per_axis[axis] = layers.len();
        Some(Stencil {
            dim: self.dim,
            nodes_per_axis,
            class_of: self.class_of[layers.start * per_layer..layers.end * per_layer].to_vec(),
            classes: self.classes.clone(),
            separable: None,
        })
    }

    /// The components per node (the box's dimension).
    pub fn components(&self) -> usize {
        self.dim
    }

    /// The nodes of one layer across the last axis.
    pub fn nodes_per_layer(&self) -> usize {
        self.nodes_per_axis[..self.dim - 1].iter().product()
    }

    /// The node layers along the last axis.
    pub fn node_layers(&self) -> usize {
        self.nodes_per_axis[self.dim - 1]
    }

    /// Entry `(i, j)`.
    pub fn get(&self, i: usize, j: usize) -> f64 {
        let d = self.dim;
        let (node, r) = (i / d, i % d);
        let (other, c) = (j / d, j % d);
        let delta = other as isize - node as isize;
        self.classes[usize::from(self.class_of[node])]
            .blocks
            .iter()
            .find(|(o, _)| *o == delta)
            .map_or(0.0, |(_, b)| b[r * d + c])
    }

    /// `Σ_j |A_ij|` of every row, from the blocks of each node class (the same for every node
    /// of a class).
    pub fn abs_row_sums(&self) -> Vec<f64> {
        let d = self.dim;
        let per_class: Vec<Vec<f64>> = self
            .classes
            .iter()
            .map(|class| {
                (0..d)
                    .map(|r| {
                        let row = |b: &[f64; 9]| {
                            b[r * d..(r + 1) * d].iter().map(|v| v.abs()).sum::<f64>()
                        };
                        class.blocks.iter().map(|(_, b)| row(b)).sum()
                    })
                    .collect()
            })
            .collect();
        self.class_of
            .iter()
            .flat_map(|&c| per_class[usize::from(c)].iter().copied())
            .collect()
    }

    /// Calls `f(j, A_ij)` for every entry of row `i` in a non-zero block.
    pub fn for_each_in_row(&self, i: usize, mut f: impl FnMut(usize, f64)) {
        let d = self.dim;
        let (node, r) = (i / d, i % d);
        for (delta, b) in &self.classes[usize::from(self.class_of[node])].blocks {
            let first = (node as isize + delta) as usize * d;
            for c in 0..d {
                f(first + c, b[r * d + c]);
            }
        }
    }

    /// The largest `|i − j|` over the non-zero blocks.
    pub fn bandwidth(&self) -> usize {
        let d = self.dim;
        self.classes
            .iter()
            .flat_map(|c| c.blocks.iter().map(|(o, _)| o.unsigned_abs() * d + d - 1))
            .max()
            .unwrap_or(0)
    }

    /// `a·self + b·other` for two stencils on one mesh (blockwise), with the combined
    /// separable part ([`SeparablePart::combine`]); `None` when the meshes differ.
    pub fn linear_combination(&self, a: f64, other: &Stencil, b: f64) -> Option<Stencil> {
        if self.dim != other.dim || self.nodes_per_axis != other.nodes_per_axis {
            return None;
        }
        let mut pairs: Vec<(u16, u16)> = Vec::new();
        let mut class_of = Vec::with_capacity(self.class_of.len());
        let mut classes = Vec::new();
        for (&p, &q) in self.class_of.iter().zip(&other.class_of) {
            let class = match pairs.iter().position(|&k| k == (p, q)) {
                Some(c) => c,
                None => {
                    pairs.push((p, q));
                    classes.push(combine(
                        self.dim,
                        &self.classes[usize::from(p)],
                        a,
                        &other.classes[usize::from(q)],
                        b,
                    ));
                    pairs.len() - 1
                }
            };
            class_of.push(u16::try_from(class).ok()?);
        }
        let separable = match (&self.separable, &other.separable) {
            (Some(p), Some(q)) => SeparablePart::combine(p, a, q, b),
            _ => None,
        };
        Some(Stencil {
            dim: self.dim,
            nodes_per_axis: self.nodes_per_axis,
            class_of,
            classes,
            separable,
        })
    }

    /// Calls `sink(node, (A x)_node)` for every node of `nodes`, in order (`x` holding `halo`
    /// nodes before the first row's, [`Stencil::mul_dot_with_halo`]), the row block
    /// summed column by column into `2·D` independent accumulators (so that the additions do
    /// not wait on each other): `acc[b mod 2][c] += B(o_b)[:, c] · x_{node+o_b, c}` over the
    /// blocks `b` and the columns `c`, each a [`LANES`]-wide multiply and add (entries `D..`
    /// are zero), then `Σ_c (acc[0][c] + acc[1][c])`. Two consecutive nodes of one class are
    /// taken together, sharing the loads of their blocks' columns (the same operations per node,
    /// so the same result).
    #[inline(always)]
    fn rows<const D: usize>(
        &self,
        x: &[f64],
        halo: usize,
        nodes: std::ops::Range<usize>,
        mut sink: impl FnMut(usize, [f64; LANES]),
    ) {
        let end = nodes.end;
        let mut node = nodes.start;
        while node < end {
            let class_index = self.class_of[node];
            let class = &self.classes[usize::from(class_index)];
            let x_of = |n: usize, delta: isize| {
                let first = (n + halo).wrapping_add_signed(delta) * D;
                &x[first..first + D]
            };
            if node + 1 < end && self.class_of[node + 1] == class_index {
                let [first, second] = block_rows::<D, 2>(class, [node, node + 1], x_of);
                sink(node, first);
                sink(node + 1, second);
                node += 2;
                continue;
            }
            let [row] = block_rows::<D, 1>(class, [node], x_of);
            sink(node, row);
            node += 1;
        }
    }

    /// `y = A x`, returning `xᵀ y`; nodes in parallel tasks of [`nodes_per_task`].
    pub fn mul_dot(&self, x: &[f64], y: &mut [f64]) -> f64 {
        self.mul_dot_with_halo(x, 0, y)
    }

    /// `y = A x` on this operator's rows when `x` holds `halo` nodes before the first row's
    /// (and enough after the last row's for its blocks): the product of a slab of layers
    /// ([`Stencil::layers`]) with its neighbours' layers around it, returning the rows' part of
    /// `xᵀ y`. Every row is computed as [`Stencil::mul_dot`] computes it on the whole box.
    pub fn mul_dot_with_halo(&self, x: &[f64], halo: usize, y: &mut [f64]) -> f64 {
        match self.dim {
            2 => self.mul_dot_of::<2>(x, halo, y),
            _ => self.mul_dot_of::<3>(x, halo, y),
        }
    }

    fn mul_dot_of<const D: usize>(&self, x: &[f64], halo: usize, y: &mut [f64]) -> f64 {
        let per_task = nodes_per_task(self.class_of.len());
        let partial: Vec<f64> = y
            .par_chunks_mut(per_task * D)
            .enumerate()
            .map(|(task, ys)| self.mul_dot_task::<D>(x, halo, task * per_task, ys))
            .collect();
        partial.iter().sum()
    }

    /// [`Stencil::mul_dot_task_portable`], compiled for AVX2 when the processor has it: the
    /// same multiplies and adds in the same order (no fused multiply-add), so the result is
    /// the same bit for bit, four lanes at a time instead of two.
    fn mul_dot_task<const D: usize>(
        &self,
        x: &[f64],
        halo: usize,
        first: usize,
        ys: &mut [f64],
    ) -> f64 {
        #[cfg(target_arch = "x86_64")]
        if std::arch::is_x86_feature_detected!("avx2") {
            // SAFETY: `mul_dot_task_avx2` only requires AVX2, which the processor has (checked
            // just above).
            return unsafe { self.mul_dot_task_avx2::<D>(x, halo, first, ys) };
        }
        self.mul_dot_task_portable::<D>(x, halo, first, ys)
    }

    #[cfg(target_arch = "x86_64")]
    #[target_feature(enable = "avx2")]
    fn mul_dot_task_avx2<const D: usize>(
        &self,
        x: &[f64],
        halo: usize,
        first: usize,
        ys: &mut [f64],
    ) -> f64 {
        self.mul_dot_task_portable::<D>(x, halo, first, ys)
    }

    /// `y = A x` on the nodes from `first` (`ys` their rows), returning their part of `xᵀ y`.
    #[inline(always)]
    fn mul_dot_task_portable<const D: usize>(
        &self,
        x: &[f64],
        halo: usize,
        first: usize,
        ys: &mut [f64],
    ) -> f64 {
        let mut xy = 0.0;
        self.rows::<D>(x, halo, first..first + ys.len() / D, |node, row| {
            let k = (node - first) * D;
            ys[k..k + D].copy_from_slice(&row[..D]);
            xy += row_dot::<D>(&row, x, node + halo);
        });
        xy
    }

    /// The bilinear form `xᵀ A y`, without allocation.
    pub fn bilinear_form(&self, x: &[f64], y: &[f64]) -> f64 {
        match self.dim {
            2 => self.bilinear_form_of::<2>(x, y),
            _ => self.bilinear_form_of::<3>(x, y),
        }
    }

    fn bilinear_form_of<const D: usize>(&self, x: &[f64], y: &[f64]) -> f64 {
        let n_nodes = self.class_of.len();
        let per_task = nodes_per_task(n_nodes);
        let partial: Vec<f64> = (0..n_nodes.div_ceil(per_task))
            .into_par_iter()
            .map(|task| {
                let first = task * per_task;
                self.bilinear_form_task::<D>(x, y, first..(first + per_task).min(n_nodes))
            })
            .collect();
        partial.iter().sum()
    }

    /// [`Stencil::bilinear_form_task_portable`], compiled for AVX2 when the processor has it
    /// (the same operations in the same order, as [`Stencil::mul_dot_task`]).
    fn bilinear_form_task<const D: usize>(&self, x: &[f64], y: &[f64], nodes: Range<usize>) -> f64 {
        #[cfg(target_arch = "x86_64")]
        if std::arch::is_x86_feature_detected!("avx2") {
            // SAFETY: `bilinear_form_task_avx2` only requires AVX2, which the processor has
            // (checked just above).
            return unsafe { self.bilinear_form_task_avx2::<D>(x, y, nodes) };
        }
        self.bilinear_form_task_portable::<D>(x, y, nodes)
    }

    #[cfg(target_arch = "x86_64")]
    #[target_feature(enable = "avx2")]
    fn bilinear_form_task_avx2<const D: usize>(
        &self,
        x: &[f64],
        y: &[f64],
        nodes: Range<usize>,
    ) -> f64 {
        self.bilinear_form_task_portable::<D>(x, y, nodes)
    }

    /// The part of `xᵀ A y` of the rows of `nodes`.
    #[inline(always)]
    fn bilinear_form_task_portable<const D: usize>(
        &self,
        x: &[f64],
        y: &[f64],
        nodes: Range<usize>,
    ) -> f64 {
        let mut total = 0.0;
        self.rows::<D>(y, 0, nodes, |node, row| {
            total += row_dot::<D>(&row, x, node)
        });
        total
    }
}

/// `(A y)_node · x_node`: the first `D` entries of a row block (`row`) against node `node`'s
/// entries of `x`.
#[inline(always)]
fn row_dot<const D: usize>(row: &[f64; LANES], x: &[f64], node: usize) -> f64 {
    row[..D]
        .iter()
        .zip(&x[node * D..])
        .map(|(a, b)| a * b)
        .sum::<f64>()
}

/// The rows `(A x)_n` of the `N` nodes `nodes`, all of class `class`, through their blocks
/// together (each block's columns loaded once for the `N` nodes): per node, the block's columns
/// summed into two sets of accumulators, even blocks into one and odd into the other, then
/// [`row_sum`] ([`Stencil::rows`]). `x_of(n, o)` is node `n + o`'s entries of `x`.
#[inline(always)]
fn block_rows<'x, const D: usize, const N: usize>(
    class: &NodeClass,
    nodes: [usize; N],
    x_of: impl Fn(usize, isize) -> &'x [f64],
) -> [[f64; LANES]; N] {
    let mut acc = [[[[0.0; LANES]; D]; 2]; N];
    let mut blocks = class
        .offsets
        .iter()
        .zip(class.columns.chunks_exact(D * LANES));
    while let Some((&even, columns)) = blocks.next() {
        for (acc, &n) in acc.iter_mut().zip(&nodes) {
            add_block(&mut acc[0], x_of(n, even), columns);
        }
        match blocks.next() {
            Some((&odd, columns)) => {
                for (acc, &n) in acc.iter_mut().zip(&nodes) {
                    add_block(&mut acc[1], x_of(n, odd), columns);
                }
            }
            None => break,
        }
    }
    acc.map(|acc| row_sum(&acc))
}

/// `Σ_c (acc[0][c] + acc[1][c])`: a row block's result from its two sets of column
/// accumulators ([`Stencil::rows`]).
#[inline(always)]
fn row_sum<const D: usize>(acc: &[[[f64; LANES]; D]; 2]) -> [f64; LANES] {
    let mut row = [0.0; LANES];
    for (even, odd) in acc[0].iter().zip(&acc[1]) {
        for ((r, e), o) in row.iter_mut().zip(even).zip(odd) {
            *r += e + o;
        }
    }
    row
}

/// `sum[c] += B[:, c] · x_c` for the columns `c` of one block (`columns`, [`LANES`] apart).
#[inline(always)]
fn add_block<const D: usize>(sum: &mut [[f64; LANES]; D], xs: &[f64], columns: &[f64]) {
    for ((&xc, column), sum) in xs.iter().zip(columns.chunks_exact(LANES)).zip(sum) {
        for (a, entry) in sum.iter_mut().zip(column) {
            *a += entry * xc;
        }
    }
}

/// The class key of the kept node at grid `index`: per axis, whether it is the first node,
/// the last (for the last axis: the last kept, below the eliminated face) and, along the last
/// axis, the second (its element below is the first layer, which `M^mod` leaves out). Nodes
/// with one key have the same blocks.
fn class_key(dim: usize, counts: &[usize], index: &[usize; 3]) -> u16 {
    let mut key = 0u16;
    for k in 0..dim {
        let last = k + 1 == dim;
        let top = if last { counts[k] - 1 } else { counts[k] };
        let flags = u16::from(index[k] == 0)
            | u16::from(index[k] == top) << 1
            | u16::from(last && index[k] == 1) << 2;
        key |= flags << (3 * k);
    }
    key
}

/// The blocks of the node at grid `index`, summed over the elements around it.
fn node_class(
    dim: usize,
    counts: &[usize],
    nodes_per_axis: &[usize; 3],
    index: &[usize; 3],
    entry: &impl Fn(usize, usize) -> f64,
    without_first_layer: bool,
) -> NodeClass {
    let mut blocks: Vec<(isize, [f64; 9])> = Vec::new();
    let stride = |k: usize| nodes_per_axis[..k].iter().product::<usize>() as isize;
    // Side bit `k` set: the element above the node along axis `k` (the node is its lower
    // corner there); clear: the element below (the node is its upper corner).
    for side in 0..1usize << dim {
        let exists = (0..dim).all(|k| {
            let above = side >> k & 1 == 1;
            let layer_ok = if above {
                index[k] < counts[k]
            } else {
                index[k] > 0
            };
            let layer = if above {
                index[k]
            } else {
                index[k].wrapping_sub(1)
            };
            layer_ok && !(k + 1 == dim && without_first_layer && layer == 0)
        });
        if !exists {
            continue;
        }
        let own_bits = !side & ((1 << dim) - 1);
        let a = corner_of_bits(dim, own_bits);
        for other_bits in 0..1usize << dim {
            let offset: Vec<isize> = (0..dim)
                .map(|k| (other_bits >> k & 1) as isize - (own_bits >> k & 1) as isize)
                .collect();
            // The neighbour above the last kept layer is on the eliminated face.
            if offset[dim - 1] == 1 && index[dim - 1] + 1 == counts[dim - 1] {
                continue;
            }
            let delta: isize = (0..dim).map(|k| offset[k] * stride(k)).sum();
            let b = corner_of_bits(dim, other_bits);
            let slot = match blocks.iter().position(|(o, _)| *o == delta) {
                Some(s) => s,
                None => {
                    blocks.push((delta, [0.0; 9]));
                    blocks.len() - 1
                }
            };
            for r in 0..dim {
                for c in 0..dim {
                    blocks[slot].1[r * dim + c] += entry(a * dim + r, b * dim + c);
                }
            }
        }
    }
    blocks.retain(|(_, b)| b.iter().any(|&v| v != 0.0));
    blocks.sort_by_key(|(o, _)| *o);
    NodeClass::new(dim, blocks)
}

/// `a·p + b·q` blockwise, for `dim` components.
fn combine(dim: usize, p: &NodeClass, a: f64, q: &NodeClass, b: f64) -> NodeClass {
    let mut blocks: Vec<(isize, [f64; 9])> = p
        .blocks
        .iter()
        .map(|(o, block)| (*o, block.map(|v| a * v)))
        .collect();
    for (o, block) in &q.blocks {
        match blocks.iter_mut().find(|(p_o, _)| p_o == o) {
            Some((_, sum)) => sum.iter_mut().zip(block).for_each(|(s, v)| *s += b * v),
            None => blocks.push((*o, block.map(|v| b * v))),
        }
    }
    blocks.sort_by_key(|(o, _)| *o);
    NodeClass::new(dim, blocks)
}

/// The grid point of a lexicographic node index (first coordinate fastest).
fn unflatten(mut flat: usize, sizes: &[usize; 3]) -> [usize; 3] {
    let mut index = [0; 3];
    for (k, &n) in sizes.iter().enumerate() {
        index[k] = flat % n;
        flat /= n;
    }
    index
}
