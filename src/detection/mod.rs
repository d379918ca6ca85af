//! Photographs of deposits: detection of every grain, written as deposit tables (docs/model.md §4)
//! with confidence and cut columns, a sidecar when the photograph's place in its silo is known,
//! and optional overlays. `facets detect` and `facets reproduce` both detect through
//! [`detect_photo`].

mod in_silo;
mod outline;
mod photos;

use std::path::{Path, PathBuf};

use anyhow::Context;
use vision::{DetectParams, Detection, detect_report};

pub use in_silo::{Framing, InSilo};
pub use outline::{DEFAULT_ROD_WIDTH_MM, MAX_ASPECT, ShapeName, Sought};
pub use photos::{collect_photos, overlay_path, read_photo, refuse_existing, stem, table_paths};

use crate::deposit::{Deposit, Grain, fold_angle, meta_path, write_detected_csv, write_meta_json};
use crate::io::write_atomic;

/// What one photograph gave.
#[derive(Debug)]
pub struct PhotoResult {
    pub table: PathBuf,
    /// The sidecar, when the photograph's place in its silo was given.
    pub sidecar: Option<PathBuf>,
    pub grains: usize,
    pub cut: usize,
    /// Fraction of the photograph's dark pixels the grains found explain ([`vision::Report`]).
    pub explained: Option<f64>,
    /// The detector's wall time step by step ([`vision::Report::phases`]).
    pub phases: vision::Phases,
    /// What the user should know of this photograph ([`vision::Report::warnings`]): why it
    /// has no grains, a scale that disagrees with the one measured.
    pub warnings: Vec<String>,
}

/// Detects the grains of one photograph and writes its table to `table` (and the overlay to
/// `overlay` when given). With `in_silo`, the table is in the silo's coordinates (the
/// photograph's corner added) and its sidecar `NAME.meta.json` is written last, so that a
/// table with a sidecar is complete; a photograph with no grains gets its table too, header
/// only. Every error names the file.
pub fn detect_photo(
    photo: &Path,
    params: &DetectParams,
    table: &Path,
    overlay: Option<&Path>,
    in_silo: Option<&InSilo>,
) -> anyhow::Result<PhotoResult> {
    let image = read_photo(photo, params.max_pixels)?;
    let meta = in_silo
        .map(|s| s.meta(image.width(), image.height(), params.scale / 1e3))
        .transpose()
        .with_context(|| format!("for {}", photo.display()))?;
    let report =
        detect_report(&image, params).with_context(|| format!("in {}", photo.display()))?;
    let found = report.grains;
    if let Some(path) = overlay {
        let drawn = vision::overlay::draw_outlines(&image, &found, params.scale);
        write_atomic(path, |w| {
            drawn.write_to(w, image::ImageFormat::Png)?;
            Ok(())
        })?;
    }
    let corner = in_silo.map_or([0.0, 0.0], InSilo::corner);
    write_detected_csv(table, &shifted(&to_deposit(&found), corner, 1.0))?;
    let sidecar = match meta {
        Some(meta) => {
            let path = meta_path(table);
            write_meta_json(&path, &meta)?;
            Some(path)
        }
        None => None,
    };
    Ok(PhotoResult {
        table: table.to_path_buf(),
        sidecar,
        grains: found.len(),
        cut: found.iter().filter(|d| d.cut).count(),
        explained: report.explained,
        phases: report.phases,
        warnings: report.warnings,
    })
}

/// Detects every photograph of a batch in parallel, each into its table of `tables`
/// ([`table_paths`]) with its overlay when `overlays`; `done` is called after each photograph.
/// One result per photograph, in order: a photograph that fails does not stop the others.
pub fn detect_all(
    photos: &[PathBuf],
    tables: &[PathBuf],
    params: &DetectParams,
    overlays: bool,
    in_silo: Option<&InSilo>,
    done: &(dyn Fn() + Sync),
) -> Vec<anyhow::Result<PhotoResult>> {
    use rayon::prelude::*;
    photos
        .par_iter()
        .zip(tables)
        .map(|(photo, table)| {
            let overlay = overlays.then(|| overlay_path(table));
            let result = detect_photo(photo, params, table, overlay.as_deref(), in_silo);
            done();
            result
        })
        .collect()
}

/// The deposit moved by `sign` x a photograph's corner (mm): +1 from the photograph's to the
/// silo's coordinates, -1 back.
pub fn shifted(deposit: &Deposit, corner_mm: [f64; 2], sign: f64) -> Deposit {
    let mut out = deposit.clone();
    if corner_mm != [0.0, 0.0] {
        for g in &mut out.grains {
            g.x += sign * corner_mm[0] * 1e-3;
            g.y += sign * corner_mm[1] * 1e-3;
        }
    }
    out
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
