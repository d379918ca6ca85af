//! What a deposit table alone does not say: the silo it lies in, the photographed frame, the
//! control parameter phi0, where it came from.
//!
//! Convention (sidecars): a deposit table `NAME.csv` may have beside it
//! - `NAME.meta.json` — a [`DepositMeta`], e.g.
//!   `{"silo_width_mm": 256, "phi0": 0.1, "frame_mm": {"x_min": 0, "x_max": 256, "y_min": 290,
//!   "y_max": 410}, "source": "simulation"}`; unknown fields are an error;
//! - `NAME.contacts.csv` — the contact table of a simulated deposit (docs/model.md §4).
//!
//! Without a sidecar the command line supplies `phi0` and the silo width (`facets analyse
//! --phi0 --silo-width-mm`); the frame then defaults to the silo's whole width and the height of
//! the deposit.

use std::path::{Path, PathBuf};

use anyhow::{Context, bail};
use serde::{Deserialize, Serialize};

use super::Deposit;
use crate::grains::GrainKind;

const MM: f64 = 1e-3;

/// A rectangle in millimetres, as written in the sidecar.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct FrameMm {
    pub x_min: f64,
    pub x_max: f64,
    pub y_min: f64,
    pub y_max: f64,
}

impl FrameMm {
    /// How every command writes a frame (`--frame-mm`): x_min,x_max,y_min,y_max in mm.
    pub const SYNTAX: &'static str = "x_min,x_max,y_min,y_max";

    /// Reads `x_min,x_max,y_min,y_max` (mm) and checks it ([`FrameMm::check`]); the error
    /// says what was expected, the caller names the option.
    pub fn parse(text: &str) -> Result<FrameMm, String> {
        let values: Vec<f64> = text
            .split(',')
            .map(|v| v.trim().parse::<f64>())
            .collect::<Result<_, _>>()
            .map_err(|e| {
                format!(
                    "`{text}`: {e}; expected four numbers {} in mm",
                    Self::SYNTAX
                )
            })?;
        let [x_min, x_max, y_min, y_max] = values[..] else {
            return Err(format!(
                "`{text}` has {} values, expected four: {} in mm",
                values.len(),
                Self::SYNTAX
            ));
        };
        let frame = FrameMm {
            x_min,
            x_max,
            y_min,
            y_max,
        };
        frame.check("the frame").map_err(|e| e.to_string())?;
        Ok(frame)
    }

    /// Refuses a frame that is not a finite rectangle of positive size, naming it `name` (an
    /// option or a field).
    pub fn check(&self, name: &str) -> anyhow::Result<()> {
        let f = self;
        let ok = [f.x_min, f.x_max, f.y_min, f.y_max]
            .iter()
            .all(|v| v.is_finite())
            && f.x_max > f.x_min
            && f.y_max > f.y_min;
        if !ok {
            bail!(
                "{name} is {},{},{},{} mm, expected finite {} with x_min < x_max and \
                 y_min < y_max",
                f.x_min,
                f.x_max,
                f.y_min,
                f.y_max,
                Self::SYNTAX
            );
        }
        Ok(())
    }

    pub fn width_mm(&self) -> f64 {
        self.x_max - self.x_min
    }

    pub fn height_mm(&self) -> f64 {
        self.y_max - self.y_min
    }
}

/// Where a deposit came from; experiment and simulation are drawn in two styles.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Serialize, Deserialize, Default)]
#[serde(rename_all = "lowercase")]
pub enum Source {
    #[default]
    Experiment,
    Simulation,
}

/// The sidecar `NAME.meta.json`.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct DepositMeta {
    /// Silo width W between the side walls (mm); x = 0 is the left wall.
    pub silo_width_mm: f64,
    /// Volume fraction of the falling rain that built the deposit.
    pub phi0: f64,
    /// The part of the silo the table covers (a photograph's frame; a simulation's whole box).
    /// Default: the whole width, from the floor to the top of the deposit.
    #[serde(default)]
    pub frame_mm: Option<FrameMm>,
    /// Mass per area of one grain's outline (kg/m^2). Default: docs/model.md §2 (nuts 20.3, rods 18.5).
    #[serde(default)]
    pub areal_density_kg_m2: Option<f64>,
    /// Gravity (m/s^2). Default 10 (docs/model.md §2).
    #[serde(default)]
    pub gravity_m_s2: Option<f64>,
    #[serde(default)]
    pub source: Source,
}

impl DepositMeta {
    /// Checks the numbers, naming the field that is wrong.
    pub fn validate(&self) -> anyhow::Result<()> {
        self.check(&|field| format!("field `{field}`"))
    }

    /// The sidecar given as command-line options (`--phi0`, `--silo-width-mm`, `--frame-mm`,
    /// `--source`) for tables without one, checked; None when none is given.
    pub fn from_options(
        phi0: Option<f64>,
        silo_width_mm: Option<f64>,
        frame_mm: Option<FrameMm>,
        source: Source,
    ) -> anyhow::Result<Option<DepositMeta>> {
        match (phi0, silo_width_mm) {
            (Some(phi0), Some(silo_width_mm)) => {
                let meta = DepositMeta {
                    silo_width_mm,
                    phi0,
                    frame_mm,
                    areal_density_kg_m2: None,
                    gravity_m_s2: None,
                    source,
                };
                meta.validate_options()?;
                Ok(Some(meta))
            }
            (None, None) if frame_mm.is_some() => bail!(
                "--frame-mm is the frame of deposits without a sidecar: it needs --phi0 and \
                 --silo-width-mm"
            ),
            (None, None) => Ok(None),
            _ => bail!("--phi0 and --silo-width-mm go together"),
        }
    }

