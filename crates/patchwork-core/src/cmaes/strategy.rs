//! The CMA-ES step: `ask` samples a population, `tell` updates the
//! distribution from their ranked fitness. Dynamic state only; the static
//! parameters live in [`StrategyParams`].

use nalgebra::{DMatrix, DVector};
use serde::{Deserialize, Serialize};

use super::params::StrategyParams;
use super::rng::SeededRng;

/// The evolving distribution N(m, σ² C) and its evolution paths.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct CmaEs {
    pub params: StrategyParams,
    pub mean: DVector<f64>,
    pub sigma: f64,
    /// Evolution path of the step size.
    pub ps: DVector<f64>,
    /// Evolution path of the covariance.
    pub pc: DVector<f64>,
    pub covariance: DMatrix<f64>,
    /// C = B diag(d²) Bᵀ, refreshed lazily.
    eigenbasis: DMatrix<f64>,
    eigenroots: DVector<f64>,
    pub evaluations: usize,
    eigen_evaluation: usize,
    pub generation: usize,
    rng: SeededRng,
}

impl CmaEs {
    /// Starts at `mean` with step size `sigma`; `rng` is the only source of
    /// randomness, so a seed reproduces the run exactly.
    pub fn new(mean: Vec<f64>, sigma: f64, lambda: Option<usize>, rng: SeededRng) -> CmaEs {
        let n = mean.len();
        let params = StrategyParams::new(n, lambda);
        CmaEs {
            params,
            mean: DVector::from_vec(mean),
            sigma,
            ps: DVector::zeros(n),
            pc: DVector::zeros(n),
            covariance: DMatrix::identity(n, n),
            eigenbasis: DMatrix::identity(n, n),
            eigenroots: DVector::from_element(n, 1.0),
            evaluations: 0,
            eigen_evaluation: 0,
            generation: 0,
            rng,
        }
    }

    pub fn dimension(&self) -> usize {
        self.params.dimension
    }

    /// λ new candidates xₖ = m + σ B (d ∘ zₖ), zₖ ~ N(0, I).
    pub fn ask(&mut self) -> Vec<Vec<f64>> {
        let n = self.dimension();
        (0..self.params.lambda)
            .map(|_| {
                let z = DVector::from_fn(n, |_, _| self.rng.normal());
                let y = &self.eigenbasis * z.component_mul(&self.eigenroots);
                (&self.mean + self.sigma * y).as_slice().to_vec()
            })
            .collect()
    }

    /// Updates the distribution from the candidates of the last `ask` and their
    /// fitness (lower is better). Non-finite fitness ranks last.
    pub fn tell(&mut self, candidates: &[Vec<f64>], fitness: &[f64]) {
        let p = &self.params;
        let n = p.dimension as f64;
        self.evaluations += candidates.len();
        self.generation += 1;
        let mut order: Vec<usize> = (0..candidates.len()).collect();
        order.sort_by(|&a, &b| rank_key(fitness[a]).total_cmp(&rank_key(fitness[b])));
        let old_mean = self.mean.clone();
        // Steps of the μ best, in units of σ: yᵢ = (x_{i:λ} − m_old)/σ.
        let steps: Vec<DVector<f64>> = order[..p.mu]
            .iter()
            .map(|&k| (DVector::from_column_slice(&candidates[k]) - &old_mean) / self.sigma)
            .collect();
        // Weighted recombination: m ← m + σ Σ wᵢ yᵢ.
        let mean_step = steps
            .iter()
            .zip(&p.weights)
            .fold(DVector::zeros(p.dimension), |acc, (y, w)| acc + y * *w);
        self.mean = &old_mean + self.sigma * &mean_step;
        // Step-size path in the isotropic frame: C^(−½) y_w = B diag(1/d) Bᵀ y_w.
        let whitened = &self.eigenbasis
            * (self.eigenbasis.transpose() * &mean_step).component_div(&self.eigenroots);
        self.ps = (1.0 - p.cs) * &self.ps + (p.cs * (2.0 - p.cs) * p.mueff).sqrt() * whitened;
        // Stall the covariance path while ‖pσ‖ is large (h_σ), avoiding a too-fast
        // increase of axes when σ is small.
        let generations = (self.evaluations / p.lambda) as f64;
        let ps_norm =
            self.ps.norm() / (1.0 - (1.0 - p.cs).powf(2.0 * generations)).sqrt() / p.chi_n;
        let hsig = if ps_norm < 1.4 + 2.0 / (n + 1.0) {
            1.0
        } else {
            0.0
        };
        self.pc =
            (1.0 - p.cc) * &self.pc + hsig * (p.cc * (2.0 - p.cc) * p.mueff).sqrt() * &mean_step;
        // Covariance: decay, rank-one (pc pcᵀ) and rank-μ (Σ wᵢ yᵢ yᵢᵀ) updates;
        // (1 − hσ) c_c(2 − c_c) compensates the variance lost when pc stalls.
        let decay = 1.0 - p.c1 - p.cmu + (1.0 - hsig) * p.c1 * p.cc * (2.0 - p.cc);
        let mut c = decay * &self.covariance + p.c1 * &self.pc * self.pc.transpose();
        for (y, w) in steps.iter().zip(&p.weights) {
            c += (p.cmu * w) * y * y.transpose();
        }
        self.covariance = (&c + c.transpose()) * 0.5;
        // Cumulative step-size adaptation: grow σ when ‖pσ‖ exceeds E‖N(0,I)‖.
        self.sigma *= ((p.cs / p.damps) * (self.ps.norm() / p.chi_n - 1.0))
            .min(1.0)
            .exp();
        self.refresh_eigen(false);
    }

    /// Recomputes B and d when C has changed enough (every ~n/10·1/(c1+cμ)
    /// evaluations, as purecma), or always when `force`.
    fn refresh_eigen(&mut self, force: bool) {
        let p = &self.params;
        let lag = p.lambda as f64 / ((p.c1 + p.cmu) * p.dimension as f64 * 10.0);
        if !force && ((self.evaluations - self.eigen_evaluation) as f64) < lag {
            return;
        }
        self.eigen_evaluation = self.evaluations;
        let eigen = self.covariance.clone().symmetric_eigen();
        self.eigenroots = eigen.eigenvalues.map(|v| v.max(1e-300).sqrt());
        self.eigenbasis = eigen.eigenvectors;
    }

    /// Condition number of C (ratio of largest to smallest eigenvalue).
    pub fn condition(&self) -> f64 {
        let max = self.eigenroots.max();
        let min = self.eigenroots.min();
        (max / min).powi(2)
    }

    /// Largest standard deviation of the sampling distribution along any axis.
    pub fn max_std(&self) -> f64 {
        self.sigma * self.covariance.diagonal().map(|v| v.max(0.0).sqrt()).max()
    }
}

fn rank_key(f: f64) -> f64 {
    if f.is_nan() { f64::INFINITY } else { f }
}
