//! A compact (μ/μ_w, λ)-CMA-ES (Hansen, "The CMA Evolution Strategy: A Tutorial", 2016),
//! minimising a cost over a box-free search space. Callers work in normalised coordinates
//! (each parameter scaled so that 1 is a sensible step) and map back themselves.

use nalgebra::{DMatrix, DVector, SymmetricEigen};
use serde::{Deserialize, Serialize};

/// A small deterministic generator (xorshift64*), so optimiser runs are repeatable by seed.
#[derive(Debug, Clone, Serialize, Deserialize)]
pub struct Rng(u64);

impl Rng {
    pub fn new(seed: u64) -> Self {
        Self(seed.max(1))
    }

    pub fn next_u64(&mut self) -> u64 {
        let mut x = self.0;
        x ^= x >> 12;
        x ^= x << 25;
        x ^= x >> 27;
        self.0 = x;
        x.wrapping_mul(0x2545_f491_4f6c_dd1d)
    }

    /// Uniform in [0, 1).
    pub fn uniform(&mut self) -> f64 {
        (self.next_u64() >> 11) as f64 / (1u64 << 53) as f64
    }

    /// Standard normal (Box–Muller).
    pub fn normal(&mut self) -> f64 {
        let u = self.uniform().max(1e-300);
        let v = self.uniform();
        (-2.0 * u.ln()).sqrt() * (std::f64::consts::TAU * v).cos()
    }
}

/// The optimiser state (serialisable whole, for checkpoints).
#[derive(Debug, Clone, Serialize, Deserialize)]
pub struct CmaEs {
    n: usize,
    lambda: usize,
    mu: usize,
    weights: DVector<f64>,
    mu_eff: f64,
    c_sigma: f64,
    d_sigma: f64,
    c_c: f64,
    c_1: f64,
    c_mu: f64,
    chi_n: f64,
    pub mean: DVector<f64>,
    pub sigma: f64,
    cov: DMatrix<f64>,
    p_sigma: DVector<f64>,
    p_c: DVector<f64>,
    basis: DMatrix<f64>,
    scales: DVector<f64>,
    generation: usize,
    rng: Rng,
}

impl CmaEs {
    /// Start at `mean` with step size `sigma`; `lambda = None` uses the default 4 + ⌊3 ln n⌋.
    pub fn new(mean: Vec<f64>, sigma: f64, lambda: Option<usize>, seed: u64) -> Self {
        let n = mean.len().max(1);
        let nf = n as f64;
        let lambda = lambda
            .unwrap_or(4 + (3.0 * nf.ln()).floor() as usize)
            .max(2);
        let mu = lambda / 2;
        let raw: Vec<f64> = (0..mu)
            .map(|i| ((lambda as f64 + 1.0) / 2.0).ln() - ((i + 1) as f64).ln())
            .collect();
        let sum: f64 = raw.iter().sum();
        let weights = DVector::from_iterator(mu, raw.iter().map(|w| w / sum));
        let mu_eff = 1.0 / weights.iter().map(|w| w * w).sum::<f64>();
        let c_sigma = (mu_eff + 2.0) / (nf + mu_eff + 5.0);
        let d_sigma = 1.0 + 2.0 * (((mu_eff - 1.0) / (nf + 1.0)).sqrt() - 1.0).max(0.0) + c_sigma;
        let c_c = (4.0 + mu_eff / nf) / (nf + 4.0 + 2.0 * mu_eff / nf);
        let c_1 = 2.0 / ((nf + 1.3).powi(2) + mu_eff);
        let c_mu =
            (1.0 - c_1).min(2.0 * (mu_eff - 2.0 + 1.0 / mu_eff) / ((nf + 2.0).powi(2) + mu_eff));
        Self {
            n,
            lambda,
            mu,
            weights,
            mu_eff,
            c_sigma,
            d_sigma,
            c_c,
            c_1,
            c_mu,
            chi_n: nf.sqrt() * (1.0 - 1.0 / (4.0 * nf) + 1.0 / (21.0 * nf * nf)),
            mean: DVector::from_vec(mean),
            sigma,
            cov: DMatrix::identity(n, n),
            p_sigma: DVector::zeros(n),
            p_c: DVector::zeros(n),
            basis: DMatrix::identity(n, n),
            scales: DVector::from_element(n, 1.0),
            generation: 0,
            rng: Rng::new(seed),
        }
    }

