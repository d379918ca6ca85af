//! The outline `facets detect --shape` seeks: one of the experiment's grains by name, or a rod
//! of a size given in millimetres.

use anyhow::bail;
use vision::GrainShape;

use crate::grains::GrainKind;

/// The longest rod accepted, in widths: 60 mm rods of 3 mm are no grains of these silos, and
/// the detector's blocks and searches grow with the length.
pub const MAX_ASPECT: f64 = 20.0;

/// Width of a custom rod when only its length is given (mm): the experiment's rods'.
pub const DEFAULT_ROD_WIDTH_MM: f64 = 3.0;

/// `--shape`: a grain kind by its name (as every command names it), or `rod`, a rod of the
/// size given.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ShapeName {
    Kind(GrainKind),
    Rod,
}

impl clap::ValueEnum for ShapeName {
    fn value_variants<'a>() -> &'a [Self] {
        &[
            ShapeName::Kind(GrainKind::Square),
            ShapeName::Kind(GrainKind::ShortRod),
            ShapeName::Kind(GrainKind::LongRod),
            ShapeName::Rod,
        ]
    }

    fn to_possible_value(&self) -> Option<clap::builder::PossibleValue> {
        match self {
            ShapeName::Kind(kind) => kind.to_possible_value(),
            ShapeName::Rod => Some(
                clap::builder::PossibleValue::new("rod")
                    .help("Rods of another size: give --length-mm (and --width-mm, default 3)"),
            ),
        }
    }
}

/// What to seek in the photographs.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Sought {
    /// One of the experiment's grains (square, rod53, rod3).
    Kind(GrainKind),
    /// A rod of another size (`--shape rod --length-mm L [--width-mm D]`).
    Rod {
        length_mm: Option<f64>,
        width_mm: Option<f64>,
    },
}

impl Sought {
    /// The outline the options name: a grain kind, or (`--shape rod`) a rod of the size
    /// given. A size given with a grain kind is refused: the kind has its own.
    pub fn new(
        shape: ShapeName,
        length_mm: Option<f64>,
        width_mm: Option<f64>,
    ) -> anyhow::Result<Sought> {
        match shape {
            ShapeName::Rod => Ok(Sought::Rod {
                length_mm,
                width_mm,
            }),
            ShapeName::Kind(kind) if length_mm.is_none() && width_mm.is_none() => {
                Ok(Sought::Kind(kind))
            }
            ShapeName::Kind(kind) => bail!(
                "--length-mm and --width-mm give the size of a custom rod (--shape rod); \
                 --shape {kind} has its own ({} x {} mm)",
                kind.length() * 1e3,
                kind.width() * 1e3
            ),
        }
    }

    /// The outline, checked: a custom rod needs its length, and its size must be a rod's.
    /// The experiment's grains are the benchmark's outlines to the last bit: a length an ulp
    /// off (4.9 x 1e-3 against 4.9e-3) changed which rods a benchmark photograph's detection
    /// fitted turned. A custom rod of the size of one of them is that one.
    pub fn shape(self) -> anyhow::Result<GrainShape> {
        let (length_mm, width_mm) = match self {
            Sought::Kind(kind) => return Ok(kind.photographed()),
            Sought::Rod {
                length_mm: None, ..
            } => bail!(
                "--shape rod needs the rods' size: --length-mm L (and --width-mm D, default \
                 {DEFAULT_ROD_WIDTH_MM} mm); the experiment's rods are --shape rod53 (4.9 x 3 mm) \
                 and --shape rod3 (8.9 x 3 mm)"
            ),
            Sought::Rod {
                length_mm: Some(l),
                width_mm,
            } => (l, width_mm.unwrap_or(DEFAULT_ROD_WIDTH_MM)),
        };
        if !(width_mm.is_finite() && width_mm > 0.0) {
            bail!("--width-mm is {width_mm}, expected a rod width above 0 mm");
        }
        if !(length_mm.is_finite() && length_mm >= width_mm && length_mm <= MAX_ASPECT * width_mm) {
            bail!(
                "--length-mm is {length_mm}, expected a rod length from its width (--width-mm, \
                 {width_mm} mm) to {MAX_ASPECT} widths ({} mm)",
                MAX_ASPECT * width_mm
            );
        }
        let same = |kind: GrainKind| {
            (length_mm * 1e-3 - kind.length()).abs() < 1e-9
                && (width_mm * 1e-3 - kind.width()).abs() < 1e-9
        };
        if let Some(kind) = [GrainKind::ShortRod, GrainKind::LongRod]
            .into_iter()
            .find(|&k| same(k))
        {
            return Ok(kind.photographed());
        }
        Ok(GrainShape::Rod {
            length: length_mm * 1e-3,
            width: width_mm * 1e-3,
        })
    }

    /// The options that chose this outline, as given, for a warning to name.
    pub fn options(self) -> String {
        match self {
            Sought::Kind(kind) => format!("--shape (given {kind})"),
            Sought::Rod {
                length_mm,
                width_mm,
            } => format!(
                "--shape rod, --length-mm (given {}) and --width-mm (given {})",
                length_mm.map_or("none".to_string(), |v| v.to_string()),
                width_mm.unwrap_or(DEFAULT_ROD_WIDTH_MM)
            ),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// `facets detect` on a benchmark photograph must look for the outline the benchmark
    /// looked for, bit for bit, or it finds other grains than the benchmark reports.
    #[test]
    fn the_command_line_seeks_the_benchmarks_outlines() {
        let bench = vision::evaluate::bench::shapes();
        let of = |name: &str| bench.iter().find(|(n, _)| *n == name).unwrap().1;
        for kind in GrainKind::ALL {
            assert_eq!(Sought::Kind(kind).shape().unwrap(), of(kind.name()));
        }
        let rod = |l: f64, w: Option<f64>| Sought::Rod {
            length_mm: Some(l),
            width_mm: w,
        };
        assert_eq!(rod(4.9, None).shape().unwrap(), of("rod53"));
        assert_eq!(rod(8.9, Some(3.0)).shape().unwrap(), of("rod3"));
    }

    #[test]
    fn custom_rods_are_checked_by_option() {
        let rod = |l: Option<f64>, w: Option<f64>| {
            Sought::Rod {
                length_mm: l,
                width_mm: w,
            }
            .shape()
        };
        let custom = rod(Some(6.0), None).unwrap();
        assert_eq!(custom.width(), 3e-3);
        assert!((custom.length() - 6e-3).abs() < 1e-15);
        let e = rod(None, None).unwrap_err().to_string();
        assert!(e.contains("--length-mm") && e.contains("rod53"), "{e}");
        for (l, w, option) in [
            (1.0, None, "--length-mm"),
            (f64::NAN, None, "--length-mm"),
            (100.0, None, "--length-mm"),
            (6.0, Some(0.0), "--width-mm"),
            (6.0, Some(f64::INFINITY), "--width-mm"),
        ] {
            let e = rod(Some(l), w).unwrap_err().to_string();
            assert!(e.contains(option), "{l} {w:?}: {e}");
        }
    }
}
