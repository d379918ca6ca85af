//! One-to-one matching of detections to the true grains.
//!
//! Greedy by distance inside a gate of half the grain width D is exact here, not a shortcut:
//! grains do not overlap, so true centres are at least D apart, and a detection lies within
//! D/2 of at most one true grain. The only choice left is which of several detections near
//! one true grain gets it; the closest one does, the others are false detections, which is also
//! what an optimal (Hungarian) assignment would decide.

/// Gate of the matching as a fraction of the grain width D.
pub const GATE: f64 = 0.5;

/// A detection matched to a true grain.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Pair {
    pub truth: usize,
    pub detection: usize,
    /// Centre distance (metres).
    pub distance: f64,
}

/// Matches points `detections` to `truth` (centres, metres) one-to-one within `gate` metres.
pub fn match_centres(truth: &[[f64; 2]], detections: &[[f64; 2]], gate: f64) -> Vec<Pair> {
    // Bin the true centres in cells one gate wide: only the 3 x 3 cells around a detection
    // can hold a true centre within the gate.
    let cell = gate.max(f64::MIN_POSITIVE);
    let key = |p: [f64; 2]| ((p[0] / cell).floor() as i64, (p[1] / cell).floor() as i64);
    let mut bins: std::collections::HashMap<(i64, i64), Vec<usize>> = Default::default();
    for (i, &t) in truth.iter().enumerate() {
        bins.entry(key(t)).or_default().push(i);
    }
    let mut candidates = Vec::new();
    for (j, &d) in detections.iter().enumerate() {
        let (kx, ky) = key(d);
        for dx in -1..=1 {
            for dy in -1..=1 {
                for &i in bins.get(&(kx + dx, ky + dy)).into_iter().flatten() {
                    let distance = (truth[i][0] - d[0]).hypot(truth[i][1] - d[1]);
                    if distance <= gate {
                        candidates.push(Pair {
                            truth: i,
                            detection: j,
                            distance,
                        });
                    }
                }
            }
        }
    }
    // Ties broken by index so that the result never depends on hash order.
    candidates.sort_by(|a, b| {
        a.distance
            .total_cmp(&b.distance)
            .then(a.truth.cmp(&b.truth))
            .then(a.detection.cmp(&b.detection))
    });
    let mut truth_taken = vec![false; truth.len()];
    let mut detection_taken = vec![false; detections.len()];
    let mut pairs = Vec::new();
    for c in candidates {
        if !truth_taken[c.truth] && !detection_taken[c.detection] {
            truth_taken[c.truth] = true;
            detection_taken[c.detection] = true;
            pairs.push(c);
        }
    }
    pairs.sort_by_key(|p| p.truth);
    pairs
}

/// Difference of two orientations modulo the symmetry period, in (-period/2, period/2].
pub fn angle_error(detected: f64, truth: f64, period: f64) -> f64 {
    let d = (detected - truth).rem_euclid(period);
    if d > 0.5 * period { d - period } else { d }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::f64::consts::PI;

    #[test]
    fn closest_detection_wins_and_gate_is_respected() {
        let truth = [[0.0, 0.0], [10.0, 0.0]];
        let detections = [[0.3, 0.0], [0.1, 0.0], [10.0, 6.0], [9.0, 0.0]];
        let pairs = match_centres(&truth, &detections, 5.0);
        assert_eq!(pairs.len(), 2);
        assert_eq!((pairs[0].truth, pairs[0].detection), (0, 1));
        assert_eq!((pairs[1].truth, pairs[1].detection), (1, 3));
    }

    #[test]
    fn angle_error_respects_symmetry() {
        assert!((angle_error(0.05, PI / 2.0 - 0.05, PI / 2.0) - 0.1).abs() < 1e-12);
        assert!((angle_error(PI - 0.02, 0.01, PI) + 0.03).abs() < 1e-12);
        assert!((angle_error(0.3, 0.1, PI) - 0.2).abs() < 1e-12);
    }
}
