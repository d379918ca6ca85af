//! The detector's speed-for-accuracy options, shared by `detect` and `bench vision`.

use clap::Args as ClapArgs;
use vision::Shortcuts;

/// What the detector may leave out to go faster. Each costs accuracy: "Speed against accuracy"
/// in docs/results/detector-bench.md measures what, and `facets bench vision` with the same
/// options measures it again.
#[derive(Debug, ClapArgs)]
pub struct ShortcutArgs {
    /// Sweeps of settling at the end, each grain refined again against its neighbours where
    /// they ended up. Default 2 for rods (lab, 10 px/mm: orientation error of the rods not
    /// turned 0.62 -> 0.27 degrees, centre 0.07 -> 0.04 mm, about 0.2 s a photograph) and 0
    /// for nuts (1 sweep: 0.34 -> 0.20 degrees, about 0.1-0.2 s more a photograph).
    #[arg(long)]
    pub settle_sweeps: Option<usize>,
    /// Coarse poses of each fit refined at full resolution (default 3). One is about 20 %
    /// faster for rods and turns more of them (lab rod53 at 10 px/mm, seeds 1-4: 3.8 -> 2.9 s
    /// a photograph, 0.81 -> 1.04 degrees).
    #[arg(long, value_parser = clap::value_parser!(u32).range(1..))]
    pub finalists: Option<u32>,
    /// Leave out the rods' repairs but the rows' (those of rods turned across their
    /// neighbours, left out, crowded or fitted outside the frame): about 40 % faster, and
    /// more rods turned (lab rod53 at 10 px/mm, seeds 1-4: 3.8 -> 2.2 s a photograph, 0.81
    /// -> 1.82 degrees, recall 99.92 -> 99.78 %).
    #[arg(long)]
    pub no_repairs: bool,
    /// Leave out the joint relaxation of all poses (image misfit plus overlap) that ends the
    /// detector of nuts (the rods' leaves it out already: it did not change their figures):
    /// about 4 s of one core less a full frame, and nuts in gap-free lattices fitted
    /// turned again (a held-out simulated deposit of nuts, lab, 10 px/mm: 0.37 -> 2.35 degrees,
    /// 0 -> 2 nuts turned).
    #[arg(long)]
    pub no_relax: bool,
}

impl ShortcutArgs {
    pub fn shortcuts(&self) -> Shortcuts {
        Shortcuts {
            finalists: self.finalists.map(|n| n as usize),
            settle_sweeps: self.settle_sweeps,
            no_repairs: self.no_repairs,
            no_relax: self.no_relax,
        }
    }

    /// The options taken, as they were given (`none` when none), for a table's heading and
    /// its CSV column.
    pub fn describe(&self) -> String {
        let mut taken = Vec::new();
        if let Some(n) = self.finalists {
            taken.push(format!("--finalists {n}"));
        }
        if let Some(n) = self.settle_sweeps {
            taken.push(format!("--settle-sweeps {n}"));
        }
        if self.no_repairs {
            taken.push("--no-repairs".to_string());
        }
        if self.no_relax {
            taken.push("--no-relax".to_string());
        }
        if taken.is_empty() {
            "none".to_string()
        } else {
            taken.join(" ")
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_options_taken_are_described_as_given() {
        let none = ShortcutArgs {
            settle_sweeps: None,
            finalists: None,
            no_repairs: false,
            no_relax: false,
        };
        assert_eq!(none.describe(), "none");
        assert_eq!(none.shortcuts(), Shortcuts::default());
        let all = ShortcutArgs {
            settle_sweeps: Some(0),
            finalists: Some(1),
            no_repairs: true,
            no_relax: true,
        };
        assert_eq!(
            all.describe(),
            "--finalists 1 --settle-sweeps 0 --no-repairs --no-relax"
        );
        let params = all.shortcuts().apply(vision::DetectParams::new(
            vision::GrainShape::nut(6.9e-3),
            1e4,
        ));
        assert_eq!(
            (
                params.finalists,
                params.settle_sweeps,
                params.repairs,
                params.relax
            ),
            (1, 0, false, false)
        );
    }
}
