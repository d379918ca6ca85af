//! Stage 1: the fillings of every case and seed that are not done yet, in parallel, each into
//! OUT/CASE/seed-N/ with the files of `facets sim` and the case's scene as `scene.toml`.
//!
//! A seed is done when its deposit.csv and run.json exist (`fill` writes every file
//! atomically and run.json last). A seed folder holding a `checkpoint.bin` continues it. A
//! folder whose `scene.toml` differs from the case's scene is refused, not overwritten: it
//! holds runs of another scene (the study was edited), and its deposits would be measured as
//! this case's.

use std::io::Write;
use std::path::{Path, PathBuf};
use std::sync::atomic::AtomicBool;

use anyhow::Context;

use super::study::{Case, Study};
use crate::fill::{CHECKPOINT_FILE, FillEvent, FillJob, FillOutcome, fill_all};
use crate::io::write_atomic;

/// One realisation: a seed of a case and its folder.
#[derive(Clone, Debug)]
pub struct Job {
    /// Index of the case in the study.
    pub case: usize,
    pub case_name: String,
    pub seed: u64,
    pub dir: PathBuf,
}

/// What the stage did.
#[derive(Clone, Debug, Default)]
pub struct RunSummary {
    pub ran: usize,
    pub reused: usize,
    /// Checkpoints of the runs an interrupt stopped.
    pub stopped: Vec<PathBuf>,
    /// Runs written but not relaxed within the scene's time (case, seed).
    pub unrelaxed: Vec<(String, u64)>,
}

/// Every (case, seed) of the study, in the study's order.
pub fn jobs(study: &Study, out: &Path) -> Vec<Job> {
    study
        .cases
        .iter()
        .enumerate()
        .flat_map(|(k, case)| {
            case.seeds.iter().map(move |&seed| Job {
                case: k,
                case_name: case.name.clone(),
                seed,
                dir: out.join(&case.name).join(format!("seed-{seed}")),
            })
        })
        .collect()
}

/// The run in `dir` is complete.
pub fn is_done(dir: &Path) -> bool {
    dir.join("deposit.csv").is_file() && dir.join("run.json").is_file()
}

/// Runs the jobs not done yet, in parallel ([`fill_all`]); a seed folder holding a checkpoint
/// continues it. `interrupt` (set by Ctrl-C) stops the runs at their next step boundary with
/// a checkpoint each.
pub fn run_missing(
    study: &Study,
    jobs: &[Job],
    interrupt: Option<&AtomicBool>,
    progress: &(dyn Fn(&Job, FillEvent) + Sync),
) -> anyhow::Result<RunSummary> {
    // Refuse folders of another scene before anything is simulated.
    for job in jobs {
        check_scene(&study.cases[job.case], job)?;
    }
    let mut summary = RunSummary::default();
    let mut todo = Vec::new();
    let mut fills = Vec::new();
    for job in jobs {
        if is_done(&job.dir) {
            progress(job, FillEvent::Reused);
            summary.reused += 1;
            continue;
        }
        let case = &study.cases[job.case];
        std::fs::create_dir_all(&job.dir)
            .with_context(|| format!("cannot create {}", job.dir.display()))?;
        write_atomic(&job.dir.join("scene.toml"), |w| {
            Ok(w.write_all(case.scene_toml.as_bytes())?)
        })?;
        let checkpoint = job.dir.join(CHECKPOINT_FILE);
        fills.push(FillJob {
            label: format!("case `{}` seed {}", case.name, job.seed),
            scene: &case.scene,
            seed: job.seed,
            dir: job.dir.clone(),
            resume: checkpoint.is_file().then_some(checkpoint),
        });
        todo.push(job);
    }
    let outcomes = fill_all(&fills, interrupt, &|k, event| progress(todo[k], event));
    for (job, outcome) in todo.iter().zip(outcomes) {
        match outcome? {
            FillOutcome::Finished(record) => {
                summary.ran += 1;
                if !record.relaxed {
                    summary.unrelaxed.push((job.case_name.clone(), job.seed));
                }
            }
            FillOutcome::Stopped { checkpoint, .. } => summary.stopped.push(checkpoint),
        }
    }
    Ok(summary)
}

/// Refuses a seed folder whose `scene.toml` is not the case's scene.
pub fn check_scene(case: &Case, job: &Job) -> anyhow::Result<()> {
    let path = job.dir.join("scene.toml");
    match std::fs::read_to_string(&path) {
        Ok(text) if text != case.scene_toml => anyhow::bail!(
            "{} holds a run of another scene than case `{}` now gives ({}): remove the folder or rename the case",
            job.dir.display(),
            case.name,
            case.scene_file
        ),
        _ => Ok(()),
    }
}
