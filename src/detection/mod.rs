//! Photographs of deposits: detection of every grain, written as deposit tables (docs/model.md §4)
//! with confidence and cut columns, and optional overlays.

use std::path::{Path, PathBuf};

use anyhow::{Context, bail};
use vision::{DetectParams, Detection, GrainShape, detect_report};

use crate::deposit::{Deposit, Grain, fold_angle};
use crate::grains::GrainKind;
use crate::io::write_atomic;

/// The rods of the experiments by nominal aspect ratio.
const RODS: [(f64, GrainKind); 2] = [(5.0 / 3.0, GrainKind::ShortRod), (3.0, GrainKind::LongRod)];

/// The longest rod accepted, in widths: 60 mm rods of 3 mm are no grains of these silos, and
/// the detector's blocks and searches grow with the length.
pub const MAX_ASPECT: f64 = 20.0;

/// The grain outline for `--shape` and `--aspect`: squares are the experiment's nuts; rods
/// of nominal aspect 5/3 or 3 are the experiment's 4.9 and 8.9 mm cylinders, any other
/// aspect d gives a rod of length d x 3 mm.
pub fn grain_shape(square: bool, aspect: f64) -> anyhow::Result<GrainShape> {
    // The outlines are built as the benchmark builds its own (`vision::evaluate::bench::shapes`),
    // to the last bit: a length an ulp off (4.9 x 1e-3 against 4.9e-3) changed which rods
    // a benchmark photograph's detection fitted turned.
    if square {
        return Ok(GrainShape::nut(GrainKind::Square.length()));
    }
    if !(aspect.is_finite() && (1.0..=MAX_ASPECT).contains(&aspect)) {
        bail!(
            "--aspect (rod length / width) is {aspect}, expected a number from 1 to {MAX_ASPECT}"
        );
    }
    let width = GrainKind::LongRod.width();
    let length = RODS
        .iter()
        .find(|(d, _)| (aspect / d - 1.0).abs() < 0.05)
        .map_or(aspect * width, |&(_, kind)| kind.length());
    Ok(GrainShape::Rod { length, width })
}

/// Parses an aspect ratio written as a number ("3", "1.63") or a fraction ("5/3").
pub fn parse_aspect(text: &str) -> Result<f64, String> {
    let value = match text.split_once('/') {
        Some((n, d)) => {
            let n: f64 = n
                .trim()
                .parse()
                .map_err(|_| format!("'{text}' is not a ratio"))?;
            let d: f64 = d
                .trim()
                .parse()
                .map_err(|_| format!("'{text}' is not a ratio"))?;
            n / d
        }
        None => text
            .trim()
            .parse()
            .map_err(|_| format!("'{text}' is not a number"))?,
    };
    if value.is_finite() && (1.0..=MAX_ASPECT).contains(&value) {
        Ok(value)
    } else {
        Err(format!(
            "aspect ratio (rod length / width) must be a number from 1 to {MAX_ASPECT}, got '{text}'"
        ))
    }
}

/// The photographs named: files as given, folders expanded to the PNG/TIFF/JPEG files they
/// hold (sorted, so a batch runs in a reproducible order).
pub fn collect_photos(inputs: &[PathBuf]) -> anyhow::Result<Vec<PathBuf>> {
    let mut photos = Vec::new();
    for input in inputs {
        if input.is_dir() {
            let mut found: Vec<PathBuf> = std::fs::read_dir(input)
                .with_context(|| format!("cannot read folder {}", input.display()))?
                .filter_map(|e| e.ok().map(|e| e.path()))
                .filter(|p| p.is_file() && is_photo(p))
                .collect();
            found.sort();
            photos.extend(found);
        } else {
            photos.push(input.clone());
        }
    }
    Ok(photos)
}

fn is_photo(path: &Path) -> bool {
    let ext = path
        .extension()
        .and_then(|e| e.to_str())
        .unwrap_or("")
        .to_ascii_lowercase();
    matches!(ext.as_str(), "png" | "tif" | "tiff" | "jpg" | "jpeg")
}

/// What one photograph gave.
#[derive(Debug)]
pub struct PhotoResult {
    pub table: PathBuf,
    pub grains: usize,
    pub cut: usize,
    /// Fraction of the photograph's dark pixels the grains found explain ([`vision::Report`]).
    pub explained: Option<f64>,
    /// The detector's wall time step by step ([`vision::Report::phases`]).
    pub phases: vision::Phases,
}

