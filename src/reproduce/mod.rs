//! `facets reproduce` (issue 6): the whole study from one command. For each shape and phi0 of
//! a [`Plan`]: an ensemble of silo fillings (simulation side); photographs of other fillings
//! (the stand-in experiment) or real photographs (`--photos`); detection; the same analysis on
//! both sides; the figures with both sides overlaid; and `report.md`.
//!
//! One file per stage: [`plan`], [`simulate`], [`photograph`] (or [`manifest`] for real
//! photographs), [`detect`], [`analyse`], [`report`]; [`layout`] says where each writes.
//! Every output is written atomically and every stage skips work whose outputs exist, so a
//! stopped run continues where it stopped.

pub mod analyse;
pub mod detect;
pub mod layout;
pub mod manifest;
pub mod photograph;
pub mod plan;
pub mod report;
pub mod simulate;

use std::path::Path;
use std::time::Instant;

use indicatif::{MultiProgress, ProgressBar, ProgressStyle};

pub use plan::{Plan, ShapePlan};
pub use report::Report;

use crate::io::write_atomic;
use layout::Layout;
use report::StageTime;

/// A bar for one stage (hidden when stderr is not a terminal).
fn stage_bar(stage: &str) -> ProgressBar {
    let style = ProgressStyle::with_template(
        "{prefix:>12} [{bar:40}] {pos}/{len} {msg} ({elapsed} / ETA {eta})",
    )
    .unwrap_or_else(|_| ProgressStyle::default_bar())
    .progress_chars("=> ");
    let bar = ProgressBar::new(0).with_style(style);
    bar.set_prefix(stage.to_string());
    bar
}

/// Runs the plan into `out`; with `photos`, the photographs listed in `photos/manifest.csv`
/// (or `.toml`) are the experiment side instead of rendered ones.
pub fn reproduce(plan: &Plan, photos: Option<&Path>, out: &Path) -> anyhow::Result<Report> {
    plan.validate()?;
    let real_photographs = photos.is_some();
    // Read the manifest before hours of simulation, so that its errors come first.
    let real = photos.map(manifest::read_manifest).transpose()?;
    crate::fill::check_writable(out)?;
    let layout = Layout::new(out);
    write_atomic(&out.join("plan.json"), |w| {
        serde_json::to_writer_pretty(&mut *w, plan)?;
        Ok(())
    })?;
    let mut stages = Vec::new();
    let mut timed = |name: &str, start: Instant| {
        stages.push(StageTime {
            stage: name.to_string(),
            seconds: start.elapsed().as_secs_f64(),
        })
    };

    let start = Instant::now();
    let bars = MultiProgress::new();
    let bar = bars.add(stage_bar("simulate"));
    bar.set_message("fillings");
    let fillings = simulate::fillings(plan, &layout, real.is_none())?;
    let filled = simulate::simulate(&fillings, &bars, &bar)?;
    bar.finish();
    timed("simulate", start);

    let start = Instant::now();
    let bar = stage_bar("photograph");
    bar.set_message("photographs");
    let photos = match real {
        Some(list) => {
            bar.set_length(list.len() as u64);
            bar.set_position(list.len() as u64);
            list
        }
        None => photograph::photograph(plan, &layout, &filled, &bar)?,
    };
    bar.finish();
    timed("photograph", start);

    let start = Instant::now();
    let bar = stage_bar("detect");
    bar.set_message("photographs");
    let detected = detect::detect_all(&photos, &layout, &bar)?;
    bar.finish();
    timed("detect", start);

    let start = Instant::now();
    let bar = stage_bar("analyse");
    let analyses = analyse::analyse_all(plan, &layout, &filled, &detected, &bar)?;
    bar.finish();
    timed("analyse", start);

    let report = report::build(
        plan,
        &layout,
        &filled,
        &detected,
        &analyses,
        stages,
        real_photographs,
    );
    report::write(&report, out)?;
    Ok(report)
}
