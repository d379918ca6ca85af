//! Stage 2: the stand-in experiment. Each photographed filling (seeds the simulation side never
//! uses) is photographed over its frame (region E at paper scale, full width), with the truth
//! table beside the photograph for scoring the detector. A photograph and its truth that both
//! exist are not rendered again.

use std::path::PathBuf;

use anyhow::Context;
use image::ImageFormat;
use rayon::prelude::*;
use vision::Frame;
use vision::render::{Style, render};

use super::layout::Layout;
use super::plan::Plan;
use super::progress::{Event, Progress};
use super::simulate::{Filled, Side};
use crate::deposit::{read_deposit_csv, write_deposit_csv};
use crate::grains::GrainKind;
use crate::io::write_atomic;
use crate::photo::{Region, frame_deposit};

/// A photograph of the experiment side, rendered or real.
#[derive(Clone, Debug)]
pub struct Photo {
    pub kind: GrainKind,
    pub phi0: f64,
    pub path: PathBuf,
    pub px_per_mm: f64,
    /// Ground truth (frame coordinates, as `facets render` writes), when known.
    pub truth: Option<PathBuf>,
    pub silo_width_mm: f64,
    /// Bottom-left corner of the photograph in the silo (mm; x from the left wall, y from
    /// the floor).
    pub origin_mm: [f64; 2],
    /// Seed of the noise, dust and light of a rendered photograph.
    pub seed: u64,
}

impl Photo {
    pub fn truth_path(path: &std::path::Path) -> PathBuf {
        path.with_extension("truth.csv")
    }
}

/// Renders a photograph of every photographed filling.
pub fn photograph(
    plan: &Plan,
    layout: &Layout,
    filled: &[Filled],
    progress: &Progress,
) -> anyhow::Result<Vec<Photo>> {
    let style = Style::named(&plan.photo_style)
        .with_context(|| format!("unknown photo style {:?}", plan.photo_style))?;
    let todo: Vec<&Filled> = filled
        .iter()
        .filter(|f| f.filling.side == Side::Photographed)
        .collect();
    progress(Event::Stage {
        stage: "photograph",
        counts: "photographs",
        total: todo.len(),
    });
    let photos: Vec<anyhow::Result<Photo>> = todo
        .par_iter()
        .map(|f| {
            let result = photograph_one(plan, layout, f, &style);
            progress(Event::Done);
            result
        })
        .collect();
    progress(Event::StageEnd);
    photos.into_iter().collect()
}

fn photograph_one(
    plan: &Plan,
    layout: &Layout,
    filled: &Filled,
    style: &Style,
) -> anyhow::Result<Photo> {
    let f = &filled.filling;
    let frame_mm = filled.record.frame_mm.with_context(|| {
        format!(
            "{}: run.json has no frame_mm",
            f.dir.join("run.json").display()
        )
    })?;
    let silo_width_mm = f.scene.silo.width_mm;
    let path = layout.photo(f.kind, f.phi0, f.seed);
    let truth = Photo::truth_path(&path);
    let photo = Photo {
        kind: f.kind,
        phi0: f.phi0,
        path: path.clone(),
        px_per_mm: plan.photo_px_per_mm,
        truth: Some(truth.clone()),
        silo_width_mm,
        origin_mm: [frame_mm.x_min, frame_mm.y_min],
        seed: f.seed,
    };
    if path.exists() && truth.exists() {
        return Ok(photo);
    }
    let region = Region {
        x0: frame_mm.x_min * 1e-3,
        y0: frame_mm.y_min * 1e-3,
        width: (frame_mm.x_max - frame_mm.x_min) * 1e-3,
        height: (frame_mm.y_max - frame_mm.y_min) * 1e-3,
    };
    let frame = Frame {
        width: region.width,
        height: region.height,
        scale: plan.photo_px_per_mm * 1e3,
    };
    let deposit = read_deposit_csv(&f.deposit())?;
    let (outlines, truth_table) = frame_deposit(&deposit, &region, &frame);
    let image = render(&outlines, &frame, style, f.seed).to_image(8);
    if let Some(dir) = path.parent() {
        std::fs::create_dir_all(dir).with_context(|| format!("cannot create {}", dir.display()))?;
    }
    // Truth first: a photograph on disk always has its truth beside it.
    write_deposit_csv(&truth, &truth_table)?;
    write_atomic(&path, |w| {
        image.write_to(w, ImageFormat::Png)?;
        Ok(())
    })?;
    Ok(photo)
}
