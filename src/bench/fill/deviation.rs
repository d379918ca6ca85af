//! Deviations of an ensemble from the reference ensemble in units of their standard errors
//! (formulas in the module doc of [`super`]).

use serde::{Deserialize, Serialize};

use super::measures::Measures;
use crate::analysis::stats::MeanErr;

/// A deviation at or below this is "within two standard errors".
pub const WITHIN: f64 = 2.0;

#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct Deviations {
    pub phi_f: f64,
    pub orientation: f64,
    pub rdf: f64,
    pub pressure: f64,
}

impl Deviations {
    /// The largest of the four; NaN when one cannot be measured (a missing deviation must not
    /// pass for a small one).
    pub fn largest(&self) -> f64 {
        [self.phi_f, self.orientation, self.rdf, self.pressure]
            .into_iter()
            .fold(0.0, |m: f64, d| {
                if d.is_nan() || m.is_nan() {
                    f64::NAN
                } else {
                    m.max(d)
                }
            })
    }

    pub fn within(&self) -> bool {
        self.largest() <= WITHIN
    }
}

/// num / den, with 0 / 0 = 0 (both ensembles agree exactly) and x / 0 = infinity for x > 0
/// (a difference with no spread to measure it by).
fn ratio(num: f64, den: f64) -> f64 {
    if num == 0.0 && den == 0.0 {
        0.0
    } else if den == 0.0 {
        f64::INFINITY
    } else {
        num / den
    }
}

/// |mean_s - mean_ref| / sqrt(se_s^2 + se_ref^2).
pub fn scalar(s: MeanErr, reference: MeanErr) -> f64 {
    ratio(
        (s.mean - reference.mean).abs(),
        s.stderr.hypot(reference.stderr),
    )
}

/// (mean_s - mean_ref) / sqrt(se_s^2 + se_ref^2): [`scalar`] with its sign.
pub fn signed_scalar(s: MeanErr, reference: MeanErr) -> f64 {
    let d = s.mean - reference.mean;
    ratio(d.abs(), s.stderr.hypot(reference.stderr)).copysign(d)
}

/// Independent signed deviations pooled into one (Stouffer): sum z_i / sqrt(n), of order one
/// under the null like each z_i; NaN for none. Shifts of one sign in every scene add up here
/// while each alone stays within 2.
pub fn pooled(z: &[f64]) -> f64 {
    if z.is_empty() {
        return f64::NAN;
    }
    z.iter().sum::<f64>() / (z.len() as f64).sqrt()
}

/// sum_k |y_s - y_ref| / sum_k sqrt(se_s^2 + se_ref^2); NaN when the series differ in length
/// or are empty.
pub fn l1(s: &[f64], s_err: &[f64], reference: &[f64], reference_err: &[f64]) -> f64 {
    let n = s.len();
    if n == 0 || [s_err.len(), reference.len(), reference_err.len()] != [n; 3] {
        return f64::NAN;
    }
    let num: f64 = s.iter().zip(reference).map(|(a, b)| (a - b).abs()).sum();
    let den: f64 = s_err
        .iter()
        .zip(reference_err)
        .map(|(a, b)| a.hypot(*b))
        .sum();
    ratio(num, den)
}

/// sqrt(mean (y_s - y_ref)^2) / sqrt(mean (se_s^2 + se_ref^2)) over the first
/// min(len_s, len_ref) points (the common depth range: both profiles start at the free surface
/// with the same spacing); NaN when there is none.
pub fn rms(s: &[f64], s_err: &[f64], reference: &[f64], reference_err: &[f64]) -> f64 {
    let n = s.len().min(reference.len());
    if n == 0 || s_err.len() < n || reference_err.len() < n {
        return f64::NAN;
    }
    let num: f64 = (0..n).map(|k| (s[k] - reference[k]).powi(2)).sum::<f64>() / n as f64;
    let den: f64 = (0..n)
        .map(|k| s_err[k].powi(2) + reference_err[k].powi(2))
        .sum::<f64>()
        / n as f64;
    ratio(num.sqrt(), den.sqrt())
}

/// Every deviation of `s` from `reference`. The pressure profiles must share their depth grid
/// (same silo width, same grain): otherwise the pressure deviation is NaN.
pub fn deviations(s: &Measures, reference: &Measures) -> Deviations {
    let pressure = match (&s.pressure, &reference.pressure) {
        (Some(a), Some(b)) => {
            let n = a.depth_over_w.len().min(b.depth_over_w.len());
            let same_grid = (0..n).all(|k| (a.depth_over_w[k] - b.depth_over_w[k]).abs() < 1e-9);
            if same_grid {
                rms(&a.p, &a.p_err, &b.p, &b.p_err)
            } else {
                f64::NAN
            }
        }
        _ => f64::NAN,
    };
    let same_r = s.r.len() == reference.r.len()
        && s.r
            .iter()
            .zip(&reference.r)
            .all(|(a, b)| (a - b).abs() < 1e-9);
    Deviations {
        phi_f: scalar(s.phi_f, reference.phi_f),
        orientation: l1(&s.f, &s.f_err, &reference.f, &reference.f_err),
        rdf: if same_r {
            l1(&s.g, &s.g_err, &reference.g, &reference.g_err)
        } else {
            f64::NAN
        },
        pressure,
    }
}
