use super::{Deposit, Grain};
use crate::grains::GrainKind;

/// The analysis's view of a grain kind: the class a measured grain falls in by its aspect
/// ratio, the name figures and summaries give it, and the angle its outline repeats after.
impl GrainKind {
    /// Aspect-ratio classes with boundaries halfway between the shapes (1, 1.63, 2.97), so
    /// detector noise of a few per cent never moves a grain to another class.
    pub fn of(grain: &Grain) -> GrainKind {
        let aspect = grain.length / grain.width;
        if aspect < 1.3 {
            GrainKind::Square
        } else if aspect < 2.3 {
            GrainKind::ShortRod
        } else {
            GrainKind::LongRod
        }
    }

    /// The plural name figures, summaries and reports give the kind.
    pub fn display_name(self) -> &'static str {
        match self {
            GrainKind::Square => "squares",
            GrainKind::ShortRod => "short rods",
            GrainKind::LongRod => "long rods",
        }
    }

    /// The angle after which the outline looks the same.
    pub fn symmetry_period(self) -> f64 {
        match self {
            GrainKind::Square => std::f64::consts::FRAC_PI_2,
            _ => std::f64::consts::PI,
        }
    }

    /// The one shape of a deposit; a deposit mixing shapes is refused, naming the first grain
    /// (by its line in the table) that differs from the first grain.
    pub fn of_deposit(deposit: &Deposit) -> anyhow::Result<GrainKind> {
        let first = deposit
            .grains
            .first()
            .ok_or_else(|| anyhow::anyhow!("the deposit has no grains"))?;
        let shape = GrainKind::of(first);
        for (k, g) in deposit.grains.iter().enumerate() {
            let s = GrainKind::of(g);
            if s != shape {
                anyhow::bail!(
                    "mixed shapes: line 2 is {} but line {} is {} ({:.2} x {:.2} mm); an ensemble holds one shape",
                    shape.display_name(),
                    k + 2,
                    s.display_name(),
                    g.length * 1e3,
                    g.width * 1e3
                );
            }
        }
        Ok(shape)
    }
}
