//! Axis ranges that hold every point with its error bar, with a margin so that no bar's cap
//! touches the frame.

/// Share of the span left free beyond the outermost bar end, at each side.
pub const MARGIN: f64 = 0.05;

/// The range of an axis holding `value - error ..= value + error` for every pair whose value
/// and error are finite (an error of 0 is a point without a bar), widened by [`MARGIN`] of the
/// span at each side. A single value gets +-10 % of itself (+-1 at 0); no finite value gives
/// 0..1.
pub fn axis_range(points: impl IntoIterator<Item = (f64, f64)>) -> (f64, f64) {
    let (lo, hi) = points
        .into_iter()
        .filter(|(v, e)| v.is_finite() && e.is_finite())
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), (v, e)| {
            let e = e.abs();
            (lo.min(v - e), hi.max(v + e))
        });
    if lo > hi {
        return (0.0, 1.0);
    }
    if hi - lo <= f64::EPSILON * lo.abs().max(hi.abs()) {
        let half = if lo == 0.0 { 1.0 } else { 0.1 * lo.abs() };
        return (lo - half, hi + half);
    }
    let pad = MARGIN * (hi - lo);
    (lo - pad, hi + pad)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_error_bar_lies_inside_with_a_margin() {
        // A large bar on a low point and one on a high point set the range, not the values.
        let points = [(1.0, 0.1), (5.0, 4.0), (2.0, 0.0), (-1.0, 3.0)];
        let (lo, hi) = axis_range(points);
        let span = hi - lo;
        for (v, e) in points {
            assert!(v - e > lo + 0.04 * span, "bar {v} - {e} below {lo}");
            assert!(v + e < hi - 0.04 * span, "bar {v} + {e} above {hi}");
        }
        // No more than the margin beyond the outermost bar ends (-4 and 9).
        assert!((lo - (-4.0 - MARGIN * 13.0)).abs() < 1e-12);
        assert!((hi - (9.0 + MARGIN * 13.0)).abs() < 1e-12);
    }

    #[test]
    fn points_that_cannot_be_drawn_do_not_stretch_the_axis() {
        let (lo, hi) = axis_range([
            (1.0, 0.5),
            (f64::NAN, 0.1),
            (2.0, f64::INFINITY),
            (1e9, f64::NAN),
        ]);
        assert!(lo < 0.5 && lo > 0.4 && hi > 1.5 && hi < 1.6, "{lo}..{hi}");
        assert_eq!(axis_range(std::iter::empty()), (0.0, 1.0));
    }

    #[test]
    fn a_single_value_gets_a_range_around_it() {
        let (lo, hi) = axis_range([(0.25, 0.0)]);
        assert!(lo < 0.25 && hi > 0.25 && hi - lo < 0.1);
        let (lo, hi) = axis_range([(0.0, 0.0), (0.0, 0.0)]);
        assert_eq!((lo, hi), (-1.0, 1.0));
    }
}
