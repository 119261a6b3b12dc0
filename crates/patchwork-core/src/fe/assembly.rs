//! Assembly of the model's potential Π, its gradient and the lower triangle
//! of its Hessian over the triangles, on one thread or several.
//!
//! Each triangle's share is computed alone: its energy less the pressure's
//! work, its nine nodal forces, and its tangent entries, which go straight to
//! the triangle's own slots of the value array (every triangle fills a fixed
//! run of [`Model::pattern`], at `value_offsets[t]`). The energies and forces
//! are then summed over the triangles in their order, so Π and ∇Π are the same
//! to the last bit whatever the thread count: threads change the wall time of
//! a solve, never its result.

use faer::sparse::Pair;

use super::model::Model;
use super::pressure::{volume, volume_gradient, volume_hessian};
use super::section::Section;
use crate::curve::Point;
use crate::parallel::{nested, ranges, run_marked};

/// One triangle's energy less the pressure's work, and its nodal forces less
/// the pressure's (node a's at `3a..3a + 3`).
type Share = (f64, [f64; 9]);

/// Work on a range of triangles, with their items and tangent slots.
type RangeWork<'a, T> =
    dyn Fn(std::ops::Range<usize>, &mut [T], &mut [f64]) -> Option<()> + Sync + 'a;

impl Model {
    /// Where each triangle's tangent entries start in [`Model::pattern`]
    /// order, and (last) where the shift slots start.
    pub(super) fn entry_offsets(&self) -> Vec<usize> {
        let mut offsets = Vec::with_capacity(self.triangles.len() + 1);
        let mut next = 0;
        for t in 0..self.triangles.len() {
            offsets.push(next);
            self.triangle_entries(t, |_, _, _, _| next += 1);
        }
        offsets.push(next);
        offsets
    }

    /// Total potential Π; +∞ outside the materials' domain.
    pub fn potential(&self, x: &[Point], sections: &[Section]) -> f64 {
        let mut energies = vec![0.0; self.triangles.len()];
        self.in_chunks(&mut energies, &mut [], &|range, energies, _| {
            for (t, energy) in range.zip(energies) {
                let tri = &self.triangles[t];
                *energy = tri.energy(&self.corners(x, t), &sections[t], &self.materials);
            }
            Some(())
        });
        let strain = energies.iter().fold(0.0, |sum, e| sum + e);
        match strain.is_finite() {
            true => strain - self.load() * self.volume(x),
            false => f64::INFINITY,
        }
    }

    /// The (lower-triangle) sparsity pattern in the order [`Model::assemble`]
    /// fills values, followed by one diagonal entry per DOF (for shifts).
    pub fn pattern(&self) -> Vec<Pair<usize, usize>> {
        let mut pairs = Vec::new();
        for t in 0..self.triangles.len() {
            self.triangle_entries(t, |_, _, row, col| pairs.push(Pair::new(row, col)));
        }
        pairs.extend((0..self.dof_count).map(|i| Pair::new(i, i)));
        pairs
    }

    /// Visits (local row, local col in the 9×9 element matrix, global row,
    /// global col) for every lower-triangle entry of triangle `t` between free
    /// DOFs, in a fixed order: the same order for the pattern and the values.
    fn triangle_entries(&self, t: usize, mut visit: impl FnMut(usize, usize, usize, usize)) {
        let nodes = self.triangles[t].nodes;
        for (a, &node_a) in nodes.iter().enumerate() {
            let Some(da) = self.dof[node_a] else {
                continue;
            };
            for (b, &node_b) in nodes.iter().enumerate() {
                let Some(db) = self.dof[node_b] else {
                    continue;
                };
                for i in 0..3 {
                    for j in 0..3 {
                        if da + i >= db + j {
                            visit(3 * a + i, 3 * b + j, da + i, db + j);
                        }
                    }
                }
            }
        }
    }

    /// Π, its gradient and the lower triangle of its Hessian (values in
    /// [`Model::pattern`] order, shift entries set to `shift`). `None` when a
    /// material leaves its domain.
    pub fn assemble(
        &self,
        x: &[Point],
        sections: &[Section],
        shift: f64,
        gradient: &mut [f64],
        values: &mut Vec<f64>,
    ) -> Option<f64> {
        self.assemble_at(x, sections, self.pressure, shift, gradient, values)
    }

