//! Orientation distribution f(theta) and the order parameters S2 (rods) and S4 (squares).

use serde::{Deserialize, Serialize};

use super::stats::{MeanErr, mean_err_columns};
use crate::deposit::{Ensemble, fold_angle};
use crate::grains::GrainKind;

#[derive(Clone, Copy, Debug, Serialize, Deserialize)]
pub struct OrientationInput {
    /// Bin width (rad). 5 degrees resolves the peaks at 0 and pi/2 of the paper's f(theta)
    /// while keeping ~100 grains a bin in one photograph.
    pub bin_width: f64,
}

impl Default for OrientationInput {
    fn default() -> Self {
        OrientationInput {
            bin_width: 5f64.to_radians(),
        }
    }
}

#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct OrientationResult {
    pub phi0: f64,
    pub shape: GrainKind,
    /// Folding period: pi/2 for squares, pi for rods.
    pub period: f64,
    /// Bin centres (rad).
    pub theta: Vec<f64>,
    /// f(theta), normalised so that its integral over one period is 1.
    pub f: Vec<f64>,
    pub f_err: Vec<f64>,
    /// S2 = <cos 2(theta - theta_d)>, theta_d the director that maximises it. Rods only: for
    /// squares cos 2 theta is not invariant under a quarter turn, so S2 would measure the folding.
    pub s2: Option<MeanErr>,
    /// S4 = |<exp(4 i theta)>|: fourfold order, the relevant one for squares.
    pub s4: MeanErr,
    pub n_grains: usize,
}

/// Normalised histogram of the folded angles over [0, period).
pub fn histogram(thetas: &[f64], period: f64, bins: usize) -> Vec<f64> {
    let mut h = vec![0.0; bins];
    for &t in thetas {
        let k = ((fold_angle(t, period) / period) * bins as f64) as usize;
        h[k.min(bins - 1)] += 1.0;
    }
    let norm = thetas.len() as f64 * period / bins as f64;
    h.iter().map(|c| c / norm).collect()
}

/// |<exp(i m theta)>|: with theta_d = arg/m, this is <cos m(theta - theta_d)>.
pub fn order_parameter(thetas: &[f64], m: f64) -> f64 {
    let (c, s) = thetas.iter().fold((0.0, 0.0), |(c, s), t| {
        (c + (m * t).cos(), s + (m * t).sin())
    });
    let n = thetas.len() as f64;
    (c / n).hypot(s / n)
}

/// f(theta), S2, S4 of the grains in each realisation's analysed area; ensemble mean and
/// standard error.
pub fn compute(input: &OrientationInput, ensemble: &Ensemble) -> anyhow::Result<OrientationResult> {
    let period = ensemble.shape.symmetry_period();
    let bins = ((period / input.bin_width).round() as usize).max(1);
    let mut hists = Vec::new();
    let (mut s2, mut s4) = (Vec::new(), Vec::new());
    let mut n_grains = 0;
    for real in &ensemble.realisations {
        let area = real.analysed_area()?;
        let thetas: Vec<f64> = area.grains(&real.deposit).map(|g| g.theta).collect();
        if thetas.is_empty() {
            continue;
        }
        n_grains += thetas.len();
        hists.push(histogram(&thetas, period, bins));
        s2.push(order_parameter(&thetas, 2.0));
        s4.push(order_parameter(&thetas, 4.0));
    }
    if hists.is_empty() {
        anyhow::bail!(
            "phi0 = {}: no grain lies in any analysed area",
            ensemble.phi0
        );
    }
    let (f, f_err) = mean_err_columns(&hists);
    Ok(OrientationResult {
        phi0: ensemble.phi0,
        shape: ensemble.shape,
        period,
        theta: (0..bins)
            .map(|k| (k as f64 + 0.5) * period / bins as f64)
            .collect(),
        f,
        f_err,
        s2: (ensemble.shape != GrainKind::Square).then(|| MeanErr::of(&s2)),
        s4: MeanErr::of(&s4),
        n_grains,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn histogram_integrates_to_one_and_order_parameters_are_exact() {
        let period = std::f64::consts::PI;
        // Half the grains at 0.1, half at 0.1 + pi/2: S2 = 0, S4 = 1.
        let thetas: Vec<f64> = (0..100)
            .map(|k| 0.1 + if k % 2 == 0 { 0.0 } else { period / 2.0 })
            .collect();
        let h = histogram(&thetas, period, 36);
        let integral: f64 = h.iter().sum::<f64>() * period / 36.0;
        assert!((integral - 1.0).abs() < 1e-12);
        assert!(order_parameter(&thetas, 2.0) < 1e-12);
        assert!((order_parameter(&thetas, 4.0) - 1.0).abs() < 1e-12);
        // All aligned at 0.3: S2 = 1 whatever the director.
        assert!((order_parameter(&[0.3; 10], 2.0) - 1.0).abs() < 1e-12);
        // Folding: -0.01 lands in the last bin.
        let h = histogram(&[-0.01], period, 36);
        assert!(h[35] > 0.0);
    }
}
