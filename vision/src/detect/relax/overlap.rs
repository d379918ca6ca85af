//! The overlap term: grains are rigid and cannot overlap, so every pixel two outlines claim
//! at once costs, whatever the photograph shows there. The image misfit alone cannot see an
//! overlap: where grains touch on every side the photograph is dark under both outlines, and a
//! nut turned in place, or a rod slipped across its neighbour's seam, explains the darkness
//! as well as the true pose does.

/// Cost of one pixel of overlap (outline coverage beyond 1). A penetration one pixel deep
/// along an edge of n pixels then costs n, as much as the misfit of a strip of n pixels one
/// pixel wide left dark and unexplained (or rendered dark over bright field): an overlap is
/// worth no more and no less than the misfit it could buy.
pub const PIXEL_COST: f64 = 1.0;

/// The overlap cost of a pixel whose outline coverages (every grain's, summed) add up to
/// `covered`.
#[inline]
pub fn cost(covered: f32) -> f64 {
    PIXEL_COST * f64::from((covered - 1.0).max(0.0))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// One outline, or two that share an anti-aliased edge (coverages adding to one), cost
    /// nothing; two stacked whole cost a pixel each.
    #[test]
    fn only_coverage_beyond_one_costs() {
        assert_eq!(cost(0.0), 0.0);
        assert_eq!(cost(1.0), 0.0);
        assert_eq!(cost(0.3 + 0.7), 0.0);
        assert!((cost(2.0) - PIXEL_COST).abs() < 1e-12);
    }
}
