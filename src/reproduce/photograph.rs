//! Stage 2: the stand-in experiment. Each photographed filling (seeds the simulation side never
//! uses) is photographed over its frame (region E at paper scale, full width), with the truth
//! table beside the photograph for scoring the detector. A photograph and its truth that both
//! exist are not rendered again.

use std::path::PathBuf;

use anyhow::Context;
use rayon::prelude::*;
use vision::render::Style;

use super::layout::Layout;
use super::plan::Plan;
use super::progress::{Event, Progress};
use super::simulate::{Filled, Side};
use crate::deposit::read_deposit_csv;
use crate::grains::GrainKind;
use crate::photo::{Region, frame_deposit, photograph_frame, write_photograph};

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
    let truth = crate::photo::truth_path(&path);
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
    let region = Region::of_frame(&frame_mm);
    let frame = photograph_frame(&region, plan.photo_px_per_mm)?;
    let deposit = read_deposit_csv(&f.deposit())?;
    let (outlines, truth_table) = frame_deposit(&deposit, &region, &frame);
    if let Some(dir) = path.parent() {
        std::fs::create_dir_all(dir).with_context(|| format!("cannot create {}", dir.display()))?;
    }
    write_photograph(&path, &outlines, &truth_table, &frame, style, f.seed, 8)?;
    Ok(photo)
}
