//! The grains of the study (docs/model.md §1): square nuts, short rods and long rods.

use std::fmt;
use std::str::FromStr;

use sim::{ShapeError, Spheropolygon};

/// One of the three grain kinds of the experiments.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum GrainKind {
    /// DIN 557 M4 square nut, 6.9 x 6.9 mm (d = 1).
    Square,
    /// Steel cylinder 4.9 x 3 mm seen from the side (d = 5/3).
    ShortRod,
    /// Steel cylinder 8.9 x 3 mm seen from the side (d = 3).
    LongRod,
}

/// Rounding radius of the DEM outline as a fraction of the width D (docs/model.md §2 default).
pub const DEFAULT_ROUNDING: f64 = 0.05;

impl GrainKind {
    pub const ALL: [GrainKind; 3] = [GrainKind::Square, GrainKind::ShortRod, GrainKind::LongRod];

    /// Outline length (m).
    pub fn length(self) -> f64 {
        match self {
            GrainKind::Square => 6.9e-3,
            GrainKind::ShortRod => 4.9e-3,
            GrainKind::LongRod => 8.9e-3,
        }
    }

    /// Outline width D (m).
    pub fn width(self) -> f64 {
        match self {
            GrainKind::Square => 6.9e-3,
            GrainKind::ShortRod | GrainKind::LongRod => 3e-3,
        }
    }

    /// Mass per unit outline area (kg/m^2): steel nuts 3.16 mm thick less the hole; steel
    /// cylinders seen from the side.
    pub fn areal_density(self) -> f64 {
        match self {
            GrainKind::Square => 20.3,
            GrainKind::ShortRod | GrainKind::LongRod => 18.5,
        }
    }

    /// The DEM outline: the L x D rectangle with corners rounded by `rounding` x D.
    pub fn outline(self, rounding: f64) -> Result<Spheropolygon, ShapeError> {
        Spheropolygon::rounded_rectangle(self.length(), self.width(), rounding * self.width())
    }

    /// The outline the photograph tools draw and seek (`vision`): the nut with its hole for
    /// squares, the rectangle for rods.
    pub fn photographed(self) -> vision::GrainShape {
        match self {
            GrainKind::Square => vision::GrainShape::nut(self.length()),
            GrainKind::ShortRod | GrainKind::LongRod => vision::GrainShape::Rod {
                length: self.length(),
                width: self.width(),
            },
        }
    }

    /// Short name used on the command line and in file names.
    pub fn name(self) -> &'static str {
        match self {
            GrainKind::Square => "square",
            GrainKind::ShortRod => "rod53",
            GrainKind::LongRod => "rod3",
        }
    }
}

impl fmt::Display for GrainKind {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

impl FromStr for GrainKind {
    type Err = String;

    fn from_str(s: &str) -> Result<Self, Self::Err> {
        match s {
            "square" | "squares" => Ok(GrainKind::Square),
            "rod53" | "short-rod" => Ok(GrainKind::ShortRod),
            "rod3" | "long-rod" => Ok(GrainKind::LongRod),
            other => Err(format!(
                "unknown grain kind `{other}`: expected square, rod53 (4.9 x 3 mm) or rod3 (8.9 x 3 mm)"
            )),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn masses_match_the_experiments() {
        // docs/model.md §2: ~0.97 g nuts, 0.27 g and 0.49 g rods.
        for (kind, grams) in [
            (GrainKind::Square, 0.97),
            (GrainKind::ShortRod, 0.27),
            (GrainKind::LongRod, 0.49),
        ] {
            let (m, _) = kind
                .outline(DEFAULT_ROUNDING)
                .unwrap()
                .mass_properties(kind.areal_density())
                .unwrap();
            assert!((m * 1e3 - grams).abs() < 0.01, "{kind}: {} g", m * 1e3);
        }
        assert_eq!("rod3".parse::<GrainKind>().unwrap(), GrainKind::LongRod);
        assert!(
            "hexagon"
                .parse::<GrainKind>()
                .unwrap_err()
                .contains("hexagon")
        );
    }
}
