//! How well detections reproduce the true grains of a photograph.
//!
//! Rules, so that figures mean the same thing everywhere:
//! - true grains cut by the frame are matched (so a detection of one is not a false detection)
//!   but do not count in recall, and do not enter the error RMS: part of a cut grain is not in
//!   the photograph, and its centre is not measurable from it;
//! - recall: matched uncut true grains / uncut true grains;
//! - precision: matched detections / detections, over detections not flagged cut; detections
//!   flagged cut are counted apart (how many, how many matched);
//! - centre RMS (mm) and orientation RMS (degrees, modulo the shape's symmetry) over matched
//!   pairs whose true grain is uncut;
//! - of those pairs, the grains turned by more than [`TURNED_DEG`] are counted apart, with the
//!   orientation RMS of the others: a few grains fitted across their neighbours can make the
//!   whole RMS, and these two figures tell that from an imprecise angle.

pub mod bench;
pub mod matching;
pub mod memory;

use crate::GrainOutline;
use crate::detect::Detection;
use matching::{GATE, angle_error, match_centres};

/// An orientation error above this (degrees) is a grain fitted turned, not an imprecise angle:
/// 99 % of rods are within 3.4 degrees at 6 px/mm and 2.4 at 10 px/mm (lab style, rod53),
/// while the rods fitted across their neighbours are off by 30-90.
pub const TURNED_DEG: f64 = 10.0;

/// Counts and sums of one or more photographs; add tallies to pool photographs.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Tally {
    /// True grains not cut by the frame.
    pub truth_uncut: usize,
    /// Of those, how many were matched.
    pub truth_uncut_matched: usize,
    /// Detections not flagged cut.
    pub detections_uncut: usize,
    /// Of those, how many were matched.
    pub detections_uncut_matched: usize,
    /// Detections flagged cut, and how many of them were matched.
    pub detections_cut: usize,
    pub detections_cut_matched: usize,
    /// Matched pairs with an uncut true grain, and their squared errors (m^2, rad^2).
    pub error_pairs: usize,
    pub centre_sq_sum: f64,
    pub angle_sq_sum: f64,
    /// Of the error pairs, those turned by more than [`TURNED_DEG`], and the squared angle
    /// errors of those that are not (rad^2).
    pub turned: usize,
    pub unturned_angle_sq_sum: f64,
}

impl std::ops::AddAssign for Tally {
    fn add_assign(&mut self, o: Tally) {
        self.truth_uncut += o.truth_uncut;
        self.truth_uncut_matched += o.truth_uncut_matched;
        self.detections_uncut += o.detections_uncut;
        self.detections_uncut_matched += o.detections_uncut_matched;
        self.detections_cut += o.detections_cut;
        self.detections_cut_matched += o.detections_cut_matched;
        self.error_pairs += o.error_pairs;
        self.centre_sq_sum += o.centre_sq_sum;
        self.angle_sq_sum += o.angle_sq_sum;
        self.turned += o.turned;
        self.unturned_angle_sq_sum += o.unturned_angle_sq_sum;
    }
}

impl Tally {
    /// Fraction of uncut true grains found (NaN with no true grains).
    pub fn recall(&self) -> f64 {
        self.truth_uncut_matched as f64 / self.truth_uncut as f64
    }

    /// Fraction of uncut detections that are real grains (NaN with no detections).
    pub fn precision(&self) -> f64 {
        self.detections_uncut_matched as f64 / self.detections_uncut as f64
    }

    /// Root mean square centre error (mm).
    pub fn centre_rms_mm(&self) -> f64 {
        (self.centre_sq_sum / self.error_pairs as f64).sqrt() * 1e3
    }

    /// Root mean square orientation error (degrees), modulo the symmetry period.
    pub fn orientation_rms_deg(&self) -> f64 {
        (self.angle_sq_sum / self.error_pairs as f64)
            .sqrt()
            .to_degrees()
    }

    /// Root mean square orientation error (degrees) of the grains not turned by more than
    /// [`TURNED_DEG`].
    pub fn unturned_orientation_rms_deg(&self) -> f64 {
        (self.unturned_angle_sq_sum / (self.error_pairs - self.turned) as f64)
            .sqrt()
            .to_degrees()
    }
}

/// A true grain and whether the photograph cuts it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Truth {
    pub outline: GrainOutline,
    pub cut: bool,
}

/// Matches the detections of one photograph to its true grains and tallies the result.
pub fn score(truth: &[Truth], detections: &[Detection]) -> Tally {
    score_with_errors(truth, detections).0
}

/// [`score`], with the orientation error of every matched pair whose true grain is uncut
/// (degrees, signed, modulo the shape's symmetry, in the order of the true grains): the pairs
/// of the orientation RMS, for medians and other quantiles.
pub fn score_with_errors(truth: &[Truth], detections: &[Detection]) -> (Tally, Vec<f64>) {
    let mut tally = Tally::default();
    let mut errors = Vec::new();
    let Some(width) = truth
        .iter()
        .map(|t| t.outline.shape.width())
        .reduce(f64::min)
    else {
        tally.detections_uncut = detections.iter().filter(|d| !d.cut).count();
        tally.detections_cut = detections.len() - tally.detections_uncut;
        return (tally, errors);
    };
    let truth_centres: Vec<[f64; 2]> = truth.iter().map(|t| [t.outline.x, t.outline.y]).collect();
    let detected: Vec<[f64; 2]> = detections
        .iter()
        .map(|d| [d.outline.x, d.outline.y])
        .collect();
    let pairs = match_centres(&truth_centres, &detected, GATE * width);
    let mut detection_matched = vec![false; detections.len()];
    tally.truth_uncut = truth.iter().filter(|t| !t.cut).count();
    for p in &pairs {
        detection_matched[p.detection] = true;
        let t = &truth[p.truth];
        if !t.cut {
            tally.truth_uncut_matched += 1;
            tally.error_pairs += 1;
            tally.centre_sq_sum += p.distance * p.distance;
            let period = t.outline.shape.symmetry_period();
            let e = angle_error(
                detections[p.detection].outline.theta,
                t.outline.theta,
                period,
            );
            tally.angle_sq_sum += e * e;
            errors.push(e.to_degrees());
            if e.abs().to_degrees() > TURNED_DEG {
                tally.turned += 1;
            } else {
                tally.unturned_angle_sq_sum += e * e;
            }
        }
    }
    for (d, matched) in detections.iter().zip(detection_matched) {
        if d.cut {
            tally.detections_cut += 1;
            tally.detections_cut_matched += usize::from(matched);
        } else {
            tally.detections_uncut += 1;
            tally.detections_uncut_matched += usize::from(matched);
        }
    }
    (tally, errors)
}

/// Median of the absolute values (NaN when empty).
pub fn median_abs(values: &[f64]) -> f64 {
    let mut v: Vec<f64> = values.iter().map(|x| x.abs()).collect();
    v.sort_by(f64::total_cmp);
    match v.len() {
        0 => f64::NAN,
        n if n % 2 == 1 => v[n / 2],
        n => 0.5 * (v[n / 2 - 1] + v[n / 2]),
    }
}
