//! The simulated deposits of the vision bench: region E of paper-scale deposits of facets' own
//! simulator, with a margin (data-samples/deposits/bench/README.md says where each comes from),
//! built into the program, and the windows the seeds pick in them.

use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

use crate::deposit::{Deposit, parse_deposit_text};
use crate::photo::Region;

/// A simulated deposit of the bench.
#[derive(Clone, Copy, Debug)]
pub struct SimulatedCase {
    /// The study's case: grain, feed fraction phi0, walls.
    pub name: &'static str,
    /// The grain, by the bench's shape names.
    pub shape: &'static str,
    /// "slow" or "fast" fill.
    pub fill: &'static str,
    table: &'static str,
}

macro_rules! case {
    ($name:literal, $shape:literal, $fill:literal) => {
        SimulatedCase {
            name: $name,
            shape: $shape,
            fill: $fill,
            table: include_str!(concat!(
                "../../../data-samples/deposits/bench/",
                $name,
                "-seed1.csv"
            )),
        }
    };
}

/// Every simulated deposit. There is no paper-scale fast fill of short rods.
pub const CASES: [SimulatedCase; 6] = [
    case!("square-p01-rough", "square", "slow"),
    case!("square-p25-rough", "square", "fast"),
    case!("square-p47-rough", "square", "fast"),
    case!("rod53-p04-rough", "rod53", "slow"),
    case!("rod3-p04-rough", "rod3", "slow"),
    case!("rod3-p25-rough", "rod3", "fast"),
];

/// The silo's width (m): the deposits' x runs from 0 to this.
pub const SILO_WIDTH: f64 = 0.256;
/// Region E's band (m, from the floor).
pub const REGION_E: [f64; 2] = [0.290, 0.410];
/// The band cut from the deposits (m): region E and 25 mm either side.
pub const CUT: [f64; 2] = [0.265, 0.435];
/// How far a grain reaches from its centre (m), at most: half the nut's diagonal.
const REACH: f64 = 4.9e-3;

impl SimulatedCase {
    /// The deposit's grains in the cut band (silo coordinates).
    pub fn deposit(&self) -> anyhow::Result<Deposit> {
        parse_deposit_text(self.table, &format!("{}-seed1.csv (built in)", self.name))
    }

    /// The window of `width` x `height` (m) that `seed` picks: anywhere across the silo, and
    /// up or down from region E's centre as far as the cut band holds every grain it shows.
    pub fn window(width: f64, height: f64, seed: u64) -> anyhow::Result<Region> {
        let low = CUT[0] + REACH;
        let high = CUT[1] - REACH - height;
        if !(width > 0.0 && width <= SILO_WIDTH && height > 0.0 && low <= high) {
            anyhow::bail!(
                "--frame-mm {:.1},{:.1}: the simulated deposits hold windows up to {:.0} x {:.0} mm",
                width * 1e3,
                height * 1e3,
                SILO_WIDTH * 1e3,
                (CUT[1] - CUT[0] - 2.0 * REACH) * 1e3
            );
        }
        let mut rng = ChaCha8Rng::seed_from_u64(seed);
        let x0 = (SILO_WIDTH - width) * rng.random::<f64>();
        // Centred on region E, shifted at most as far as the band allows either way.
        let centred = 0.5 * (REGION_E[0] + REGION_E[1]) - 0.5 * height;
        let shift = (centred - low).min(high - centred);
        let y0 = centred + shift * (2.0 * rng.random::<f64>() - 1.0);
        Ok(Region {
            x0,
            y0,
            width,
            height,
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_deposit_reads_and_fills_its_band_with_its_grain() {
        let shapes = vision::evaluate::bench::shapes();
        for case in CASES {
            let deposit = case.deposit().unwrap();
            let (_, shape) = shapes.iter().find(|(n, _)| *n == case.shape).unwrap();
            assert!(deposit.grains.len() > 500, "{}", case.name);
            for g in &deposit.grains {
                assert!((CUT[0]..=CUT[1]).contains(&g.y), "{}: y {}", case.name, g.y);
                // Between the rough walls' bumps a grain's centre can lie a little beyond x = 0
                // or the silo's width, never a grain's reach.
                assert!(
                    (-REACH..=SILO_WIDTH + REACH).contains(&g.x),
                    "{}: x {}",
                    case.name,
                    g.x
                );
                assert!((g.length - shape.length()).abs() < 1e-6, "{}", case.name);
                assert!((g.width - shape.width()).abs() < 1e-6, "{}", case.name);
            }
        }
    }

    #[test]
    fn windows_stay_in_the_band_and_move_with_the_seed() {
        let full = SimulatedCase::window(SILO_WIDTH, 0.120, 1).unwrap();
        assert_eq!(full.x0, 0.0);
        let windows: Vec<Region> = (0..50)
            .map(|seed| SimulatedCase::window(0.05, 0.120, seed).unwrap())
            .collect();
        for w in &windows {
            assert!(w.x0 >= 0.0 && w.x0 + w.width <= SILO_WIDTH);
            assert!(w.y0 >= CUT[0] + REACH && w.y0 + w.height <= CUT[1] - REACH);
        }
        assert!(windows.iter().any(|w| w.y0 != windows[0].y0));
        assert_eq!(windows[3], SimulatedCase::window(0.05, 0.120, 3).unwrap());
        let too_tall = SimulatedCase::window(0.1, 0.2, 1).unwrap_err().to_string();
        assert!(too_tall.contains("--frame-mm"), "{too_tall}");
    }
}
