//! The grains of the study (docs/model.md §1): square nuts, short rods and long rods.

use std::fmt;
use std::str::FromStr;

use sim::{ShapeError, Spheropolygon};

/// One of the three grain kinds of the experiments, named alike in every command, scene,
/// plan and manifest: `square`, `rod53`, `rod3` (older names are read too).
#[derive(
    Clone, Copy, Debug, PartialEq, Eq, Hash, serde::Serialize, serde::Deserialize, clap::ValueEnum,
)]
pub enum GrainKind {
    /// DIN 557 M4 square nut, 6.9 x 6.9 mm (d = 1).
    #[serde(rename = "square", alias = "squares")]
    #[value(name = "square", alias = "squares")]
    Square,
    /// Steel cylinder 4.9 x 3 mm seen from the side (d = 5/3).
    #[serde(rename = "rod53", alias = "short-rod", alias = "short_rod")]
    #[value(name = "rod53", alias = "short-rod")]
    ShortRod,
    /// Steel cylinder 8.9 x 3 mm seen from the side (d = 3).
    #[serde(rename = "rod3", alias = "long-rod", alias = "long_rod")]
    #[value(name = "rod3", alias = "long-rod")]
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

    /// The command-line names, any case, with the older ones (`squares`, `short-rod`,
    /// `rod5/3`, `long-rod`).
    fn from_str(s: &str) -> Result<Self, Self::Err> {
        match s.trim().to_ascii_lowercase().as_str() {
            "square" | "squares" => Ok(GrainKind::Square),
            "rod53" | "rod5/3" | "short-rod" => Ok(GrainKind::ShortRod),
            "rod3" | "long-rod" => Ok(GrainKind::LongRod),
            _ => Err(format!(
                "unknown grain kind `{s}`: expected square, rod53 (4.9 x 3 mm) or rod3 (8.9 x 3 mm)"
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
        // Files and the command line use the same names.
        for kind in GrainKind::ALL {
            let json = serde_json::to_string(&kind).unwrap();
            assert_eq!(json, format!("\"{}\"", kind.name()));
            let value = clap::ValueEnum::to_possible_value(&kind).unwrap();
            assert_eq!(value.get_name(), kind.name());
            assert_eq!(kind.name().parse::<GrainKind>().unwrap(), kind);
        }
        // Summaries written before the analysis used GrainKind name the rods so.
        for (old, kind) in [
            ("short_rod", GrainKind::ShortRod),
            ("long_rod", GrainKind::LongRod),
        ] {
            let read: GrainKind = serde_json::from_str(&format!("\"{old}\"")).unwrap();
            assert_eq!(read, kind);
        }
        assert!(
            "hexagon"
                .parse::<GrainKind>()
                .unwrap_err()
                .contains("hexagon")
        );
    }
}
