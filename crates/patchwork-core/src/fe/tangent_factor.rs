//! Sparse Cholesky factorisation of the Newton tangent, with everything that
//! depends only on the sparsity pattern done once per model.
//!
//! Once, at construction: a fill-reducing ordering (faer's AMD), the tangent's
//! pattern *already permuted* into that ordering and stored as the compressed
//! columns the numeric factorisation reads, the slot in those columns of every
//! triplet the assembly writes, and the symbolic factorisation (identity
//! ordering of the permuted pattern). The assembly's triplets (45 per
//! triangle, each distinct entry written by about three) are sorted once,
//! into the distinct entries and each triplet's entry; the ordering moves
//! only the distinct entries, and a triplet's slot is its entry's. A graded
//! mesh is new with every design, so a design run builds dozens of these:
//! sorting the triplets three times and finding each slot by binary search
//! took 5 % of a Hilbert `standard` run's samples (`perf`), and the run
//! 3–5 % longer (docs/studies.md, "Where a design's time goes").
//!
//! Per factorisation: scatter-add the assembly's triplets into their slots and
//! factor in place into a buffer allocated once per solve — no sorting, no
//! permuting of the matrix and no allocation. faer's general entry point spends
//! a third of a 2 mm factorisation on those (measured with `perf` on the
//! Hilbert scene: sorting triplets into a new matrix 8 %, permuting it 7 %,
//! copies 4 %).
//!
//! Solves permute the right-hand side into the factor's ordering and back.

use faer::dyn_stack::{MemBuffer, MemStack};
use faer::linalg::cholesky::llt::factor::LltRegularization;
use faer::sparse::linalg::cholesky::{
    CholeskySymbolicParams, LltRef, SymbolicCholesky, SymmetricOrdering,
    factorize_symbolic_cholesky,
};
use faer::sparse::linalg::{SupernodalThreshold, amd};
use faer::sparse::{Pair, SparseColMatRef, SymbolicSparseColMat};
use faer::{Conj, MatMut, Par, Side};

/// The pattern-only part: ordering, permuted pattern, slots, symbolic factor.
pub struct TangentPattern {
    n: usize,
    /// `forward[i]`: the original unknown at position `i` of the factor's ordering.
    forward: Vec<usize>,
    /// The permuted pattern's lower triangle, as the supernodal numeric
    /// factorisation reads it without transposing.
    columns: SymbolicSparseColMat<usize>,
    /// For triplet `k` of the assembly, its index in the column values.
    slot: Vec<usize>,
    symbolic: SymbolicCholesky<usize>,
}

/// The numeric part, allocated once per solve and refilled per factorisation.
pub struct TangentFactor<'p> {
    pattern: &'p TangentPattern,
    column_values: Vec<f64>,
    factor_values: Vec<f64>,
    scratch: MemBuffer,
    permuted: Vec<f64>,
}

impl TangentPattern {
    /// `pairs`: the (row, col) of each triplet the assembly writes, row ≥ col
    /// (lower triangle), duplicates summed.
    pub fn new(n: usize, pairs: &[Pair<usize, usize>]) -> Result<TangentPattern, String> {
        // The distinct entries, and which one each triplet adds to.
        let (original, entry_of) = indexed_columns(n, pairs.iter().map(|p| (p.row, p.col)))?;
        let mut forward = vec![0usize; n];
        let mut inverse = vec![0usize; n];
        let nnz = original.row_idx().len();
        amd::order(
            &mut forward,
            &mut inverse,
            original.as_ref(),
            amd::Control::default(),
            MemStack::new(&mut MemBuffer::new(amd::order_scratch::<usize>(n, nnz))),
        )
        .map_err(|e| format!("{e:?}"))?;
        // Each distinct entry moved into the ordering, in the lower triangle;
        // the permutation keeps them distinct.
        let permuted = entries(&original).map(|(row, col)| {
            let (r, c) = (inverse[row], inverse[col]);
            (r.max(c), r.min(c))
        });
        let (columns, position) = indexed_columns(n, permuted)?;
        // Supernodal, forced: on these tangents faster than faer's default
        // choice, simplicial (Hilbert scene, cold solve: 2 mm 15 % less CPU
        // time, 1 mm 1.8 → 1.2 s). Without a permutation faer's symbolic
        // factorisation reads the upper triangle whatever side it is told; the
        // supernodal numeric factorisation reads the lower one.
        let upper = transposed(&columns);
        let symbolic = factorize_symbolic_cholesky(
            upper.as_ref(),
            Side::Upper,
            SymmetricOrdering::Identity,
            CholeskySymbolicParams {
                supernodal_flop_ratio_threshold: SupernodalThreshold::FORCE_SUPERNODAL,
                ..Default::default()
            },
        )
        .map_err(|e| format!("{e:?}"))?;
        let slot = entry_of.iter().map(|&entry| position[entry]).collect();
        Ok(TangentPattern {
            n,
            forward,
            columns,
            slot,
            symbolic,
        })
    }

