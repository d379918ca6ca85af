//! Which runs `facets sim` does: consecutive seeds into fresh `seed-N/` folders, or
//! checkpoints to continue; each checked before any simulating.

use std::path::{Path, PathBuf};

use anyhow::Context;

use super::checkpoint::Checkpoint;
use super::earlier::{clear_earlier_run, refuse_earlier_runs};
use super::output::check_writable;
use crate::scene::Scene;

/// What was asked.
#[derive(Clone, Debug)]
pub enum Runs {
    /// `count` runs from seed `first_seed`, into `out/seed-N/`. A folder holding an earlier
    /// run is refused unless `restart`, which clears it.
    Fresh {
        first_seed: u64,
        count: u64,
        out: PathBuf,
        restart: bool,
    },
    /// Continue these checkpoints: of seed `seed` when given (else each checkpoint's own),
    /// into `out/seed-N/` when given (else the checkpoint's folder).
    Resume {
        checkpoints: Vec<PathBuf>,
        seed: Option<u64>,
        out: Option<PathBuf>,
    },
}

/// One run to do.
#[derive(Clone, Debug, PartialEq)]
pub struct PlannedRun {
    pub seed: u64,
    pub dir: PathBuf,
    /// The checkpoint it continues.
    pub resume: Option<PathBuf>,
}

/// The default output folder of a scene file: `runs/SCENE-NAME`.
pub fn default_out(scene_path: &Path) -> PathBuf {
    PathBuf::from("runs").join(scene_path.file_stem().unwrap_or_default())
}

/// The runs asked for, checked before any simulating: folders writable; fresh folders free of
/// earlier runs (or cleared, with `restart`); checkpoints of this scene (`scene_path` names
/// it in errors) and seed, one per seed.
pub fn planned_runs(
    scene: &Scene,
    scene_path: &Path,
    runs: &Runs,
) -> anyhow::Result<Vec<PlannedRun>> {
    let planned = match runs {
        Runs::Fresh {
            first_seed,
            count,
            out,
            ..
        } => {
            anyhow::ensure!(*count >= 1, "--realisations 0: expected at least one run");
            (0..*count)
                .map(|k| PlannedRun {
                    seed: first_seed + k,
                    dir: out.join(format!("seed-{}", first_seed + k)),
                    resume: None,
                })
                .collect()
        }
        Runs::Resume {
            checkpoints,
            seed,
            out,
        } => resumed(scene, scene_path, checkpoints, *seed, out.as_deref())?,
    };
    for run in &planned {
        check_writable(&run.dir)?;
    }
    if let Runs::Fresh { restart, .. } = runs {
        let dirs: Vec<PathBuf> = planned.iter().map(|r| r.dir.clone()).collect();
        if *restart {
            for dir in &dirs {
                clear_earlier_run(dir)?;
            }
        } else {
            refuse_earlier_runs(&dirs)?;
        }
    }
    Ok(planned)
}

fn resumed(
    scene: &Scene,
    scene_path: &Path,
    checkpoints: &[PathBuf],
    seed: Option<u64>,
    out: Option<&Path>,
) -> anyhow::Result<Vec<PlannedRun>> {
    let mut planned: Vec<PlannedRun> = Vec::new();
    for path in checkpoints {
        let checkpoint = Checkpoint::read(path)?;
        let seed = seed.unwrap_or(checkpoint.seed());
        checkpoint.check_matches(scene, seed).with_context(|| {
            format!(
                "cannot resume {} with scene {} and seed {seed}",
                path.display(),
                scene_path.display()
            )
        })?;
        anyhow::ensure!(
            planned.iter().all(|r| r.seed != seed),
            "--resume: two checkpoints of seed {seed}"
        );
        let dir = match out {
            Some(out) => out.join(format!("seed-{seed}")),
            None => path
                .parent()
                .filter(|p| !p.as_os_str().is_empty())
                .map_or_else(|| PathBuf::from("."), Path::to_path_buf),
        };
        planned.push(PlannedRun {
            seed,
            dir,
            resume: Some(path.clone()),
        });
    }
    Ok(planned)
}
