//! Pressure profile along the silo's vertical centre line against depth h below the free
//! surface (docs/model.md §3), with the overburden and a Janssen fit.
//!
//! The free surface above the centre line is the top of the highest grain whose centre lies
//! within max(w, 2 D) of the line. The fit uses depths down to 2 w above the floor: closer to
//! the floor the kernel reaches below it, where there are no grains, and the coarse-grained
//! stress falls off for that reason alone.

use serde::{Deserialize, Serialize};

use super::coarse_grain::{CoarseGrainInput, branches, stress_at};
use super::stats::{MeanErr, mean_err_columns};
use crate::deposit::{Ensemble, Realisation};

#[derive(Clone, Copy, Debug, Serialize, Deserialize)]
pub struct PressureInput {
    pub coarse_grain: CoarseGrainInput,
    /// Spacing of the evaluation points along the centre line (m).
    pub dh: f64,
}

#[derive(Clone, Copy, Debug, Serialize, Deserialize)]
pub struct JanssenFit {
    /// Screening length over silo width.
    pub lambda_over_w: f64,
    /// Saturation pressure (N/m; divide by the plate gap for Pa).
    pub p_sat: f64,
    /// Root-mean-square of P - fit over the fitted points (N/m).
    pub rms_residual: f64,
    /// Deepest h/W used.
    pub h_over_w_max: f64,
}

/// The longest screening length the fit searches, in silo widths.
pub const JANSSEN_LAMBDA_MAX_OVER_W: f64 = 100.0;

/// Whether a fitted lambda / W lies below the fit's longest screening length. At that bound
/// the profile is still straight over the depth fitted (a deposit shallower than lambda), so
/// lambda is only a lower bound and P_sat only the slope times that length.
pub fn janssen_saturates(lambda_over_w: f64) -> bool {
    lambda_over_w < 0.99 * JANSSEN_LAMBDA_MAX_OVER_W
}

impl JanssenFit {
    /// The profile saturates within the depth fitted ([`janssen_saturates`]).
    pub fn saturates(&self) -> bool {
        janssen_saturates(self.lambda_over_w)
    }
}

/// Ensemble-mean profile; stresses in N/m, compressive negative.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct PressureProfile {
    pub phi0: f64,
    /// Coarse-graining width (m).
    pub w: f64,
    pub silo_width: f64,
    pub h_over_w: Vec<f64>,
    pub sigma_xx: Vec<f64>,
    pub sigma_xx_err: Vec<f64>,
    pub sigma_yy: Vec<f64>,
    pub sigma_yy_err: Vec<f64>,
    pub trace: Vec<f64>,
    pub trace_err: Vec<f64>,
    /// rho g h with packing fraction 1 (N/m).
    pub overburden_full: Vec<f64>,
    /// phi_f rho g h with the measured packing fraction.
    pub overburden_measured: Vec<f64>,
    pub phi_f: MeanErr,
    /// Fit of P = -sigma_yy.
    pub janssen: Option<JanssenFit>,
    pub n_realisations: usize,
}

/// Height of the free surface above the centre line x_c.
pub fn free_surface(real: &Realisation, x_c: f64, w: f64) -> f64 {
    let half = w.max(2.0 * real.grain_width());
    real.deposit
        .grains
        .iter()
        .filter(|g| (g.x - x_c).abs() <= half)
        .map(|g| g.y + 0.5 * g.length)
        .fold(f64::NEG_INFINITY, f64::max)
}

/// The profile of the realisations that have contacts; None when none has.
pub fn compute(
    input: &PressureInput,
    ensemble: &Ensemble,
) -> anyhow::Result<Option<PressureProfile>> {
    let with_contacts: Vec<&Realisation> = ensemble
        .realisations
        .iter()
        .filter(|r| r.contacts.is_some())
        .collect();
    let Some(first) = with_contacts.first() else {
        return Ok(None);
    };
    let w = input.coarse_grain.w;
    let silo_width = first.meta.silo_width();
    let x_c = 0.5 * silo_width;
    let surfaces: Vec<f64> = with_contacts
        .iter()
        .map(|r| free_surface(r, x_c, w))
        .collect();
    let h_max = surfaces.iter().copied().fold(f64::INFINITY, f64::min);
    if !(h_max.is_finite() && h_max > input.dh) {
        anyhow::bail!(
            "phi0 = {}: no grains near the centre line, no pressure profile",
            ensemble.phi0
        );
    }
    let n = (h_max / input.dh).floor() as usize + 1;
    let hs: Vec<f64> = (0..n).map(|k| k as f64 * input.dh).collect();
    let mut xx = Vec::new();
    let mut yy = Vec::new();
    let mut tr = Vec::new();
    let mut phis = Vec::new();
    let mut rho_g = Vec::new();
    for (real, surface) in with_contacts.iter().zip(&surfaces) {
        let contacts = real.contacts.as_deref().unwrap_or_default();
        let points: Vec<[f64; 2]> = hs.iter().map(|h| [x_c, surface - h]).collect();
        let s = stress_at(
            &branches(&real.deposit, contacts),
            &points,
            &input.coarse_grain,
        );
        xx.push(s.iter().map(|s| s[0]).collect());
        yy.push(s.iter().map(|s| s[3]).collect());
        tr.push(s.iter().map(|s| s[0] + s[3]).collect());
        phis.push(real.analysed_area()?.packing_fraction(&real.deposit));
        rho_g.push(real.meta.areal_density(real.shape) * real.meta.gravity());
    }
    let (sigma_xx, sigma_xx_err) = mean_err_columns(&xx);
    let (sigma_yy, sigma_yy_err) = mean_err_columns(&yy);
    let (trace, trace_err) = mean_err_columns(&tr);
    let phi_f = MeanErr::of(&phis);
    let rho_g = MeanErr::of(&rho_g).mean;
    let fit_n = hs.iter().filter(|&&h| h <= h_max - 2.0 * w).count();
    let pressure: Vec<f64> = sigma_yy.iter().map(|s| -s).collect();
    let janssen = (fit_n >= 4).then(|| janssen_fit(&hs[..fit_n], &pressure[..fit_n], silo_width));
    Ok(Some(PressureProfile {
        phi0: ensemble.phi0,
        w,
        silo_width,
        h_over_w: hs.iter().map(|h| h / silo_width).collect(),
        sigma_xx,
        sigma_xx_err,
        sigma_yy,
        sigma_yy_err,
        trace,
        trace_err,
        overburden_full: hs.iter().map(|h| rho_g * h).collect(),
        overburden_measured: hs.iter().map(|h| phi_f.mean * rho_g * h).collect(),
        phi_f,
        janssen,
        n_realisations: with_contacts.len(),
    }))
}

