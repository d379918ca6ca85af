//! Radial distribution function g(r) (docs/model.md §3), r in grain widths D.
//!
//! Bins are centred on multiples of dr (bin k covers [(k - 1/2) dr, (k + 1/2) dr)), so a
//! lattice distance of exactly 1 D sits mid-bin and its annulus area is exactly 2 pi r dr.

use kiddo::{ImmutableKdTree, SquaredEuclidean};
use rayon::prelude::*;
use serde::{Deserialize, Serialize};

use super::stats::{MeanErr, mean_err_columns};
use crate::deposit::{AnalysedArea, Ensemble};

/// Parameters, in grain widths D.
#[derive(Clone, Copy, Debug, Serialize, Deserialize)]
pub struct RdfInput {
    pub dr: f64,
    /// g is reported for r < r_max.
    pub r_max: f64,
    /// Centres must lie at least this far inside the analysed area.
    pub margin: f64,
}

impl Default for RdfInput {
    fn default() -> Self {
        RdfInput {
            dr: 0.1,
            r_max: 4.0,
            margin: 4.0,
        }
    }
}

/// g(r) of one deposit.
#[derive(Clone, Debug, PartialEq)]
pub struct DepositRdf {
    /// Bin centres (D).
    pub r: Vec<f64>,
    pub g: Vec<f64>,
    /// Neighbour counts per centre in each bin.
    pub neighbours_per_centre: Vec<f64>,
    pub n_centres: usize,
}

/// Ensemble g(r).
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct RdfResult {
    pub phi0: f64,
    pub r: Vec<f64>,
    pub g: Vec<f64>,
    pub g_err: Vec<f64>,
    /// g at r = 1 D (the bin centred on 1).
    pub g_at_1: MeanErr,
    /// Packing fraction of the analysed area.
    pub packing_fraction: MeanErr,
    /// Realisations with at least one centre deep enough in the analysed area.
    pub n_used: usize,
    pub n_centres: usize,
}

/// Bin centres k dr for k = 1.. while the bin's upper edge stays below r_max.
pub fn bin_centres(input: &RdfInput) -> Vec<f64> {
    let n = ((input.r_max / input.dr) - 0.5 + 1e-9).floor() as usize;
    (1..=n).map(|k| k as f64 * input.dr).collect()
}

/// g(r) of the points `centres` (m) in `area`, grain width `d` (m). None when no point lies
/// `margin` widths inside the area.
pub fn deposit_rdf(
    points: &[[f64; 2]],
    area: &AnalysedArea,
    d: f64,
    input: &RdfInput,
) -> Option<DepositRdf> {
    let inside: Vec<[f64; 2]> = points
        .iter()
        .copied()
        .filter(|p| area.contains(p[0], p[1]))
        .collect();
    let r = bin_centres(input);
    let n_bins = r.len();
    let centres: Vec<[f64; 2]> = inside
        .iter()
        .copied()
        .filter(|p| area.depth_inside(p[0], p[1]) >= input.margin * d)
        .collect();
    if centres.is_empty() {
        return None;
    }
    // Points are in units of D from here on, so distances are bin coordinates.
    let scaled: Vec<[f64; 2]> = inside.iter().map(|p| [p[0] / d, p[1] / d]).collect();
    let tree: ImmutableKdTree<f64, 2> = ImmutableKdTree::new_from_slice(&scaled).ok()?;
    let reach = (n_bins as f64 + 0.5) * input.dr;
    let mut counts = vec![0u64; n_bins];
    for c in &centres {
        let q = [c[0] / d, c[1] / d];
        for hit in tree
            .query(&q)
            .within::<SquaredEuclidean<f64>>(reach * reach)
            .unsorted()
            .execute()
        {
            let k = (hit.distance.sqrt() / input.dr + 0.5).floor() as usize;
            if (1..=n_bins).contains(&k) {
                counts[k - 1] += 1;
            }
        }
    }
    Some(normalise(
        &counts,
        &r,
        centres.len(),
        inside.len(),
        area,
        d,
        input,
    ))
}

