//! The bench's photographs pooled: over seeds per source, or over sources and seeds per
//! shape; grains, not photographs, weigh equally.

use vision::Phases;
use vision::render::LookRange;

use super::{Row, Spent};

/// Rows pooling `photos` over seeds, per source, shape, scale and look range (`over_sources`
/// false), or over sources too, per shape, scale and look range; in the order first met.
pub fn pooled(photos: &[Row], over_sources: bool) -> Vec<Row> {
    let mut out: Vec<Row> = Vec::new();
    for r in photos {
        let same = |p: &&mut Row| {
            p.shape == r.shape
                && p.px_per_mm == r.px_per_mm
                && p.look == r.look
                && (over_sources || p.source == r.source)
        };
        match out.iter_mut().find(same) {
            Some(p) => {
                p.photos += r.photos;
                p.tally += r.tally;
                p.orientation_errors_deg
                    .extend_from_slice(&r.orientation_errors_deg);
                p.grains += r.grains;
                p.seconds += r.seconds;
                p.render_seconds += r.render_seconds;
                p.refused += r.refused;
                p.peak_memory_bytes = match (p.peak_memory_bytes, r.peak_memory_bytes) {
                    (Some(a), Some(b)) => Some(a.max(b)),
                    (a, b) => a.or(b),
                };
                if p.fill != r.fill {
                    p.fill = "both";
                }
            }
            None => out.push(Row {
                seed: None,
                source: if over_sources { "all" } else { r.source },
                ..r.clone()
            }),
        }
    }
    out
}

/// Adds a photograph's steps to those of its shape, scale and look range.
pub fn spend(
    spent: &mut Vec<Spent>,
    shape: &'static str,
    px_per_mm: f64,
    look: LookRange,
    phases: &Phases,
) {
    let same = |s: &&mut Spent| s.shape == shape && s.px_per_mm == px_per_mm && s.look == look;
    match spent.iter_mut().find(same) {
        Some(s) => {
            s.photos += 1;
            s.phases.add_all(phases);
        }
        None => {
            let mut s = Spent {
                shape,
                px_per_mm,
                look,
                photos: 1,
                phases: Phases::default(),
            };
            s.phases.add_all(phases);
            spent.push(s);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use vision::evaluate::Tally;

    fn photo(source: &'static str, fill: &'static str, seed: u64, matched: usize) -> Row {
        Row {
            source,
            fill,
            shape: "square",
            seed: Some(seed),
            px_per_mm: 10.0,
            look: LookRange::LabLike,
            photos: 1,
            tally: Tally {
                truth_uncut: 10,
                truth_uncut_matched: matched,
                ..Tally::default()
            },
            orientation_errors_deg: vec![matched as f64],
            grains: 12,
            seconds: 1.0,
            render_seconds: 0.5,
            peak_memory_bytes: Some(100 * seed),
            refused: usize::from(matched == 0),
        }
    }

    #[test]
    fn photographs_pool_by_source_then_over_sources() {
        let photos = [
            photo("a", "slow", 1, 10),
            photo("a", "slow", 2, 8),
            photo("b", "fast", 1, 0),
        ];
        let by_source = pooled(&photos, false);
        assert_eq!(by_source.len(), 2);
        let a = &by_source[0];
        assert_eq!((a.source, a.seed, a.photos), ("a", None, 2));
        assert_eq!(a.tally.truth_uncut_matched, 18);
        assert_eq!(a.orientation_errors_deg, [10.0, 8.0]);
        assert_eq!(a.peak_memory_bytes, Some(200));
        let all = pooled(&photos, true);
        assert_eq!(all.len(), 1);
        assert_eq!(
            (all[0].source, all[0].fill, all[0].photos),
            ("all", "both", 3)
        );
        assert!((all[0].tally.recall() - 18.0 / 30.0).abs() < 1e-12);
        assert_eq!(
            (by_source[0].refused, by_source[1].refused, all[0].refused),
            (0, 1, 1)
        );
    }
}