    pub fn population_size(&self) -> usize {
        self.lambda
    }

    pub fn generation(&self) -> usize {
        self.generation
    }

    /// λ new candidates.
    pub fn ask(&mut self) -> Vec<Vec<f64>> {
        (0..self.lambda)
            .map(|_| {
                let z = DVector::from_fn(self.n, |_, _| self.rng.normal());
                let y = &self.basis * z.component_mul(&self.scales);
                (&self.mean + self.sigma * y).iter().copied().collect()
            })
            .collect()
    }

    /// Update from the candidates of [`Self::ask`] and their costs (lower is better).
    pub fn tell(&mut self, candidates: &[Vec<f64>], costs: &[f64]) {
        let mut order: Vec<usize> = (0..candidates.len()).collect();
        order.sort_by(|&a, &b| costs[a].total_cmp(&costs[b]));
        let old_mean = self.mean.clone();
        let ys: Vec<DVector<f64>> = order[..self.mu]
            .iter()
            .map(|&i| (DVector::from_column_slice(&candidates[i]) - &old_mean) / self.sigma)
            .collect();
        let mut y_w = DVector::zeros(self.n);
        for (w, y) in self.weights.iter().zip(&ys) {
            y_w += *w * y;
        }
        self.mean = &old_mean + self.sigma * &y_w;
        // C^(-1/2) · y_w through the eigen decomposition.
        let inv_sqrt = &self.basis
            * DMatrix::from_diagonal(&self.scales.map(|s| 1.0 / s))
            * self.basis.transpose();
        self.p_sigma = (1.0 - self.c_sigma) * &self.p_sigma
            + (self.c_sigma * (2.0 - self.c_sigma) * self.mu_eff).sqrt() * (&inv_sqrt * &y_w);
        self.generation += 1;
        let norm = self.p_sigma.norm();
        let decay = 1.0 - (1.0 - self.c_sigma).powi(2 * self.generation as i32);
        let h_sigma = norm / decay.sqrt() / self.chi_n < 1.4 + 2.0 / (self.n as f64 + 1.0);
        let h = if h_sigma { 1.0 } else { 0.0 };
        self.p_c = (1.0 - self.c_c) * &self.p_c
            + h * (self.c_c * (2.0 - self.c_c) * self.mu_eff).sqrt() * &y_w;
        let mut rank_mu = DMatrix::zeros(self.n, self.n);
        for (w, y) in self.weights.iter().zip(&ys) {
            rank_mu += *w * y * y.transpose();
        }
        let delta_h = (1.0 - h) * self.c_c * (2.0 - self.c_c);
        self.cov = (1.0 - self.c_1 - self.c_mu) * &self.cov
            + self.c_1 * (&self.p_c * self.p_c.transpose() + delta_h * &self.cov)
            + self.c_mu * rank_mu;
        self.sigma *= ((self.c_sigma / self.d_sigma) * (norm / self.chi_n - 1.0)).exp();
        self.decompose();
    }

    fn decompose(&mut self) {
        let sym = (&self.cov + self.cov.transpose()) * 0.5;
        let eig = SymmetricEigen::new(sym);
        self.basis = eig.eigenvectors;
        self.scales = eig.eigenvalues.map(|v| v.max(1e-20).sqrt());
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn minimises_a_shifted_ellipsoid() {
        let target = [1.0, -2.0, 0.5, 3.0];
        let cost = |x: &[f64]| -> f64 {
            x.iter()
                .zip(target)
                .enumerate()
                .map(|(i, (a, b))| (i + 1) as f64 * (a - b).powi(2))
                .sum()
        };
        let mut es = CmaEs::new(vec![0.0; 4], 1.0, None, 7);
        for _ in 0..200 {
            let xs = es.ask();
            let costs: Vec<f64> = xs.iter().map(|x| cost(x)).collect();
            es.tell(&xs, &costs);
        }
        let best: Vec<f64> = es.mean.iter().copied().collect();
        assert!(cost(&best) < 1e-6, "{best:?}");
    }
}