    /// Buffers for the factorisations of one solve.
    pub fn factor(&self) -> TangentFactor<'_> {
        let factor = self
            .symbolic
            .factorize_numeric_llt_scratch::<f64>(Par::Seq, Default::default());
        let solve = self.symbolic.solve_in_place_scratch::<f64>(1, Par::Seq);
        TangentFactor {
            pattern: self,
            column_values: vec![0.0; self.columns.row_idx().len()],
            factor_values: vec![0.0; self.symbolic.len_val()],
            scratch: MemBuffer::new(factor.or(solve)),
            permuted: vec![0.0; self.n],
        }
    }
}

impl TangentFactor<'_> {
    /// Number of unknowns.
    pub fn dimension(&self) -> usize {
        self.pattern.n
    }

    /// Factors the matrix whose triplets (in the pattern's order) are
    /// `values`. `false` when it is not numerically positive definite.
    pub fn factorise(&mut self, values: &[f64]) -> bool {
        let pattern = self.pattern;
        self.column_values.fill(0.0);
        for (&slot, &v) in pattern.slot.iter().zip(values) {
            self.column_values[slot] += v;
        }
        let matrix = SparseColMatRef::new(pattern.columns.as_ref(), &self.column_values);
        pattern
            .symbolic
            .factorize_numeric_llt(
                &mut self.factor_values,
                matrix,
                Side::Lower,
                LltRegularization::default(),
                Par::Seq,
                MemStack::new(&mut self.scratch),
                Default::default(),
            )
            .is_ok()
    }

    /// Solves K x = b in place, with K the last successful factorisation.
    pub fn solve_in_place(&mut self, b: &mut [f64]) {
        let pattern = self.pattern;
        for (y, &f) in self.permuted.iter_mut().zip(&pattern.forward) {
            *y = b[f];
        }
        let llt = LltRef::new(&pattern.symbolic, &self.factor_values);
        llt.solve_in_place_with_conj(
            Conj::No,
            MatMut::from_column_major_slice_mut(&mut self.permuted, pattern.n, 1),
            Par::Seq,
            MemStack::new(&mut self.scratch),
        );
        for (y, &f) in self.permuted.iter().zip(&pattern.forward) {
            b[f] = *y;
        }
    }
}

/// Compressed columns (rows sorted, duplicates merged) of the entries
/// `(row, col)`, and for each entry, in the order given, its index in the
/// columns' values. Entries are bucketed by column and each short column
/// sorted on its own (a tangent's column holds a few dozen entries, so this
/// is linear in the entry count), each as its row and its place in the
/// input packed into one integer.
fn indexed_columns(
    n: usize,
    entries: impl Iterator<Item = (usize, usize)> + Clone,
) -> Result<(SymbolicSparseColMat<usize>, Vec<usize>), String> {
    let mut start = vec![0usize; n + 1];
    for (_, c) in entries.clone() {
        start[c + 1] += 1;
    }
    for c in 0..n {
        start[c + 1] += start[c];
    }
    let count = start[n];
    if n > u32::MAX as usize || count > u32::MAX as usize {
        return Err(format!(
            "a tangent of {n} unknowns and {count} entries is too large"
        ));
    }
    let mut bucket = vec![0u64; count];
    let mut fill = start.clone();
    for (k, (r, c)) in entries.enumerate() {
        bucket[fill[c]] = ((r as u64) << 32) | k as u64;
        fill[c] += 1;
    }
    let mut index = vec![0usize; count];
    let mut col_ptr = Vec::with_capacity(n + 1);
    let mut row_idx: Vec<usize> = Vec::with_capacity(count);
    col_ptr.push(0);
    for c in 0..n {
        let column = &mut bucket[start[c]..start[c + 1]];
        column.sort_unstable();
        let first = row_idx.len();
        for &packed in column.iter() {
            let r = (packed >> 32) as usize;
            if row_idx.len() == first || row_idx.last() != Some(&r) {
                row_idx.push(r);
            }
            index[(packed & u64::from(u32::MAX)) as usize] = row_idx.len() - 1;
        }
        col_ptr.push(row_idx.len());
    }
    let columns = SymbolicSparseColMat::new_checked(n, n, col_ptr, None, row_idx);
    Ok((columns, index))
}

/// The `(row, col)` of every stored entry of `columns`, column by column.
fn entries(columns: &SymbolicSparseColMat<usize>) -> impl Iterator<Item = (usize, usize)> + Clone {
    let (col_ptr, row_idx) = (columns.col_ptr(), columns.row_idx());
    (0..columns.ncols()).flat_map(move |c| {
        row_idx[col_ptr[c]..col_ptr[c + 1]]
            .iter()
            .map(move |&r| (r, c))
    })
}