fn normalise(
    counts: &[u64],
    r: &[f64],
    n_centres: usize,
    n_inside: usize,
    area: &AnalysedArea,
    d: f64,
    input: &RdfInput,
) -> DepositRdf {
    let rho = n_inside as f64 / (area.area() / (d * d));
    let per_centre: Vec<f64> = counts
        .iter()
        .map(|&c| c as f64 / n_centres as f64)
        .collect();
    let g = per_centre
        .iter()
        .zip(r)
        .map(|(n, r)| n / (rho * 2.0 * std::f64::consts::PI * r * input.dr))
        .collect();
    DepositRdf {
        r: r.to_vec(),
        g,
        neighbours_per_centre: per_centre,
        n_centres,
    }
}

/// The ensemble's g(r): mean and standard error over realisations, g(1), packing fraction.
pub fn compute(input: &RdfInput, ensemble: &Ensemble) -> anyhow::Result<RdfResult> {
    let per: Vec<(Option<DepositRdf>, f64)> = ensemble
        .realisations
        .par_iter()
        .map(|real| -> anyhow::Result<_> {
            let area = real.analysed_area()?;
            let points: Vec<[f64; 2]> = real.deposit.grains.iter().map(|g| [g.x, g.y]).collect();
            let rdf = deposit_rdf(&points, &area, real.grain_width(), input);
            Ok((rdf, area.packing_fraction(&real.deposit)))
        })
        .collect::<anyhow::Result<_>>()?;
    let r = bin_centres(input);
    let k1 = r.iter().position(|&x| (x - 1.0).abs() < 1e-9);
    let used: Vec<&DepositRdf> = per.iter().filter_map(|(g, _)| g.as_ref()).collect();
    let series: Vec<Vec<f64>> = used.iter().map(|g| g.g.clone()).collect();
    let (g, g_err) = mean_err_columns(&series);
    let g1: Vec<f64> = match k1 {
        Some(k) => used.iter().map(|x| x.g[k]).collect(),
        None => Vec::new(),
    };
    let phis: Vec<f64> = per.iter().map(|(_, p)| *p).collect();
    Ok(RdfResult {
        phi0: ensemble.phi0,
        r,
        g: if used.is_empty() { Vec::new() } else { g },
        g_err: if used.is_empty() { Vec::new() } else { g_err },
        g_at_1: MeanErr::of(&g1),
        packing_fraction: MeanErr::of(&phis),
        n_used: used.len(),
        n_centres: used.iter().map(|g| g.n_centres).sum(),
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;
    use rand::{Rng, SeedableRng};
    use rand_chacha::ChaCha8Rng;

    /// The definition, O(N^2), with the same bins and normalisation.
    fn brute_force(
        points: &[[f64; 2]],
        area: &AnalysedArea,
        d: f64,
        input: &RdfInput,
    ) -> Option<DepositRdf> {
        let inside: Vec<[f64; 2]> = points
            .iter()
            .copied()
            .filter(|p| area.contains(p[0], p[1]))
            .collect();
        let r = bin_centres(input);
        let mut counts = vec![0u64; r.len()];
        let mut n_centres = 0;
        for a in &inside {
            if area.depth_inside(a[0], a[1]) < input.margin * d {
                continue;
            }
            n_centres += 1;
            for b in &inside {
                let (dx, dy) = (a[0] / d - b[0] / d, a[1] / d - b[1] / d);
                let dist = (dx * dx + dy * dy).sqrt();
                let k = (dist / input.dr + 0.5).floor() as usize;
                if (1..=r.len()).contains(&k) {
                    counts[k - 1] += 1;
                }
            }
        }
        (n_centres > 0).then(|| normalise(&counts, &r, n_centres, inside.len(), area, d, input))
    }

    #[test]
    fn square_lattice_peaks_at_1_sqrt2_2_with_four_neighbours_each() {
        let d = 6.9e-3;
        let n = 30;
        let pts: Vec<[f64; 2]> = (0..n * n)
            .map(|k| [(k % n) as f64 * d + 0.05, (k / n) as f64 * d])
            .collect();
        // The area tiles the lattice exactly: one point per d^2, so rho = 1 / d^2.
        let area = AnalysedArea {
            x_min: 0.05 - 0.5 * d,
            x_max: 0.05 + (n as f64 - 0.5) * d,
            y_min: -0.5 * d,
            y_max: (n as f64 - 0.5) * d,
        };
        let input = RdfInput::default();
        let rdf = deposit_rdf(&pts, &area, d, &input).unwrap();
        // Lattice distances below 4: 1, sqrt2, 2, sqrt5, sqrt8, 3, sqrt10, sqrt13 with
        // 4, 4, 4, 8, 4, 4, 8, 8 neighbours.
        let shells = [
            (1.0, 4.0),
            (2f64.sqrt(), 4.0),
            (2.0, 4.0),
            (5f64.sqrt(), 8.0),
            (8f64.sqrt(), 4.0),
            (3.0, 4.0),
            (10f64.sqrt(), 8.0),
            (13f64.sqrt(), 8.0),
        ];
        for (k, (&r, &count)) in rdf.r.iter().zip(&rdf.neighbours_per_centre).enumerate() {
            let expected = shells
                .iter()
                .find(|(s, _)| ((s / input.dr + 0.5).floor() as usize) == k + 1)
                .map_or(0.0, |s| s.1);
            assert_eq!(count, expected, "r = {r}");
            let g = expected / (2.0 * std::f64::consts::PI * r * input.dr);
            assert!((rdf.g[k] - g).abs() < 1e-12 * g.max(1.0), "r = {r}");
        }
        assert!((rdf.g[9] - 4.0 / (0.2 * std::f64::consts::PI)).abs() < 1e-12);
    }

    #[test]
    fn uniform_random_points_have_g_one_within_statistical_error() {
        let mut rng = ChaCha8Rng::seed_from_u64(5);
        let d = 3e-3;
        let area = AnalysedArea {
            x_min: 0.0,
            x_max: 0.12,
            y_min: 0.0,
            y_max: 0.12,
        };
        let input = RdfInput::default();
        let series: Vec<Vec<f64>> = (0..40)
            .map(|_| {
                let pts: Vec<[f64; 2]> = (0..1600)
                    .map(|_| [rng.random::<f64>() * 0.12, rng.random::<f64>() * 0.12])
                    .collect();
                deposit_rdf(&pts, &area, d, &input).unwrap().g
            })
            .collect();
        let (g, err) = mean_err_columns(&series);
        let mut chi2 = 0.0;
        for (k, (g, e)) in g.iter().zip(&err).enumerate() {
            // Four standard errors: over 39 bins a false alarm has odds below 1 in 400.
            assert!((g - 1.0).abs() < 4.0 * e, "bin {k}: g = {g} +- {e}");
            chi2 += ((g - 1.0) / e).powi(2);
        }
        // chi^2 with 39 degrees of freedom: mean 39, sd 8.8; 80 is beyond 4 sd.
        assert!(chi2 < 80.0, "chi2 = {chi2}");
    }

    proptest! {
        #![proptest_config(ProptestConfig::with_cases(64))]
        #[test]
        fn kd_tree_equals_brute_force(seed in 0u64..10_000, n in 1usize..400, width in 0.03f64..0.1) {
            let mut rng = ChaCha8Rng::seed_from_u64(seed);
            let d = 3e-3;
            let pts: Vec<[f64; 2]> = (0..n)
                .map(|_| [rng.random::<f64>() * 0.1, rng.random::<f64>() * 0.1])
                .collect();
            let area = AnalysedArea { x_min: 0.0, x_max: width, y_min: 0.01, y_max: 0.1 };
            let input = RdfInput::default();
            let fast = deposit_rdf(&pts, &area, d, &input);
            let slow = brute_force(&pts, &area, d, &input);
            prop_assert_eq!(fast, slow);
        }
    }
}
