//! `facets validate` (issue 53): runs a study's cases as ensembles and judges the simulation
//! against the study's findings F1-F5 in a report.
//!
//! Stages, in order:
//! 1. read the study ([`study`]): its cases, scenes with overrides, seeds;
//! 2. fill every seed not done yet, in parallel, resumable ([`run`]);
//! 3. measure every finished seed ([`measures`]) and write OUT/results.csv and results.json
//!    ([`results`]);
//! 4. the cases' means and standard errors, the findings' checks ([`findings`]);
//! 5. the figures ([`figures`]) and the report ([`report`]).
//!
//! `report_only` skips stage 2: the report then reads the runs that exist.

pub mod figures;
pub mod findings;
pub mod measures;
pub mod report;
pub mod results;
pub mod run;
pub mod study;

use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicBool, AtomicUsize, Ordering};

use anyhow::Context;
use rayon::prelude::*;

use crate::fill::FillEvent;
use findings::Verdict;
use results::Measured;
use run::{Job, RunSummary};
use study::Study;

/// What the command was asked.
#[derive(Clone, Debug)]
pub struct Options {
    /// The study file; None: the built-in study.
    pub study: Option<PathBuf>,
    /// Where the runs and the raw results go.
    pub out: PathBuf,
    /// The report's markdown; its figures go to the folder REPORT-STEM-figures beside it.
    pub report: PathBuf,
    /// Only measure and report the runs that exist.
    pub report_only: bool,
}

/// Progress of the stages.
#[derive(Clone, Copy, Debug)]
pub enum Progress<'a> {
    Run(&'a Job, FillEvent),
    /// Realisations measured so far, of the total.
    Measured {
        done: usize,
        total: usize,
    },
}

