//! Speed against error of the filling's settings (issue 3, docs/model.md §5): each faster setting runs
//! the same reference scenes and seeds as the paper-faithful one, and its ensemble is compared
//! with the faithful ensemble.
//!
//! With `reuse`, a scene x setting whose K runs are already in the output folder, made by the
//! same version from the same scene and seeds (`group.json`), is not run again: its times are
//! the ones recorded. Adding a setting to a finished bench costs only the new setting's runs,
//! as long as the engine has not changed in between (nothing can check that).
//!
//! For every scene x setting, the K seeds run in parallel (rayon over runs; each run is
//! deterministic given scene and seed, so the deposits, and every deviation, do not depend on
//! the thread count; only the times do). Times are those of the K runs together: wall time,
//! and processor time of the process (user + system, all threads). The speed-up is the
//! faithful setting's processor time over the setting's: on a shared machine the wall time
//! also measures the other processes.
//!
//! Deviations from the faithful ensemble, each in units of the standard error (s: the setting,
//! ref: faithful; means and standard errors over the K realisations; se = sd / sqrt(K)):
//!
//! - packing fraction: |phi_s - phi_ref| / sqrt(se_s^2 + se_ref^2);
//! - f(theta), 5-degree bins over one period:
//!   sum_k |f_s,k - f_ref,k| / sum_k sqrt(se_s,k^2 + se_ref,k^2);
//! - g(r), the same L1 form over the bins with r < 4 D;
//! - pressure -sigma_yy on the centre line against depth below the free surface, over the
//!   depths both ensembles reach: sqrt(mean_k (p_s,k - p_ref,k)^2) /
//!   sqrt(mean_k (se_s,k^2 + se_ref,k^2)).
//!
//! Under the null (both ensembles drawn from one distribution) each term is of order one. With
//! standard errors estimated from K = 8 runs the scalar is |t| with about 14 degrees of freedom:
//! mean 0.82, above 2 in 6.5 % of cases. The L1 form is a weighted mean of the bins' |t_k|: mean
//! about 0.8, and for 18 independent bins next to never above 2. The RMS form is about 1
//! (tests/bench_fill.rs checks these numbers on synthetic ensembles). A setting is "within 2
//! standard errors" when all four are <= 2 ([`WITHIN`]). Neighbouring bins of g(r) and of the
//! smoothed pressure are correlated, which makes the L1 and RMS forms spread more than
//! independent bins would; with one scalar among four, about one faithful-equivalent setting
//! in twelve would still fail on phi_f alone: read values near 2 as borderline, not verdicts.
//!
//! Each scene alone can stay within 2 while the packing fraction shifts the same way in all of
//! them (session 9: dt = t_c / 8 gave -1.31, -0.93 and -1.34, phi_f 0.018-0.026 low). So the
//! signed packing-fraction deviations are also pooled over the scenes, sum z_i / sqrt(n)
//! ([`pooled_phi_shift`]), and the candidate for the defaults must keep that within 2 too.

mod deviation;
mod measures;
mod report;
mod settings;

use std::path::{Path, PathBuf};
use std::time::Instant;

use anyhow::Context;
use rayon::prelude::*;
use serde::{Deserialize, Serialize};

use super::process::cpu_time;
use crate::deposit::{Ensemble, LoadOptions, load_realisation};
use crate::fill::{RunRecord, check_writable, fill};
use crate::io::write_atomic;

pub use deviation::{Deviations, WITHIN, deviations, l1, pooled, rms, scalar, signed_scalar};
pub use measures::{MeasureInput, Measures, PressureMeasure, RDF_R_MAX};
pub use report::{write_csv, write_markdown, write_plot};
pub use settings::{REFERENCE, ReferenceScene, SCENES, SETTINGS, Setting};

/// What to run.
#[derive(Clone, Debug)]
pub struct BenchConfig {
    pub scenes: Vec<&'static ReferenceScene>,
    /// The reference is added in front when missing: every deviation needs it.
    pub settings: Vec<&'static Setting>,
    /// Grains per run (overrides the scene's count).
    pub grains: usize,
    /// Seeds first_seed .. first_seed + seeds.
    pub seeds: u64,
    pub first_seed: u64,
    /// run.max_relaxation_time_s of every run (s).
    pub max_relaxation_time_s: f64,
    pub measure: MeasureInput,
    /// Runs go to out/runs/SCENE/SETTING/seed-N/.
    pub out: PathBuf,
    /// Keep finished groups of an earlier bench in `out` (see the module doc).
    pub reuse: bool,
}

