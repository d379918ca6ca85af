//! An ensemble of fillings run in parallel, each into its own folder: what `facets sim`,
//! `facets validate` and `facets reproduce` all run. Each filling is deterministic given its
//! scene and seed, so neither the order nor the thread count changes a file.

use std::path::PathBuf;
use std::sync::atomic::AtomicBool;

use anyhow::Context;
use rayon::prelude::*;

use super::checkpoint::Checkpoint;
use super::run::{FillControl, FillOutcome, FillProgress, fill_with};
use crate::scene::Scene;

/// One filling of an ensemble.
#[derive(Clone, Debug)]
pub struct FillJob<'a> {
    /// What errors call the run ("run seed 3 (scene.toml)").
    pub label: String,
    pub scene: &'a Scene,
    pub seed: u64,
    /// The run's folder (created if missing).
    pub dir: PathBuf,
    /// A checkpoint to continue; it must be of the same scene and seed.
    pub resume: Option<PathBuf>,
}

/// What happens to a filling, for a progress display.
#[derive(Clone, Copy, Debug)]
pub enum FillEvent {
    /// Found done by the caller and not run again.
    Reused,
    /// Filling starts (`resumed`: from a checkpoint).
    Started {
        resumed: bool,
    },
    Filling(FillProgress),
    Finished {
        relaxed: bool,
    },
    /// Stopped by the interrupt; a checkpoint continues it.
    Stopped,
}

/// Runs the fillings in parallel; `progress` hears each one's events by its index in `jobs`.
/// `interrupt` (set by Ctrl-C) stops every run at its next step boundary with a checkpoint.
/// One outcome per job, in order: a run that fails does not stop the others.
pub fn fill_all(
    jobs: &[FillJob],
    interrupt: Option<&AtomicBool>,
    progress: &(dyn Fn(usize, FillEvent) + Sync),
) -> Vec<anyhow::Result<FillOutcome>> {
    jobs.par_iter()
        .enumerate()
        .map(|(k, job)| {
            fill_one(job, interrupt, &|event| progress(k, event)).with_context(|| job.label.clone())
        })
        .collect()
}

fn fill_one(
    job: &FillJob,
    interrupt: Option<&AtomicBool>,
    progress: &dyn Fn(FillEvent),
) -> anyhow::Result<FillOutcome> {
    let resume = match &job.resume {
        Some(path) => {
            let checkpoint = Checkpoint::read(path)?;
            checkpoint
                .check_matches(job.scene, job.seed)
                .with_context(|| format!("cannot resume {}", path.display()))?;
            Some(checkpoint)
        }
        None => None,
    };
    progress(FillEvent::Started {
        resumed: resume.is_some(),
    });
    let control = FillControl {
        resume,
        interrupt,
        ..FillControl::default()
    };
    let outcome = fill_with(job.scene, job.seed, &job.dir, control, &mut |p| {
        progress(FillEvent::Filling(p))
    })?;
    progress(match &outcome {
        FillOutcome::Finished(r) => FillEvent::Finished { relaxed: r.relaxed },
        FillOutcome::Stopped { .. } => FillEvent::Stopped,
    });
    Ok(outcome)
}