/// How it went.
#[derive(Clone, Debug)]
pub struct Outcome {
    pub runs: RunSummary,
    /// Realisations measured.
    pub measured: usize,
    /// Realisations the study asks for.
    pub asked: usize,
    /// None when the runs were interrupted (no report written).
    pub report: Option<PathBuf>,
    pub figures: Vec<PathBuf>,
    pub verdicts: Vec<(&'static str, Verdict)>,
}

/// The study the options name.
pub fn read_study(options: &Options) -> anyhow::Result<Study> {
    match &options.study {
        Some(path) => study::load_study(path),
        None => study::default_study(),
    }
}

/// Runs the stages (see the module doc); `interrupt` (Ctrl-C) stops the fillings with
/// checkpoints and returns without a report.
pub fn validate(
    options: &Options,
    interrupt: Option<&AtomicBool>,
    progress: &(dyn Fn(Progress) + Sync),
) -> anyhow::Result<Outcome> {
    let study = read_study(options)?;
    let jobs = run::jobs(&study, &options.out);
    let runs = if options.report_only {
        RunSummary::default()
    } else {
        crate::fill::check_writable(&options.out)?;
        run::run_missing(&study, &jobs, interrupt, &|job, event| {
            progress(Progress::Run(job, event))
        })?
    };
    let mut outcome = Outcome {
        runs,
        measured: 0,
        asked: jobs.len(),
        report: None,
        figures: Vec::new(),
        verdicts: Vec::new(),
    };
    if !outcome.runs.stopped.is_empty() {
        return Ok(outcome);
    }
    let done: Vec<&Job> = jobs.iter().filter(|j| run::is_done(&j.dir)).collect();
    for job in &done {
        run::check_scene(&study.cases[job.case], job)?;
    }
    let measured = measure_all(&study, &done, progress)?;
    outcome.measured = measured.len();
    std::fs::create_dir_all(&options.out)
        .with_context(|| format!("cannot create {}", options.out.display()))?;
    results::write_results_csv(&options.out.join("results.csv"), &study, &measured)?;
    results::write_results_json(&options.out.join("results.json"), &study, &measured)?;
    let stats = results::case_stats(&study, &measured);
    let findings = findings::findings(&study, &stats);
    let (figures_dir, figures_name) = figures_dir(&options.report);
    outcome.figures = figures::write_figures(&figures_dir, &study, &stats)?;
    let provenance = report::Provenance {
        command: command(options),
        date: newest_run_date(&done),
        figures_dir: figures_name,
    };
    let text = report::render(&study, &stats, &findings, &provenance);
    crate::io::write_atomic(&options.report, |w| {
        use std::io::Write;
        Ok(w.write_all(text.as_bytes())?)
    })
    .with_context(|| format!("cannot write the report {}", options.report.display()))?;
    outcome.report = Some(options.report.clone());
    outcome.verdicts = findings.iter().map(|f| (f.id, f.verdict())).collect();
    Ok(outcome)
}

/// Measures the finished runs in parallel; the order is the study's.
fn measure_all(
    study: &Study,
    done: &[&Job],
    progress: &(dyn Fn(Progress) + Sync),
) -> anyhow::Result<Vec<Measured>> {
    let count = AtomicUsize::new(0);
    let total = done.len();
    progress(Progress::Measured { done: 0, total });
    done.par_iter()
        .map(|job| {
            let m = measure_one(study, job);
            let k = count.fetch_add(1, Ordering::Relaxed) + 1;
            progress(Progress::Measured { done: k, total });
            m
        })
        .collect()
}

fn measure_one(study: &Study, job: &Job) -> anyhow::Result<Measured> {
    let case = &study.cases[job.case];
    let measures = measures::measure(&job.dir, &study.analysis)
        .with_context(|| format!("case `{}` seed {}", case.name, job.seed))?;
    let record = job.dir.join("run.json");
    let text = std::fs::read_to_string(&record)
        .with_context(|| format!("cannot read {}", record.display()))?;
    let run: serde_json::Value = serde_json::from_str(&text)
        .with_context(|| format!("{}: not a run record", record.display()))?;
    Ok(Measured {
        case: job.case,
        seed: job.seed,
        shape: case.scene.grains.kind,
        phi0: case.scene.feed.phi0,
        relaxed: run["relaxed"].as_bool().unwrap_or(false),
        grains: run["grains"].as_u64().unwrap_or(0) as usize,
        measures,
    })
}

/// The figures' folder (REPORT-STEM-figures beside the report) and its name as the report
/// links it.
fn figures_dir(report: &Path) -> (PathBuf, String) {
    let stem = report
        .file_stem()
        .map_or_else(|| "report".into(), |s| s.to_string_lossy().into_owned());
    let name = format!("{stem}-figures");
    let dir = report.parent().unwrap_or(Path::new("")).join(&name);
    (dir, name)
}

/// The command that runs this study and writes this report (`--report-only` aside: it writes
/// the same report from the same runs).
fn command(options: &Options) -> String {
    let mut c = "facets validate".to_string();
    if let Some(s) = &options.study {
        c.push_str(&format!(" --study {}", s.display()));
    }
    c.push_str(&format!(
        " --out {} --report {}",
        options.out.display(),
        options.report.display()
    ));
    c
}

/// The date (UTC) of the newest run.json among the runs.
fn newest_run_date(done: &[&Job]) -> Option<String> {
    let newest = done
        .iter()
        .filter_map(|j| {
            std::fs::metadata(j.dir.join("run.json"))
                .ok()?
                .modified()
                .ok()
        })
        .max()?;
    let secs = newest.duration_since(std::time::UNIX_EPOCH).ok()?.as_secs();
    let (y, m, d) = civil_date((secs / 86_400) as i64);
    Some(format!("{y:04}-{m:02}-{d:02}"))
}

/// Year, month, day of a count of days since 1970-01-01 (proleptic Gregorian calendar).
fn civil_date(days: i64) -> (i64, u32, u32) {
    let z = days + 719_468;
    let era = z.div_euclid(146_097);
    let doe = z.rem_euclid(146_097);
    let yoe = (doe - doe / 1460 + doe / 36_524 - doe / 146_096) / 365;
    let doy = doe - (365 * yoe + yoe / 4 - yoe / 100);
    let mp = (5 * doy + 2) / 153;
    let d = (doy - (153 * mp + 2) / 5 + 1) as u32;
    let m = if mp < 10 { mp + 3 } else { mp - 9 } as u32;
    let y = yoe + era * 400 + i64::from(m <= 2);
    (y, m, d)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn civil_dates() {
        assert_eq!(civil_date(0), (1970, 1, 1));
        assert_eq!(civil_date(59), (1970, 3, 1));
        assert_eq!(civil_date(11_016), (2000, 2, 29));
        assert_eq!(civil_date(19_723), (2024, 1, 1));
    }
}
