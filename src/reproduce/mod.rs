//! `facets reproduce` (issue 6): the whole study from one command. For each shape and phi0 of
//! a [`Plan`]: an ensemble of silo fillings (simulation side); photographs of other fillings
//! (the stand-in experiment) or real photographs (`--photos`); detection; the same analysis on
//! both sides; the figures with both sides overlaid; and `report.md`.
//!
//! One file per stage, in order: [`plan`], [`simulate`], [`photograph`] (or [`manifest`] for
//! real photographs), [`detect`], [`analyse`], [`report`]; [`layout`] says where each writes.
//! Every output is written atomically and every stage skips work whose outputs exist, so a
//! stopped run continues where it stopped.
//!
//! Beyond one machine: [`shard`] splits the first three stages' work into independent units
//! ([`reproduce_shard`] runs one share, [`collect`] the last two stages once all are done),
//! and [`slurm`] writes the batch scripts that run the shares as a Slurm job array.

pub mod analyse;
pub mod detect;
pub mod layout;
pub mod manifest;
pub mod photograph;
pub mod plan;
pub mod progress;
pub mod report;
pub mod shard;
pub mod simulate;
pub mod slurm;

use std::path::Path;
use std::time::Instant;

pub use plan::{Plan, ShapePlan};
pub use progress::{Event, Progress};
pub use report::Report;
pub use shard::Shard;

use crate::io::write_atomic;
use layout::Layout;
use report::StageTime;
use shard::Unit;

/// Runs the plan into `out`; with `photos`, the photographs listed in `photos/manifest.csv`
/// (or `.toml`) are the experiment side instead of rendered ones. `progress` hears each
/// stage's advance ([`Event`]).
pub fn reproduce(
    plan: &Plan,
    photos: Option<&Path>,
    out: &Path,
    progress: &Progress,
) -> anyhow::Result<Report> {
    let study = Study::prepare(plan, photos, out)?;
    let done = study.produce(None, progress)?;
    study.finish(done, progress)
}

/// What one task ([`reproduce_shard`]) did.
#[derive(Clone, Debug)]
pub struct ShardDone {
    /// Indices of the task's units in the plan's list, and the list's length.
    pub units: Vec<usize>,
    pub of: usize,
    pub fillings_run: usize,
    pub fillings_reused: usize,
    pub stages: Vec<StageTime>,
}

/// Runs the share `shard` of the plan's units (fillings, photographs, detections) into `out`;
/// [`collect`] analyses and reports once every task is done.
pub fn reproduce_shard(
    plan: &Plan,
    photos: Option<&Path>,
    out: &Path,
    shard: Shard,
    progress: &Progress,
) -> anyhow::Result<ShardDone> {
    let study = Study::prepare(plan, photos, out)?;
    let done = study.produce(Some(shard), progress)?;
    Ok(ShardDone {
        units: (0..study.units.len()).filter(|&k| shard.takes(k)).collect(),
        of: study.units.len(),
        fillings_run: done.filled.iter().filter(|f| !f.reused).count(),
        fillings_reused: done.filled.iter().filter(|f| f.reused).count(),
        stages: done.stages,
    })
}

/// Analyses, draws and reports a plan whose units are all done (by [`reproduce_shard`] tasks
/// or an earlier run); refuses, naming every missing unit, otherwise. With `tasks`, the
/// message also names the task of `tasks` that runs each missing unit.
pub fn collect(
    plan: &Plan,
    photos: Option<&Path>,
    out: &Path,
    tasks: Option<usize>,
    progress: &Progress,
) -> anyhow::Result<Report> {
    let study = Study::prepare(plan, photos, out)?;
    let missing = shard::missing(&study.units, &study.layout);
    if !missing.is_empty() {
        let lines: Vec<String> = missing
            .iter()
            .map(|(k, what)| match tasks {
                Some(n) if n > 0 => format!("  unit {k} (task {} of {n}): {what}", k % n),
                _ => format!("  unit {k}: {what}"),
            })
            .collect();
        anyhow::bail!(
            "cannot collect {}: {} of {} units are not done (unit k is run by task k mod N of --tasks N):\n{}",
            out.display(),
            missing.len(),
            study.units.len(),
            lines.join("\n")
        );
    }
    let done = study.produce(None, progress)?;
    study.finish(done, progress)
}

/// A plan, its output folder and its list of units.
struct Study<'a> {
    plan: &'a Plan,
    out: &'a Path,
    layout: Layout,
    units: Vec<Unit>,
    real_photographs: bool,
}

/// What the producing stages gave.
struct Produced {
    filled: Vec<simulate::Filled>,
    detected: Vec<detect::Detected>,
    stages: Vec<StageTime>,
}

impl<'a> Study<'a> {
    fn prepare(plan: &'a Plan, photos: Option<&Path>, out: &'a Path) -> anyhow::Result<Self> {
        plan.validate()?;
        // Read the manifest before hours of simulation, so that its errors come first.
        let real = photos.map(manifest::read_manifest).transpose()?;
        crate::fill::check_writable(out)?;
        let layout = Layout::new(out);
        write_atomic(&out.join("plan.json"), |w| {
            serde_json::to_writer_pretty(&mut *w, plan)?;
            Ok(())
        })?;
        let real_photographs = real.is_some();
        let fillings = simulate::fillings(plan, &layout, real.is_none())?;
        Ok(Study {
            plan,
            out,
            units: shard::units(fillings, real),
            layout,
            real_photographs,
        })
    }

    /// The stages that make files, in order: simulate, photograph, detect; over every unit,
    /// or over one share of them.
    fn produce(&self, shard: Option<Shard>, progress: &Progress) -> anyhow::Result<Produced> {
        let mine = |k: usize| shard.is_none_or(|s| s.takes(k));
        let mut fillings = Vec::new();
        let mut real = Vec::new();
        for (_, unit) in self.units.iter().enumerate().filter(|(k, _)| mine(*k)) {
            match unit {
                Unit::Filling(f) => fillings.push((**f).clone()),
                Unit::Photo(p) => real.push(p.clone()),
            }
        }
        let mut stages = Vec::new();
        let mut timed = |name: &str, start: Instant| {
            stages.push(StageTime {
                stage: name.to_string(),
                seconds: start.elapsed().as_secs_f64(),
            })
        };

        let start = Instant::now();
        let filled = simulate::simulate(&fillings, progress)?;
        timed("simulate", start);

        let start = Instant::now();
        let mut photos = photograph::photograph(self.plan, &self.layout, &filled, progress)?;
        photos.extend(real);
        timed("photograph", start);

        let start = Instant::now();
        let overlays = shard::overlay_photos(&self.units, &self.layout);
        let detected = detect::detect_all(&photos, &self.layout, &overlays, progress)?;
        timed("detect", start);
        Ok(Produced {
            filled,
            detected,
            stages,
        })
    }

    /// The stages that read every unit's files: analyse, then the report.
    fn finish(&self, done: Produced, progress: &Progress) -> anyhow::Result<Report> {
        let Produced {
            filled,
            detected,
            mut stages,
        } = done;
        let start = Instant::now();
        let analyses = analyse::analyse_all(self.plan, &self.layout, &filled, &detected, progress)?;
        stages.push(StageTime {
            stage: "analyse".into(),
            seconds: start.elapsed().as_secs_f64(),
        });
        let report = report::build(
            self.plan,
            &self.layout,
            &filled,
            &detected,
            &analyses,
            stages,
            self.real_photographs,
        );
        report::write(&report, self.out)?;
        Ok(report)
    }
}