/// The transpose of `columns` (rows sorted, as a column-by-column scan
/// writes them).
fn transposed(columns: &SymbolicSparseColMat<usize>) -> SymbolicSparseColMat<usize> {
    let n = columns.nrows();
    let mut col_ptr = vec![0usize; n + 1];
    for &r in columns.row_idx() {
        col_ptr[r + 1] += 1;
    }
    for r in 0..n {
        col_ptr[r + 1] += col_ptr[r];
    }
    let mut fill = col_ptr.clone();
    let mut row_idx = vec![0usize; columns.row_idx().len()];
    for (r, c) in entries(columns) {
        row_idx[fill[r]] = c;
        fill[r] += 1;
    }
    SymbolicSparseColMat::new_checked(columns.ncols(), n, col_ptr, None, row_idx)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A 1-D Laplacian plus identity, given as duplicated element triplets
    /// (two-node elements), as the assembly writes them.
    fn chain(n: usize, diagonal: f64) -> (Vec<Pair<usize, usize>>, Vec<f64>) {
        let mut pairs = Vec::new();
        let mut values = Vec::new();
        for e in 0..n - 1 {
            for (r, c, v) in [(e, e, 1.0), (e + 1, e, -1.0), (e + 1, e + 1, 1.0)] {
                pairs.push(Pair::new(r, c));
                values.push(v);
            }
        }
        for i in 0..n {
            pairs.push(Pair::new(i, i));
            values.push(diagonal);
        }
        (pairs, values)
    }

    #[test]
    fn solves_a_summed_triplet_matrix() {
        let n = 40;
        let (pairs, values) = chain(n, 0.5);
        let pattern = TangentPattern::new(n, &pairs).expect("pattern");
        let mut factor = pattern.factor();
        assert!(factor.factorise(&values));
        let x: Vec<f64> = (0..n).map(|i| (i as f64 * 0.37).sin()).collect();
        // b = K x with K from the triplets.
        let mut b = vec![0.0; n];
        for (p, v) in pairs.iter().zip(&values) {
            b[p.row] += v * x[p.col];
            if p.row != p.col {
                b[p.col] += v * x[p.row];
            }
        }
        factor.solve_in_place(&mut b);
        for (got, want) in b.iter().zip(&x) {
            assert!((got - want).abs() < 1e-12, "{got} vs {want}");
        }
    }

    #[test]
    fn every_triplet_adds_to_its_own_entry_in_the_ordering() {
        // A 2-D grid's lower triangle, each entry given two or three times
        // in a scrambled order, as overlapping elements write it.
        let side = 9;
        let n = side * side;
        let mut pairs = Vec::new();
        for i in 0..n {
            for j in [i, i + 1, i + side, i + side + 1] {
                if j < n {
                    for _ in 0..2 + (i + j) % 2 {
                        pairs.push(Pair::new(j.max(i), j.min(i)));
                    }
                }
            }
        }
        let len = pairs.len();
        let scrambled: Vec<_> = (0..len).map(|k| pairs[(k * 37) % len]).collect();
        assert_ne!(
            len % 37,
            0,
            "37 is prime to the count, so each triplet appears once"
        );
        let pattern = TangentPattern::new(n, &scrambled).expect("pattern");
        let mut inverse = vec![0; n];
        for (i, &f) in pattern.forward.iter().enumerate() {
            inverse[f] = i;
        }
        let (col_ptr, row_idx) = (pattern.columns.col_ptr(), pattern.columns.row_idx());
        for c in 0..n {
            let column = &row_idx[col_ptr[c]..col_ptr[c + 1]];
            assert!(
                column.windows(2).all(|w| w[0] < w[1]),
                "column {c} sorted, distinct"
            );
            assert!(
                column.iter().all(|&r| r >= c),
                "column {c} in the lower triangle"
            );
        }
        let distinct: std::collections::BTreeSet<_> =
            scrambled.iter().map(|p| (p.row, p.col)).collect();
        assert_eq!(row_idx.len(), distinct.len());
        for (p, &slot) in scrambled.iter().zip(&pattern.slot) {
            let (r, c) = (inverse[p.row], inverse[p.col]);
            let (row, col) = (r.max(c), r.min(c));
            assert!((col_ptr[col]..col_ptr[col + 1]).contains(&slot));
            assert_eq!(row_idx[slot], row);
        }
    }

    #[test]
    fn reports_an_indefinite_matrix() {
        let n = 10;
        let (pairs, values) = chain(n, -0.5);
        let pattern = TangentPattern::new(n, &pairs).expect("pattern");
        assert!(!pattern.factor().factorise(&values));
    }
}