/// Least-squares fit of P(h) = P_sat (1 - exp(-h / lambda)): P_sat is linear given lambda, and
/// lambda is found by golden-section search on log lambda between W/100 and 100 W
/// ([`JANSSEN_LAMBDA_MAX_OVER_W`]) after a coarse
/// scan (the residual can have a shallow second minimum when P is nearly linear).
pub fn janssen_fit(h: &[f64], p: &[f64], silo_width: f64) -> JanssenFit {
    let sse_at = |log_lambda: f64| -> (f64, f64) {
        let lambda = log_lambda.exp();
        let (mut pe, mut ee) = (0.0, 0.0);
        for (&h, &p) in h.iter().zip(p) {
            let e = 1.0 - (-h / lambda).exp();
            pe += p * e;
            ee += e * e;
        }
        let p_sat = if ee > 0.0 { pe / ee } else { 0.0 };
        let sse = h
            .iter()
            .zip(p)
            .map(|(&h, &p)| (p - p_sat * (1.0 - (-h / lambda).exp())).powi(2))
            .sum();
        (sse, p_sat)
    };
    let (lo, hi) = (
        (silo_width / JANSSEN_LAMBDA_MAX_OVER_W).ln(),
        (silo_width * JANSSEN_LAMBDA_MAX_OVER_W).ln(),
    );
    let steps = 200;
    let best = (0..=steps)
        .map(|k| lo + (hi - lo) * k as f64 / steps as f64)
        .min_by(|a, b| sse_at(*a).0.total_cmp(&sse_at(*b).0))
        .unwrap_or(lo);
    let step = (hi - lo) / steps as f64;
    let (mut a, mut b) = ((best - step).max(lo), (best + step).min(hi));
    let g = 0.5 * (5f64.sqrt() - 1.0);
    for _ in 0..100 {
        let c = b - g * (b - a);
        let d = a + g * (b - a);
        if sse_at(c).0 < sse_at(d).0 {
            b = d;
        } else {
            a = c;
        }
    }
    let log_lambda = 0.5 * (a + b);
    let (sse, p_sat) = sse_at(log_lambda);
    JanssenFit {
        lambda_over_w: log_lambda.exp() / silo_width,
        p_sat,
        rms_residual: (sse / h.len() as f64).sqrt(),
        h_over_w_max: h.last().copied().unwrap_or(0.0) / silo_width,
    }
}

/// The centre-line profile for each coarse-graining width.
pub fn w_scan(
    ws: &[f64],
    base: &PressureInput,
    ensemble: &Ensemble,
) -> anyhow::Result<Vec<PressureProfile>> {
    let mut out = Vec::new();
    for &w in ws {
        let input = PressureInput {
            coarse_grain: CoarseGrainInput {
                w,
                ..base.coarse_grain
            },
            ..*base
        };
        if let Some(p) = compute(&input, ensemble)? {
            out.push(p);
        }
    }
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn janssen_fit_recovers_its_parameters() {
        let width = 0.256;
        let (lambda, p_sat) = (0.7 * width, 12.5);
        let h: Vec<f64> = (0..200).map(|k| k as f64 * 0.004).collect();
        let p: Vec<f64> = h
            .iter()
            .map(|h| p_sat * (1.0 - (-h / lambda).exp()))
            .collect();
        let fit = janssen_fit(&h, &p, width);
        assert!((fit.lambda_over_w - 0.7).abs() < 1e-6, "{fit:?}");
        assert!((fit.p_sat - p_sat).abs() < 1e-5 * p_sat, "{fit:?}");
        assert!(fit.rms_residual < 1e-6 * p_sat);
        assert!(fit.saturates());
    }

    #[test]
    fn a_hydrostatic_profile_is_not_saturated() {
        // A deposit a fifth of a width deep under a straight overburden line: nothing in it
        // sets a screening length, and the fit must say so rather than report its bound.
        let width = 0.16;
        let h: Vec<f64> = (0..40).map(|k| k as f64 * 0.0008).collect();
        let p: Vec<f64> = h.iter().map(|h| 0.8 * 18.5 * 10.0 * h).collect();
        let fit = janssen_fit(&h, &p, width);
        assert!(!fit.saturates(), "{fit:?}");
        assert!(
            fit.lambda_over_w > 0.99 * JANSSEN_LAMBDA_MAX_OVER_W,
            "{fit:?}"
        );
    }
}
