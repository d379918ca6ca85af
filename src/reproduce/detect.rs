//! Stage 3: the detector on every photograph of the experiment side. Each table is written in
//! the silo's coordinates (the photograph's origin added) with a sidecar giving the silo
//! width, phi0 and the photographed frame, so the analysis reads it like any deposit. Where a
//! truth table exists, detections are matched to it (`vision::evaluate`, gate D/2) and pooled
//! per (shape, phi0). A table that exists is not detected again; the score is always
//! recomputed from the files.

use std::path::{Path, PathBuf};

use anyhow::Context;
use rayon::prelude::*;
use vision::evaluate::{Tally, Truth, score};
use vision::{DetectParams, Detection};

use super::layout::Layout;
use super::photograph::Photo;
use super::progress::{Event, Progress};
use crate::deposit::{Deposit, meta_path, read_deposit_csv};
use crate::detection::{
    Framing, InSilo, detect_photo, overlay_path, poorly_explained, shifted, stem,
};
use crate::grains::GrainKind;
use crate::photo::outline_of;

/// A detected table of one photograph.
#[derive(Clone, Debug)]
pub struct Detected {
    pub kind: GrainKind,
    pub phi0: f64,
    pub photo: PathBuf,
    pub table: PathBuf,
    pub overlay: Option<PathBuf>,
    /// Matching against the truth, when there is one.
    pub tally: Option<Tally>,
    /// Detector wall time (s); None when the table was found done.
    pub seconds: Option<f64>,
    pub grains: usize,
}

/// The detector's outline for a grain kind (the experiment's nuts and rods).
pub fn shape_of(kind: GrainKind) -> anyhow::Result<vision::GrainShape> {
    Ok(kind.photographed())
}

/// Where the detector's table of a photograph goes.
pub fn table_path(layout: &Layout, kind: GrainKind, phi0: f64, photo: &Path) -> PathBuf {
    layout
        .detected_dir(kind, phi0)
        .join(format!("{}.csv", stem(photo)))
}

/// A table is complete when its sidecar exists (written last).
pub fn table_done(table: &Path) -> bool {
    table.exists() && meta_path(table).exists()
}

/// Detects every photograph (in parallel) and scores those with a truth table. The
/// photographs listed in `overlays` also get an overlay for the report.
pub fn detect_all(
    photos: &[Photo],
    layout: &Layout,
    overlays: &[PathBuf],
    progress: &Progress,
) -> anyhow::Result<Vec<Detected>> {
    progress(Event::Stage {
        stage: "detect",
        counts: "photographs",
        total: photos.len(),
    });
    let results: Vec<anyhow::Result<Detected>> = photos
        .par_iter()
        .map(|p| {
            let overlay = overlays.contains(&p.path);
            let r = detect_one(p, layout, overlay, progress)
                .with_context(|| format!("photograph {}", p.path.display()));
            progress(Event::Done);
            r
        })
        .collect();
    progress(Event::StageEnd);
    results.into_iter().collect()
}

fn detect_one(
    photo: &Photo,
    layout: &Layout,
    want_overlay: bool,
    progress: &Progress,
) -> anyhow::Result<Detected> {
    let table = table_path(layout, photo.kind, photo.phi0, &photo.path);
    let dir = layout.detected_dir(photo.kind, photo.phi0);
    std::fs::create_dir_all(&dir).with_context(|| format!("cannot create {}", dir.display()))?;
    let overlay_path = overlay_path(&table);
    let mut seconds = None;
    if !table_done(&table) {
        let params = DetectParams::new(shape_of(photo.kind)?, photo.px_per_mm * 1e3);
        let in_silo = InSilo {
            silo_width_mm: photo.silo_width_mm,
            phi0: photo.phi0,
            framing: Framing::Corner(photo.origin_mm),
        };
        let overlay = want_overlay.then_some(overlay_path.as_path());
        let result = detect_photo(&photo.path, &params, &table, overlay, Some(&in_silo))?;
        seconds = Some(result.phases.total().as_secs_f64());
        for warning in &result.warnings {
            progress(Event::Warning(&format!(
                "{}: {warning}",
                photo.path.display()
            )));
        }
        let check = "the photograph's shape and px_per_mm in the manifest";
        if let Some(warning) = poorly_explained(&photo.path, result.explained, check) {
            progress(Event::Warning(&warning));
        }
    }
    let deposit = read_deposit_csv(&table)?;
    let tally = match &photo.truth {
        Some(truth) => Some(score_table(&deposit, photo.origin_mm, truth)?),
        None => None,
    };
    Ok(Detected {
        kind: photo.kind,
        phi0: photo.phi0,
        photo: photo.path.clone(),
        table,
        overlay: overlay_path.exists().then_some(overlay_path),
        tally,
        seconds,
        grains: deposit.grains.len(),
    })
}

/// Matches a detected table (silo coordinates) to a truth table (frame coordinates).
fn score_table(detected: &Deposit, origin_mm: [f64; 2], truth: &Path) -> anyhow::Result<Tally> {
    let truth = read_deposit_csv(truth)?;
    let truths: Vec<Truth> = truth
        .grains
        .iter()
        .map(|g| Truth {
            outline: outline_of(g),
            cut: g.cut,
        })
        .collect();
    let detections: Vec<Detection> = shifted(detected, origin_mm, -1.0)
        .grains
        .iter()
        .map(|g| Detection {
            outline: outline_of(g),
            confidence: g.confidence.unwrap_or(1.0),
            cut: g.cut,
        })
        .collect();
    Ok(score(&truths, &detections))
}

/// Detector figures of one (shape, phi0), pooled over its photographs.
#[derive(Clone, Copy, Debug, Default)]
pub struct Accuracy {
    pub photographs: usize,
    pub scored: usize,
    pub tally: Tally,
    /// Mean detector wall time per photograph detected in this run (s).
    pub seconds_per_photo: Option<f64>,
}

pub fn accuracy(detected: &[Detected], kind: GrainKind, phi0: f64) -> Accuracy {
    let mine: Vec<&Detected> = detected
        .iter()
        .filter(|d| d.kind == kind && (d.phi0 - phi0).abs() < 1e-9)
        .collect();
    let mut a = Accuracy {
        photographs: mine.len(),
        ..Accuracy::default()
    };
    for d in &mine {
        if let Some(t) = d.tally {
            a.scored += 1;
            a.tally += t;
        }
    }
    let times: Vec<f64> = mine.iter().filter_map(|d| d.seconds).collect();
    if !times.is_empty() {
        a.seconds_per_photo = Some(times.iter().sum::<f64>() / times.len() as f64);
    }
    a
}