/// One scene x setting.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct Row {
    pub scene: String,
    pub setting: String,
    pub runs: usize,
    /// Time step of the runs (s).
    pub time_step_s: f64,
    /// Mean steps per run.
    pub mean_steps: f64,
    /// Wall time of the runs together (s).
    pub wall_s: f64,
    /// Processor time of the runs together (s).
    pub cpu_s: f64,
    /// Faithful processor time over this one's.
    pub speed_up: f64,
    /// None for the reference itself.
    pub deviations: Option<Deviations>,
    pub not_relaxed: usize,
    /// The seeds that did not relax, with kinetic / elastic energy at their end.
    pub not_relaxed_seeds: Vec<(u64, f64)>,
    pub measures: Measures,
}

#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct BenchReport {
    pub grains: usize,
    pub seeds: u64,
    pub threads: usize,
    pub max_relaxation_time_s: f64,
    pub rows: Vec<Row>,
}

/// Where one run writes.
pub fn run_dir(out: &Path, scene: &str, setting: &str, seed: u64) -> PathBuf {
    out.join("runs")
        .join(scene)
        .join(setting)
        .join(format!("seed-{seed}"))
}

/// A finished scene x setting, written after its last run: what it was run from, and the
/// times of its runs together.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
struct GroupRecord {
    facets_version: String,
    /// The scene as run, written as TOML.
    scene: String,
    seeds: Vec<u64>,
    wall_s: f64,
    cpu_s: f64,
}

const GROUP_FILE: &str = "group.json";

/// What the table needs of a run's record; read on its own from `run.json` (the scene inside
/// a record may hold infinite thresholds, which JSON writes as null).
#[derive(Clone, Debug, Deserialize)]
struct RunOutcome {
    seed: u64,
    time_step_s: f64,
    steps: u64,
    relaxed: bool,
    energies: crate::fill::EnergiesRecord,
}

impl From<RunRecord> for RunOutcome {
    fn from(r: RunRecord) -> Self {
        Self {
            seed: r.seed,
            time_step_s: r.time_step_s,
            steps: r.steps,
            relaxed: r.relaxed,
            energies: r.energies,
        }
    }
}

/// The times of an earlier run of the same group, if every run of it is there.
fn finished_group(
    dir: &Path,
    expected: &GroupRecord,
    out: &Path,
    scene: &str,
    setting: &str,
) -> Option<(f64, f64, Vec<RunOutcome>)> {
    let text = std::fs::read_to_string(dir.join(GROUP_FILE)).ok()?;
    let found: GroupRecord = serde_json::from_str(&text).ok()?;
    let same = found.facets_version == expected.facets_version
        && found.scene == expected.scene
        && found.seeds == expected.seeds;
    if !same {
        return None;
    }
    let records = expected
        .seeds
        .iter()
        .map(|&seed| {
            let run = run_dir(out, scene, setting, seed);
            let text = std::fs::read_to_string(run.join("run.json")).ok()?;
            let record: RunOutcome = serde_json::from_str(&text).ok()?;
            (record.seed == seed && run.join("deposit.csv").exists()).then_some(record)
        })
        .collect::<Option<Vec<_>>>()?;
    Some((found.wall_s, found.cpu_s, records))
}

