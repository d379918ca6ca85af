//! Stage 1: the silo fillings of both sides, in parallel, each into its own folder. A filling
//! whose `run.json` exists for the same scene and seed is not run again: `fill` writes
//! `run.json` last and every file atomically, so its presence means the run is complete.

use std::path::{Path, PathBuf};

use anyhow::Context;
use serde::Deserialize;

use super::layout::Layout;
use super::plan::Plan;
use super::progress::{Event, Progress};
use crate::deposit::FrameMm;
use crate::fill::{FillEvent, FillJob, FillOutcome, RunRecord, fill_all};
use crate::grains::GrainKind;
use crate::io::write_atomic;
use crate::scene::Scene;

/// Which side a filling belongs to.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Side {
    Simulation,
    Photographed,
}

/// One filling to run (or found done).
#[derive(Clone, Debug)]
pub struct Filling {
    pub kind: GrainKind,
    pub phi0: f64,
    pub seed: u64,
    pub side: Side,
    pub dir: PathBuf,
    pub scene: Scene,
    /// The scene as written to `scene.toml`; a run is reused only when its file says the same.
    pub scene_toml: String,
}

impl Filling {
    pub fn deposit(&self) -> PathBuf {
        self.dir.join("deposit.csv")
    }

    /// How progress and errors call it.
    pub fn name(&self) -> String {
        format!("{} phi0 {} seed {}", self.kind.name(), self.phi0, self.seed)
    }
}

/// What the later stages need of a run's `run.json`. Read as its own struct, not as the
/// whole `RunRecord`: JSON writes the record's NaN fields (a feed rate measured on fewer than
/// two bands) as null, which do not read back as f64.
#[derive(Clone, Debug, Deserialize)]
pub struct RunSummary {
    pub seed: u64,
    pub relaxed: bool,
    pub frame_mm: Option<FrameMm>,
}

impl From<&RunRecord> for RunSummary {
    fn from(r: &RunRecord) -> Self {
        RunSummary {
            seed: r.seed,
            relaxed: r.relaxed,
            frame_mm: r.frame_mm,
        }
    }
}

/// A finished filling and what it recorded.
#[derive(Clone, Debug)]
pub struct Filled {
    pub filling: Filling,
    pub record: RunSummary,
    /// True when the run was found done and not run again.
    pub reused: bool,
}

/// The fillings of the plan; `photographed` false leaves out the photographed side (real
/// photographs given).
pub fn fillings(plan: &Plan, layout: &Layout, photographed: bool) -> anyhow::Result<Vec<Filling>> {
    let mut out = Vec::new();
    for shape in &plan.shapes {
        for &phi0 in &shape.phi0s {
            let scene = plan.scene(shape, phi0)?;
            let scene_toml = plan.scene_toml(shape, phi0);
            let mut sides = vec![(Side::Simulation, plan.simulation_seeds())];
            if photographed {
                sides.push((Side::Photographed, plan.photo_seeds()));
            }
            for (side, seeds) in sides {
                for seed in seeds {
                    out.push(Filling {
                        kind: shape.kind,
                        phi0,
                        seed,
                        side,
                        dir: layout.run_dir(shape.kind, phi0, side, seed),
                        scene: scene.clone(),
                        scene_toml: scene_toml.clone(),
                    });
                }
            }
        }
    }
    Ok(out)
}

/// The record of a complete earlier run of the same scene and seed, if there is one. The
/// scene is compared as the text of `scene.toml` (exact, unlike floats read back from JSON);
/// a rerun deletes `run.json` before it rewrites `scene.toml`, so an interrupted rerun is
/// never taken for a finished one.
pub fn done(filling: &Filling) -> Option<RunSummary> {
    let scene = std::fs::read_to_string(filling.dir.join("scene.toml")).ok()?;
    let text = std::fs::read_to_string(filling.dir.join("run.json")).ok()?;
    let record: RunSummary = serde_json::from_str(&text).ok()?;
    let complete =
        scene == filling.scene_toml && record.seed == filling.seed && filling.deposit().exists();
    complete.then_some(record)
}