    /// [`Model::assemble`] at an explicit pressure (MPa; the facets loaded
    /// with it times [`Model::load_factor`]): volume control treats the
    /// pressure as an unknown.
    pub fn assemble_at(
        &self,
        x: &[Point],
        sections: &[Section],
        pressure: f64,
        shift: f64,
        gradient: &mut [f64],
        values: &mut Vec<f64>,
    ) -> Option<f64> {
        let load = pressure * self.load_factor;
        let entries = self.value_offsets[self.triangles.len()];
        values.clear();
        values.resize(entries, 0.0);
        let mut shares: Vec<Share> = vec![(0.0, [0.0; 9]); self.triangles.len()];
        self.in_chunks(&mut shares, values, &|range, shares, values| {
            let first = self.value_offsets[range.start];
            for (t, share) in range.zip(shares) {
                let slots = self.value_offsets[t] - first..self.value_offsets[t + 1] - first;
                *share = self.triangle_share(x, t, &sections[t], load, &mut values[slots])?;
            }
            Some(())
        })?;
        // Summed in triangle order on one thread or many: the same bits.
        gradient.fill(0.0);
        let mut potential = 0.0;
        for (tri, (energy, forces)) in self.triangles.iter().zip(&shares) {
            potential += energy;
            for (a, &node) in tri.nodes.iter().enumerate() {
                if let Some(d) = self.dof[node] {
                    for i in 0..3 {
                        gradient[d + i] += forces[3 * a + i];
                    }
                }
            }
        }
        values.extend(std::iter::repeat_n(shift, self.dof_count));
        Some(potential)
    }

    /// Triangle `t`'s share of Π and ∇Π under the pressure load `load`, its
    /// tangent entries written to `slots`.
    fn triangle_share(
        &self,
        x: &[Point],
        t: usize,
        section: &Section,
        load: f64,
        slots: &mut [f64],
    ) -> Option<Share> {
        let corners = self.corners(x, t);
        let (w, force, mut k) = self.triangles[t].evaluate(&corners, section, &self.materials)?;
        let dv = volume_gradient(&corners);
        k -= load * volume_hessian(&corners);
        let mut forces = [0.0; 9];
        for a in 0..3 {
            for i in 0..3 {
                forces[3 * a + i] = force[(i, a)] - load * dv[(i, a)];
            }
        }
        let mut slot = slots.iter_mut();
        self.triangle_entries(t, |i, j, _, _| {
            if let Some(value) = slot.next() {
                *value = k[(i, j)];
            }
        });
        Some((w - load * volume(&corners), forces))
    }

    /// Runs `work` over the triangles split into up to `self.threads`
    /// contiguous ranges, one thread each (all on the calling thread when
    /// one is asked for or the caller is a parallel loop's), each with its
    /// items of `per_triangle` and its run of `values` (the tangent slots of
    /// its triangles; `values` empty: none). `None` when any range's work is.
    fn in_chunks<T: Send>(
        &self,
        per_triangle: &mut [T],
        values: &mut [f64],
        work: &RangeWork<'_, T>,
    ) -> Option<()> {
        let count = self.triangles.len();
        if self.threads.min(count) <= 1 || nested() {
            return work(0..count, per_triangle, values);
        }
        let mut jobs = Vec::with_capacity(self.threads);
        let (mut items, mut slots) = (per_triangle, values);
        for range in ranges(self.triangles.len(), self.threads) {
            let (mine, rest) = items.split_at_mut(range.len());
            let taken = match slots.is_empty() {
                true => 0,
                false => self.value_offsets[range.end] - self.value_offsets[range.start],
            };
            let (my_slots, other_slots) = slots.split_at_mut(taken);
            jobs.push((range, mine, my_slots));
            (items, slots) = (rest, other_slots);
        }
        let done = run_marked(jobs, &|(range, mine, my_slots)| work(range, mine, my_slots));
        done.into_iter().collect()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::design::Design;
    use crate::fe::mesh::{MeshSpec, TubeMesh};
    use crate::fe::section::CutElements;
    use crate::fe::{SimulateOptions, simulate};

    /// Splitting the triangles over threads changes nothing, to the last
    /// bit: Π, ∇Π, the tangent and the energy alone, at an inflated state
    /// moved off equilibrium (so every term is non-zero).
    #[test]
    fn every_thread_count_assembles_the_same_bits() {
        let design = Design::one_patch_test_scene();
        let options = SimulateOptions {
            mesh: MeshSpec::uniform(2.0),
            ..SimulateOptions::default()
        };
        let solved = simulate(&design, &options).unwrap();
        let x: Vec<Point> = (solved.positions.iter().enumerate())
            .map(|(i, p)| p + Point::new(0.0, 0.0, 0.01 * (i as f64 * 0.7).sin()))
            .collect();
        let mesh = TubeMesh::for_design(&design, options.mesh);
        let model = Model::new(&design, mesh, CutElements::default());
        let assembled = |threads: usize| {
            let model = model.clone().with_threads(threads);
            let (mut gradient, mut values) = (vec![0.0; model.dof_count], Vec::new());
            let potential = model
                .assemble(&x, &model.sections, 0.5, &mut gradient, &mut values)
                .unwrap();
            let energy = model.potential(&x, &model.sections);
            (potential.to_bits(), energy.to_bits(), gradient, values)
        };
        let one = assembled(1);
        assert_eq!(one.3.len(), model.pattern().len());
        assert!(one.2.iter().any(|g| g.abs() > 1e-6));
        for threads in [2, 3, 7] {
            assert!(one == assembled(threads), "{threads} threads differ");
        }
    }
}