/// Runs every scene x setting x seed and measures the deviations; `done` is called after each
/// run with its scene, setting and seed (progress).
pub fn run_bench(
    config: &BenchConfig,
    done: &(dyn Fn(&str, &str, u64) + Sync),
) -> anyhow::Result<BenchReport> {
    anyhow::ensure!(
        config.seeds >= 2,
        "--seeds {}: standard errors need at least 2 seeds",
        config.seeds
    );
    anyhow::ensure!(!config.scenes.is_empty(), "no scene to run");
    anyhow::ensure!(
        config.grains >= 1,
        "--grains {}: a filling needs at least one grain",
        config.grains
    );
    anyhow::ensure!(
        config.max_relaxation_time_s.is_finite() && config.max_relaxation_time_s > 0.0,
        "--max-relaxation-s {}: expected a positive time (s)",
        config.max_relaxation_time_s
    );
    anyhow::ensure!(
        config.measure.rdf_margin_d.is_finite() && config.measure.rdf_margin_d >= 0.0,
        "--rdf-margin {}: expected a number of grain widths >= 0",
        config.measure.rdf_margin_d
    );
    let mut settings: Vec<&'static Setting> = Vec::new();
    if !config.settings.iter().any(|s| s.name == REFERENCE) {
        settings.push(Setting::by_name(REFERENCE)?);
    }
    for s in &config.settings {
        if !settings.iter().any(|t| t.name == s.name) {
            settings.push(s);
        }
    }
    // Put the reference first: its time and measures are needed by the others.
    settings.sort_by_key(|s| s.name != REFERENCE);
    let seeds: Vec<u64> = (0..config.seeds).map(|k| config.first_seed + k).collect();
    // Every scene is built and every folder checked before anything is simulated.
    let mut jobs = Vec::new();
    for scene in &config.scenes {
        for setting in &settings {
            let built = scene.build(config.grains, config.max_relaxation_time_s, setting)?;
            for &seed in &seeds {
                check_writable(&run_dir(&config.out, scene.name, setting.name, seed))?;
            }
            jobs.push((*scene, *setting, built));
        }
    }
    let mut rows: Vec<Row> = Vec::new();
    for (scene, setting, built) in &jobs {
        let group_dir = config.out.join("runs").join(scene.name).join(setting.name);
        let mut group = GroupRecord {
            facets_version: env!("CARGO_PKG_VERSION").to_string(),
            scene: toml::to_string(built).context("cannot write a bench scene as TOML")?,
            seeds: seeds.clone(),
            wall_s: 0.0,
            cpu_s: 0.0,
        };
        let earlier = config
            .reuse
            .then(|| finished_group(&group_dir, &group, &config.out, scene.name, setting.name))
            .flatten();
        let (wall_s, cpu_s, records) = match earlier {
            Some(done_before) => {
                for &seed in &seeds {
                    done(scene.name, setting.name, seed);
                }
                done_before
            }
            None => {
                // A group interrupted half-way must not pass for finished.
                let _ = std::fs::remove_file(group_dir.join(GROUP_FILE));
                let (cpu0, start) = (cpu_time(), Instant::now());
                let records: Vec<anyhow::Result<RunRecord>> = seeds
                    .par_iter()
                    .map(|&seed| {
                        let dir = run_dir(&config.out, scene.name, setting.name, seed);
                        let record = fill(built, seed, &dir, &mut |_| {}).with_context(|| {
                            format!(
                                "scene {}, setting {}, seed {seed}",
                                scene.name, setting.name
                            )
                        });
                        done(scene.name, setting.name, seed);
                        record
                    })
                    .collect();
                group.wall_s = start.elapsed().as_secs_f64();
                group.cpu_s = cpu_time() - cpu0;
                let records = records
                    .into_iter()
                    .map(|r| r.map(RunOutcome::from))
                    .collect::<anyhow::Result<Vec<_>>>()?;
                write_atomic(&group_dir.join(GROUP_FILE), |w| {
                    serde_json::to_writer_pretty(&mut *w, &group)?;
                    Ok(())
                })?;
                (group.wall_s, group.cpu_s, records)
            }
        };
        let realisations = seeds
            .iter()
            .map(|&seed| {
                let dir = run_dir(&config.out, scene.name, setting.name, seed);
                load_realisation(&dir.join("deposit.csv"), &LoadOptions::default())
            })
            .collect::<anyhow::Result<Vec<_>>>()?;
        let ensemble = Ensemble::new(realisations)?;
        let measures = Measures::of(&ensemble, &config.measure)
            .with_context(|| format!("measuring scene {}, setting {}", scene.name, setting.name))?;
        let reference = rows
            .iter()
            .find(|r| r.scene == scene.name && r.setting == REFERENCE);
        let (speed_up, deviations) = match reference {
            Some(r) if setting.name != REFERENCE => {
                (r.cpu_s / cpu_s, Some(deviations(&measures, &r.measures)))
            }
            _ => (1.0, None),
        };
        rows.push(Row {
            scene: scene.name.to_string(),
            setting: setting.name.to_string(),
            runs: records.len(),
            time_step_s: records[0].time_step_s,
            mean_steps: records.iter().map(|r| r.steps as f64).sum::<f64>() / records.len() as f64,
            wall_s,
            cpu_s,
            speed_up,
            deviations,
            not_relaxed: records.iter().filter(|r| !r.relaxed).count(),
            not_relaxed_seeds: records
                .iter()
                .filter(|r| !r.relaxed)
                .map(|r| (r.seed, r.energies.kinetic_j / r.energies.elastic_j))
                .collect(),
            measures,
        });
    }
    Ok(BenchReport {
        grains: config.grains,
        seeds: config.seeds,
        threads: rayon::current_num_threads(),
        max_relaxation_time_s: config.max_relaxation_time_s,
        rows,
    })
}