/// Detects the grains of one photograph and writes `<stem>.csv` (and `<stem>_overlay.png`)
/// in `out_dir`. Every error names the file.
pub fn detect_photo(
    photo: &Path,
    params: &DetectParams,
    out_dir: &Path,
    overlay: bool,
) -> anyhow::Result<PhotoResult> {
    let image = read_photo(photo, params.max_pixels)?;
    let report =
        detect_report(&image, params).with_context(|| format!("in {}", photo.display()))?;
    let found = report.grains;
    let stem = photo
        .file_stem()
        .and_then(|s| s.to_str())
        .unwrap_or("photo");
    let table = out_dir.join(format!("{stem}.csv"));
    crate::deposit::write_deposit_csv(&table, &to_deposit(&found))?;
    if overlay {
        let drawn = vision::overlay::draw_outlines(&image, &found, params.scale);
        let path = out_dir.join(format!("{stem}_overlay.png"));
        write_atomic(&path, |w| {
            drawn.write_to(w, image::ImageFormat::Png)?;
            Ok(())
        })?;
    }
    Ok(PhotoResult {
        table,
        grains: found.len(),
        cut: found.iter().filter(|d| d.cut).count(),
        explained: report.explained,
        phases: report.phases,
    })
}

/// The detector's steps on one photograph as a line: each step's wall time, then the total
/// (seconds).
pub fn steps_line(phases: &vision::Phases) -> String {
    let steps: Vec<String> = phases
        .iter()
        .map(|(name, time)| format!("{name} {:.3}", time.as_secs_f64()))
        .collect();
    format!(
        "{}; total {:.3} s",
        steps.join(", "),
        phases.total().as_secs_f64()
    )
}

/// The warning for a photograph whose dark area the grains found leave largely unexplained
/// (`explained` below [`vision::WELL_EXPLAINED`]), if it is: `check` names what the user
/// should look at.
pub fn poorly_explained(photo: &Path, explained: Option<f64>, check: &str) -> Option<String> {
    let explained = explained.filter(|&e| e < vision::WELL_EXPLAINED)?;
    Some(format!(
        "{}: the grains found explain only {:.0} % of the dark area, below the {:.0} % that the \
         right outline exceeds on every benchmark photograph: the grains may not be the ones \
         asked for; check {check}",
        photo.display(),
        100.0 * explained,
        100.0 * vision::WELL_EXPLAINED,
    ))
}

/// Decodes a photograph, refusing one larger than `max_pixels` before decoding it.
pub fn read_photo(path: &Path, max_pixels: u64) -> anyhow::Result<image::DynamicImage> {
    let open = || {
        image::ImageReader::open(path)
            .and_then(|r| r.with_guessed_format())
            .with_context(|| format!("cannot open photograph {}", path.display()))
    };
    let (w, h) = open()?.into_dimensions().with_context(|| {
        format!(
            "{} is not a readable PNG, TIFF or JPEG image",
            path.display()
        )
    })?;
    if w as u64 * h as u64 > max_pixels {
        bail!(
            "{} is {w} x {h} px; at most {} megapixels are accepted (larger photographs are \
             processed in tiles, but their decoded pixels alone would not fit in memory): split \
             it into overlapping parts",
            path.display(),
            max_pixels / 1_000_000
        );
    }
    open()?.decode().with_context(|| {
        format!(
            "{} is not a readable PNG, TIFF or JPEG image",
            path.display()
        )
    })
}

/// Deposit table rows, theta folded by the grain's symmetry.
pub fn to_deposit(found: &[Detection]) -> Deposit {
    let grains = found
        .iter()
        .map(|d| {
            let o = d.outline;
            Grain {
                x: o.x,
                y: o.y,
                theta: fold_angle(o.theta, o.shape.symmetry_period()),
                length: o.shape.length(),
                width: o.shape.width(),
                confidence: Some(d.confidence),
                cut: d.cut,
            }
        })
        .collect();
    Deposit { grains }
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
        assert_eq!(grain_shape(true, 1.0).unwrap(), of("square"));
        assert_eq!(grain_shape(false, 5.0 / 3.0).unwrap(), of("rod53"));
        assert_eq!(grain_shape(false, 1.633).unwrap(), of("rod53"));
        assert_eq!(grain_shape(false, 3.0).unwrap(), of("rod3"));
    }

    #[test]
    fn other_aspects_give_rods_three_millimetres_wide() {
        let rod = grain_shape(false, 2.0).unwrap();
        assert_eq!(rod.width(), 3e-3);
        assert!((rod.length() - 6e-3).abs() < 1e-15);
        assert!(grain_shape(false, 0.5).is_err());
    }
}
