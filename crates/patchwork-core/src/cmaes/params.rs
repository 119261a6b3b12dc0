//! Static strategy parameters, computed once from the dimension and population
//! size (Hansen, "The CMA Evolution Strategy: A Tutorial", 2016, table 1; the
//! defaults of purecma).

use serde::{Deserialize, Serialize};

#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct StrategyParams {
    pub dimension: usize,
    /// Population size λ.
    pub lambda: usize,
    /// Parents μ = ⌊λ/2⌋.
    pub mu: usize,
    /// Positive recombination weights wᵢ ∝ ln(μ + ½) − ln i, summing to 1.
    pub weights: Vec<f64>,
    /// Variance-effective selection mass μ_eff = 1/Σwᵢ².
    pub mueff: f64,
    /// Learning rate of the covariance path.
    pub cc: f64,
    /// Learning rate of the step-size path.
    pub cs: f64,
    /// Rank-one update rate.
    pub c1: f64,
    /// Rank-μ update rate.
    pub cmu: f64,
    /// Step-size damping.
    pub damps: f64,
    /// E‖N(0, I)‖ ≈ √n (1 − 1/(4n) + 1/(21n²)).
    pub chi_n: f64,
}

impl StrategyParams {
    /// Default population 4 + ⌊3 ln n⌋ unless `lambda` is given.
    pub fn new(dimension: usize, lambda: Option<usize>) -> StrategyParams {
        let n = dimension as f64;
        let lambda = lambda.unwrap_or(4 + (3.0 * n.ln()).floor() as usize).max(2);
        let mu = lambda / 2;
        let raw: Vec<f64> = (1..=mu)
            .map(|i| (mu as f64 + 0.5).ln() - (i as f64).ln())
            .collect();
        let total: f64 = raw.iter().sum();
        let weights: Vec<f64> = raw.iter().map(|w| w / total).collect();
        let mueff = 1.0 / weights.iter().map(|w| w * w).sum::<f64>();
        let cc = (4.0 + mueff / n) / (n + 4.0 + 2.0 * mueff / n);
        let cs = (mueff + 2.0) / (n + mueff + 5.0);
        let c1 = 2.0 / ((n + 1.3).powi(2) + mueff);
        let cmu = (1.0 - c1).min(2.0 * (mueff - 2.0 + 1.0 / mueff) / ((n + 2.0).powi(2) + mueff));
        let damps = 2.0 * mueff / lambda as f64 + 0.3 + cs;
        let chi_n = n.sqrt() * (1.0 - 1.0 / (4.0 * n) + 1.0 / (21.0 * n * n));
        StrategyParams {
            dimension,
            lambda,
            mu,
            weights,
            mueff,
            cc,
            cs,
            c1,
            cmu,
            damps,
            chi_n,
        }
    }
}