/// Runs every filling not yet done, in parallel ([`fill_all`]; each run is deterministic
/// given its scene and seed, so the order and the thread count do not change any file).
/// Reports one stage item per filling and each running filling's events.
pub fn simulate(fillings: &[Filling], progress: &Progress) -> anyhow::Result<Vec<Filled>> {
    progress(Event::Stage {
        stage: "simulate",
        counts: "fillings",
        total: fillings.len(),
    });
    let mut found: Vec<Option<RunSummary>> = Vec::with_capacity(fillings.len());
    let mut todo = Vec::new();
    for (k, f) in fillings.iter().enumerate() {
        let record = done(f);
        if record.is_some() {
            progress(Event::Done);
        } else {
            write_scene(&f.dir, &f.scene_toml)?;
            todo.push(k);
        }
        found.push(record);
    }
    let jobs: Vec<FillJob> = todo
        .iter()
        .map(|&k| {
            let f = &fillings[k];
            FillJob {
                label: format!(
                    "filling {} phi0 = {} seed {} ({})",
                    f.kind.name(),
                    f.phi0,
                    f.seed,
                    f.dir.display()
                ),
                scene: &f.scene,
                seed: f.seed,
                dir: f.dir.clone(),
                resume: None,
            }
        })
        .collect();
    let names: Vec<String> = todo.iter().map(|&k| fillings[k].name()).collect();
    let outcomes = fill_all(&jobs, None, &|j, event| {
        progress(Event::Filling(&names[j], event));
        if matches!(event, FillEvent::Finished { .. } | FillEvent::Stopped) {
            progress(Event::Done);
        }
    });
    let mut ran = outcomes.into_iter();
    let mut filled = Vec::with_capacity(fillings.len());
    for (f, record) in fillings.iter().zip(found) {
        let (record, reused) = match record {
            Some(record) => (record, true),
            None => match ran
                .next()
                .context("a filling neither found done nor run")??
            {
                FillOutcome::Finished(record) => (RunSummary::from(&*record), false),
                FillOutcome::Stopped { .. } => {
                    anyhow::bail!("filling {} stopped before its end", f.name())
                }
            },
        };
        filled.push(Filled {
            filling: f.clone(),
            record,
            reused,
        });
    }
    progress(Event::StageEnd);
    Ok(filled)
}

/// `scene.toml` beside the run: `facets sim scene.toml --seed N` runs it again.
fn write_scene(dir: &Path, text: &str) -> anyhow::Result<()> {
    std::fs::create_dir_all(dir).with_context(|| format!("cannot create {}", dir.display()))?;
    let stale = dir.join("run.json");
    if stale.exists() {
        std::fs::remove_file(&stale)
            .with_context(|| format!("cannot remove the stale {}", stale.display()))?;
    }
    write_atomic(&dir.join("scene.toml"), |w| {
        use std::io::Write;
        Ok(w.write_all(text.as_bytes())?)
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::reproduce::plan::Plan;

    #[test]
    fn a_finished_run_is_found_done_even_with_null_fields_and_a_changed_scene_is_not() {
        let dir = tempfile::tempdir().unwrap();
        let plan = Plan::tiny();
        let layout = Layout::new(dir.path());
        let f = fillings(&plan, &layout, true).unwrap().remove(0);
        std::fs::create_dir_all(&f.dir).unwrap();
        std::fs::write(f.dir.join("scene.toml"), &f.scene_toml).unwrap();
        std::fs::write(f.deposit(), "x_mm,y_mm,theta_rad,length_mm,width_mm\n").unwrap();
        // As fill writes it: a feed rate measured on fewer than two bands is NaN -> null.
        let run = format!(
            r#"{{"seed": {}, "relaxed": false, "feed_rate_measured_per_s": null,
                "frame_mm": {{"x_min": 0, "x_max": 120, "y_min": 0, "y_max": 40}}}}"#,
            f.seed
        );
        std::fs::write(f.dir.join("run.json"), run).unwrap();
        let found = done(&f).expect("the run is complete");
        assert!(!found.relaxed);
        assert_eq!(found.frame_mm.unwrap().x_max, 120.0);
        // Another scene in the same folder (a plan edited between runs) is run again.
        let edited = format!("{}\n[run]\nseed = {}\n", f.scene_toml, f.seed + 1);
        assert_ne!(edited, f.scene_toml);
        std::fs::write(f.dir.join("scene.toml"), edited).unwrap();
        assert!(done(&f).is_none());
    }
}