/// Runs `run_bench` will make (the reference included).
pub fn total_runs(config: &BenchConfig) -> usize {
    let extra = usize::from(!config.settings.iter().any(|s| s.name == REFERENCE));
    let mut names: Vec<&str> = config.settings.iter().map(|s| s.name).collect();
    names.sort_unstable();
    names.dedup();
    config.scenes.len() * (names.len() + extra) * config.seeds as usize
}

/// Writes fill.csv, fill.md, speed_vs_error.png and report.json into `out`; returns their paths.
pub fn write_all(out: &Path, report: &BenchReport) -> anyhow::Result<Vec<PathBuf>> {
    std::fs::create_dir_all(out).with_context(|| format!("cannot create {}", out.display()))?;
    let csv = out.join("fill.csv");
    let md = out.join("fill.md");
    let png = out.join("speed_vs_error.png");
    let json = out.join("report.json");
    write_csv(&csv, report)?;
    write_markdown(&md, report)?;
    write_plot(&png, report)?;
    crate::io::write_atomic(&json, |w| {
        serde_json::to_writer_pretty(&mut *w, report)?;
        Ok(())
    })?;
    Ok(vec![csv, md, png, json])
}

/// The settings compared with the reference (rows with deviations), in the order first met.
pub fn compared_settings(report: &BenchReport) -> Vec<&str> {
    let mut names: Vec<&str> = Vec::new();
    for row in &report.rows {
        if row.deviations.is_some() && !names.contains(&row.setting.as_str()) {
            names.push(&row.setting);
        }
    }
    names
}

/// The packing fraction's signed deviations of `setting` from the reference, pooled over the
/// scenes that have both ([`pooled`]); NaN when none has.
pub fn pooled_phi_shift(report: &BenchReport, setting: &str) -> f64 {
    let z: Vec<f64> = report
        .rows
        .iter()
        .filter(|r| r.setting == setting && r.deviations.is_some())
        .filter_map(|r| {
            let reference = report
                .rows
                .iter()
                .find(|x| x.scene == r.scene && x.setting == REFERENCE)?;
            Some(signed_scalar(r.measures.phi_f, reference.measures.phi_f))
        })
        .collect();
    pooled(&z)
}

/// The setting within 2 standard errors on every scene, and with its packing-fraction shift
/// pooled over the scenes within 2, with the largest speed-up on its slowest scene, and that
/// speed-up; None when no setting passes. This is the candidate for the defaults (issue 3).
pub fn fastest_within(report: &BenchReport) -> Option<(String, f64)> {
    compared_settings(report)
        .into_iter()
        .filter_map(|name| {
            let rows: Vec<&Row> = report.rows.iter().filter(|r| r.setting == name).collect();
            let all_within = rows
                .iter()
                .all(|r| r.deviations.is_some_and(|d| d.within()));
            let slowest = rows
                .iter()
                .map(|r| r.speed_up)
                .fold(f64::INFINITY, f64::min);
            let pooled_within = pooled_phi_shift(report, name).abs() <= WITHIN;
            (all_within && pooled_within && slowest.is_finite())
                .then(|| (name.to_string(), slowest))
        })
        .max_by(|a, b| a.1.total_cmp(&b.1))
}