    /// [`DepositMeta::validate`] of a sidecar given as command-line options (`--phi0`,
    /// `--silo-width-mm`, `--frame-mm`), naming the option that is wrong.
    pub fn validate_options(&self) -> anyhow::Result<()> {
        self.check(&|field| format!("--{}", field.replace('_', "-")))
    }

    fn check(&self, name: &dyn Fn(&str) -> String) -> anyhow::Result<()> {
        if !(self.silo_width_mm.is_finite() && self.silo_width_mm > 80.0) {
            bail!(
                "{} is {}, expected a width above 80 mm (40 mm are cut at each wall)",
                name("silo_width_mm"),
                self.silo_width_mm
            );
        }
        if !(self.phi0.is_finite() && self.phi0 > 0.0 && self.phi0 < 1.0) {
            bail!(
                "{} is {}, expected a volume fraction in (0, 1)",
                name("phi0"),
                self.phi0
            );
        }
        if let Some(f) = self.frame_mm {
            f.check(&name("frame_mm"))?;
        }
        for (field, v) in [
            ("areal_density_kg_m2", self.areal_density_kg_m2),
            ("gravity_m_s2", self.gravity_m_s2),
        ] {
            if let Some(v) = v {
                if !(v.is_finite() && v > 0.0) {
                    bail!("{} is {v}, expected a positive number", name(field));
                }
            }
        }
        Ok(())
    }

    pub fn silo_width(&self) -> f64 {
        self.silo_width_mm * MM
    }

    pub fn gravity(&self) -> f64 {
        self.gravity_m_s2.unwrap_or(10.0)
    }

    pub fn areal_density(&self, shape: GrainKind) -> f64 {
        self.areal_density_kg_m2
            .unwrap_or_else(|| shape.areal_density())
    }

    /// The frame in metres as [x_min, x_max, y_min, y_max]; by default the whole width from the
    /// floor to the top of the highest grain.
    pub fn frame(&self, deposit: &Deposit) -> [f64; 4] {
        match self.frame_mm {
            Some(f) => [f.x_min * MM, f.x_max * MM, f.y_min * MM, f.y_max * MM],
            None => {
                let top = deposit
                    .grains
                    .iter()
                    .map(|g| g.y + 0.5 * g.length)
                    .fold(0.0, f64::max);
                [0.0, self.silo_width(), 0.0, top]
            }
        }
    }
}

/// `NAME.meta.json` beside `NAME.csv`.
pub fn meta_path(deposit_csv: &Path) -> PathBuf {
    sibling(deposit_csv, "meta.json")
}

/// `NAME.contacts.csv` beside `NAME.csv`.
pub fn contacts_path(deposit_csv: &Path) -> PathBuf {
    sibling(deposit_csv, "contacts.csv")
}

fn sibling(deposit_csv: &Path, suffix: &str) -> PathBuf {
    let stem = deposit_csv
        .file_stem()
        .map(|s| s.to_string_lossy().into_owned())
        .unwrap_or_default();
    deposit_csv.with_file_name(format!("{stem}.{suffix}"))
}

/// Reads and checks a sidecar; errors name the file and the field.
pub fn read_meta_json(path: &Path) -> anyhow::Result<DepositMeta> {
    let text =
        std::fs::read_to_string(path).with_context(|| format!("cannot open {}", path.display()))?;
    let meta: DepositMeta = serde_json::from_str(&text)
        .with_context(|| format!("in deposit sidecar {}", path.display()))?;
    meta.validate()
        .with_context(|| format!("in deposit sidecar {}", path.display()))?;
    Ok(meta)
}

/// Writes a sidecar atomically.
pub fn write_meta_json(path: &Path, meta: &DepositMeta) -> anyhow::Result<()> {
    crate::io::write_atomic(path, |w| {
        serde_json::to_writer_pretty(&mut *w, meta)?;
        Ok(())
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_frame_is_read_in_one_syntax_and_checked() {
        let f = FrameMm::parse("0, 160,-5,150").unwrap();
        assert_eq!(
            [f.x_min, f.x_max, f.y_min, f.y_max],
            [0.0, 160.0, -5.0, 150.0]
        );
        for bad in [
            "0,160,0",
            "0,160,0,150,1",
            "a,160,0,150",
            "160,0,0,150",
            "0,160,0,NaN",
        ] {
            let e = FrameMm::parse(bad).unwrap_err();
            assert!(e.contains("x_min,x_max,y_min,y_max"), "{bad}: {e}");
        }
    }

    #[test]
    fn sidecar_errors_name_the_field() {
        let dir = tempfile::tempdir().unwrap();
        let p = dir.path().join("d.meta.json");
        std::fs::write(&p, r#"{"silo_width_mm": 256, "phi0": 1.5}"#).unwrap();
        let e = format!("{:#}", read_meta_json(&p).unwrap_err());
        assert!(e.contains("phi0") && e.contains("d.meta.json"), "{e}");
        std::fs::write(&p, r#"{"silo_width_mm": 256, "phi0": 0.1, "colour": 3}"#).unwrap();
        let e = format!("{:#}", read_meta_json(&p).unwrap_err());
        assert!(e.contains("colour"), "{e}");
        assert_eq!(
            meta_path(Path::new("a/run1.csv")),
            Path::new("a/run1.meta.json")
        );
        assert_eq!(
            contacts_path(Path::new("a/run1.csv")),
            Path::new("a/run1.contacts.csv")
        );
    }
}
