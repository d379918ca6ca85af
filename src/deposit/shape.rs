use serde::{Deserialize, Serialize};

use super::{Deposit, Grain};
use crate::grains::GrainKind;

/// The three grain shapes of the experiment (docs/model.md §1) as the analysis tells them
/// apart in a table, by aspect ratio L/D: the [`GrainKind`] of each class, with the names
/// the figures and summaries give it.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Shape {
    /// Square nuts, d = 1.
    Square,
    /// Short rods, d = 5/3.
    ShortRod,
    /// Long rods, d = 3.
    LongRod,
}

impl From<GrainKind> for Shape {
    fn from(kind: GrainKind) -> Self {
        match kind {
            GrainKind::Square => Shape::Square,
            GrainKind::ShortRod => Shape::ShortRod,
            GrainKind::LongRod => Shape::LongRod,
        }
    }
}

impl Shape {
    /// Aspect-ratio classes with boundaries halfway between the shapes (1, 1.63, 2.97), so
    /// detector noise of a few per cent never moves a grain to another class.
    pub fn of(grain: &Grain) -> Shape {
        let aspect = grain.length / grain.width;
        if aspect < 1.3 {
            Shape::Square
        } else if aspect < 2.3 {
            Shape::ShortRod
        } else {
            Shape::LongRod
        }
    }

    pub fn name(self) -> &'static str {
        match self {
            Shape::Square => "squares",
            Shape::ShortRod => "short rods",
            Shape::LongRod => "long rods",
        }
    }

    /// The grain kind of this class.
    pub fn kind(self) -> GrainKind {
        match self {
            Shape::Square => GrainKind::Square,
            Shape::ShortRod => GrainKind::ShortRod,
            Shape::LongRod => GrainKind::LongRod,
        }
    }

    /// docs/model.md §2: nuts 20.3 kg/m^2 (net of the hole, over the square outline), rods 18.5 kg/m^2.
    pub fn default_areal_density(self) -> f64 {
        self.kind().areal_density()
    }

    /// The angle after which the outline looks the same.
    pub fn symmetry_period(self) -> f64 {
        match self {
            Shape::Square => std::f64::consts::FRAC_PI_2,
            _ => std::f64::consts::PI,
        }
    }

    /// The one shape of a deposit; a deposit mixing shapes is refused, naming the first grain
    /// (by its line in the table) that differs from the first grain.
    pub fn of_deposit(deposit: &Deposit) -> anyhow::Result<Shape> {
        let first = deposit
            .grains
            .first()
            .ok_or_else(|| anyhow::anyhow!("the deposit has no grains"))?;
        let shape = Shape::of(first);
        for (k, g) in deposit.grains.iter().enumerate() {
            let s = Shape::of(g);
            if s != shape {
                anyhow::bail!(
                    "mixed shapes: line 2 is {} but line {} is {} ({:.2} x {:.2} mm); an ensemble holds one shape",
                    shape.name(),
                    k + 2,
                    s.name(),
                    g.length * 1e3,
                    g.width * 1e3
                );
            }
        }
        Ok(shape)
    }
}
