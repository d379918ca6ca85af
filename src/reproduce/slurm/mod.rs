//! `--slurm DIR`: a plan as a Slurm job array. DIR gets
//!
//! ```text
//! DIR/plan.json       the plan, as the tasks read it
//! DIR/array.sbatch    one array task per share (--task $SLURM_ARRAY_TASK_ID --tasks N)
//! DIR/collect.sbatch  the analysis and report (--collect), once every task succeeded
//! DIR/submit.sh       submits both, the second with --dependency=afterok on the first,
//!                     and prints their job ids
//! DIR/logs/           the jobs' output
//! ```
//!
//! Each task's processors, memory and time limit are estimated in [`estimate`], and the
//! numbers behind them are written in the array script's comments. A task that failed or ran
//! out of time is run again by submitting the array again (all of it, or `--array=K,...`):
//! the stages skip what is done.

pub mod estimate;

use std::fmt::Write as _;
use std::path::{Path, PathBuf};

use anyhow::Context;

use super::layout::Layout;
use super::plan::Plan;
use super::shard::{self, Unit};
use super::{manifest, simulate};
use crate::io::write_atomic;
use estimate::{RateSource, Resources};

/// The collect job: the analysis reads every table once and draws the figures, minutes at
/// paper scale.
const COLLECT_CPUS: usize = 2;
const COLLECT_MEMORY_MB: u64 = 4096;
const COLLECT_TIME_S: u64 = 3600;

/// Choices of the user about the job.
#[derive(Clone, Debug, Default)]
pub struct SlurmOptions {
    /// Array tasks (default: one per unit).
    pub tasks: Option<usize>,
    pub partition: Option<String>,
    pub account: Option<String>,
    /// At most this many array tasks at once (`%N`).
    pub throttle: Option<usize>,
    /// Further `#SBATCH` lines for both jobs (`--qos=long`, `--constraint=avx2`, ...).
    pub sbatch_lines: Vec<String>,
    pub cpus_per_task: Option<usize>,
    /// The engine's rate (grain-steps per second, one thread); measured when missing.
    pub grain_steps_per_second: Option<f64>,
}

/// Everything the scripts name, as absolute paths.
#[derive(Clone, Debug)]
pub struct Job {
    pub name: String,
    /// The facets executable the tasks run.
    pub program: PathBuf,
    pub dir: PathBuf,
    pub out: PathBuf,
    pub photos: Option<PathBuf>,
    pub units: usize,
    pub tasks: usize,
}

/// The three scripts' text.
#[derive(Clone, Debug)]
pub struct Scripts {
    pub array: String,
    pub collect: String,
    pub submit: String,
}

/// What [`write_slurm`] wrote and estimated.
#[derive(Clone, Debug)]
pub struct Written {
    pub job: Job,
    pub resources: Resources,
    pub rate_source: RateSource,
    pub submit: PathBuf,
}

impl SlurmOptions {
    /// Refuses values Slurm would refuse or misread, naming the option.
    pub fn validate(&self) -> anyhow::Result<()> {
        if let Some(n) = self.tasks {
            anyhow::ensure!(n >= 1, "--tasks {n}: expected at least 1");
        }
        if let Some(n) = self.throttle {
            anyhow::ensure!(n >= 1, "--throttle {n}: expected at least 1 task at a time");
        }
        if let Some(n) = self.cpus_per_task {
            anyhow::ensure!(n >= 1, "--cpus-per-task {n}: expected at least 1");
        }
        for (option, value) in [
            ("--partition", &self.partition),
            ("--account", &self.account),
        ] {
            if let Some(v) = value {
                anyhow::ensure!(
                    !v.is_empty() && !v.chars().any(|c| c.is_whitespace() || c == '#'),
                    "{option} {v:?}: expected a name without spaces"
                );
            }
        }
        for line in &self.sbatch_lines {
            anyhow::ensure!(
                !line.contains('\n') && !line.contains('\r'),
                "--sbatch-line {line:?}: expected one line"
            );
            anyhow::ensure!(
                sbatch_line(line).starts_with("#SBATCH -"),
                "--sbatch-line {line:?}: expected an sbatch option such as --qos=long"
            );
        }
        Ok(())
    }
}

/// `#SBATCH` and the option, whether or not the user wrote the prefix.
fn sbatch_line(line: &str) -> String {
    let line = line.trim();
    if line.starts_with("#SBATCH") {
        line.to_string()
    } else {
        format!("#SBATCH {line}")
    }
}

/// A word for the shell, quoted.
fn quoted(path: &Path) -> String {
    format!("'{}'", path.to_string_lossy().replace('\'', r"'\''"))
}

/// Slurm's D-HH:MM:SS.
pub fn slurm_time(seconds: u64) -> String {
    let (d, rest) = (seconds / 86_400, seconds % 86_400);
    let (h, m, s) = (rest / 3600, rest % 3600 / 60, rest % 60);
    if d > 0 {
        format!("{d}-{h:02}:{m:02}:{s:02}")
    } else {
        format!("{h:02}:{m:02}:{s:02}")
    }
}

fn hours(seconds: f64) -> String {
    if seconds < 120.0 {
        format!("{seconds:.1} s")
    } else if seconds < 7200.0 {
        format!("{:.1} min", seconds / 60.0)
    } else {
        format!("{:.1} h", seconds / 3600.0)
    }
}

/// The `#SBATCH` lines both jobs share.
fn common_lines(s: &mut String, options: &SlurmOptions, name: &str) {
    let _ = writeln!(s, "#SBATCH --job-name={name}");
    if let Some(p) = &options.partition {
        let _ = writeln!(s, "#SBATCH --partition={p}");
    }
    if let Some(a) = &options.account {
        let _ = writeln!(s, "#SBATCH --account={a}");
    }
    for line in &options.sbatch_lines {
        let _ = writeln!(s, "{}", sbatch_line(line));
    }
}

/// The facets command line of a job, `extra` after the plan and folders.
fn command(job: &Job, extra: &str) -> String {
    let mut c = format!(
        "{} reproduce --plan {} --out {}",
        quoted(&job.program),
        quoted(&job.dir.join("plan.json")),
        quoted(&job.out)
    );
    if let Some(p) = &job.photos {
        let _ = write!(c, " --photos {}", quoted(p));
    }
    format!("{c} {extra}")
}

/// The scripts' text for `job` with `resources` (pure: the tests read it).
pub fn scripts(
    job: &Job,
    options: &SlurmOptions,
    resources: &Resources,
    rate_source: &RateSource,
) -> Scripts {
    let r = resources;
    let logs = job.dir.join("logs");
    let mut a = String::from("#!/bin/bash\n");
    let _ = writeln!(
        a,
        "# facets reproduce, plan {}: {} units (fillings, photographs, detections) in {} tasks;\n\
         # task K runs the units k with k mod {} = K.",
        job.name, job.units, job.tasks, job.tasks
    );
    let source = match rate_source {
        RateSource::Given => "given".to_string(),
        RateSource::Finished(n) => format!("from {n} fillings done in the output folder"),
        RateSource::Measured => {
            "measured when this script was written, on a small filling of the plan, one thread"
                .to_string()
        }
    };
    let _ = writeln!(
        a,
        "# Estimates: engine {:.3e} grain-steps per second ({source}); detector {} s per megapixel.\n\
         # Largest task: {} units, {} of processor time; its longest unit {}.\n\
         # On {} processors (units side by side, one unit on one processor): {} wall time.\n\
         # Time limit: {} x that + {} = {}; memory: {} MB + up to {} units at once = {} MB.",
        r.grain_steps_per_second,
        estimate::DETECT_CPU_SECONDS_PER_MEGAPIXEL,
        r.units_per_task,
        hours(r.task_cpu_seconds),
        hours(r.longest_unit_cpu_seconds),
        r.cpus,
        hours(r.task_wall_seconds),
        estimate::TIME_SAFETY,
        hours(estimate::TIME_MARGIN_S),
        slurm_time(r.time_limit_s),
        estimate::BASE_MEMORY_MB,
        r.cpus.min(r.units_per_task.max(1)),
        r.memory_mb,
    );
    let _ = writeln!(
        a,
        "# A task that failed or ran out of time: submit again (sbatch --array=K,... {}):\n\
         # what is done is skipped.",
        job.dir.join("array.sbatch").display()
    );
    common_lines(&mut a, options, &format!("facets-{}", job.name));
    let throttle = options.throttle.map_or(String::new(), |n| format!("%{n}"));
    let _ = writeln!(a, "#SBATCH --array=0-{}{throttle}", job.tasks - 1);
    let _ = writeln!(a, "#SBATCH --cpus-per-task={}", r.cpus);
    let _ = writeln!(a, "#SBATCH --mem={}M", r.memory_mb);
    let _ = writeln!(a, "#SBATCH --time={}", slurm_time(r.time_limit_s));
    let _ = writeln!(a, "#SBATCH --output={}/task-%A_%a.out", logs.display());
    let _ = writeln!(
        a,
        "set -euo pipefail\nexport RAYON_NUM_THREADS=\"${{SLURM_CPUS_PER_TASK:-{}}}\"",
        r.cpus
    );
    let _ = writeln!(
        a,
        "exec {}",
        command(
            job,
            &format!("--task \"$SLURM_ARRAY_TASK_ID\" --tasks {}", job.tasks)
        )
    );

    let mut c = String::from("#!/bin/bash\n");
    let _ = writeln!(
        c,
        "# facets reproduce, plan {}: analysis, figures and report.md once every task of\n\
         # array.sbatch is done (submit.sh makes it wait with --dependency=afterok).",
        job.name
    );
    common_lines(&mut c, options, &format!("facets-{}-collect", job.name));
    let _ = writeln!(c, "#SBATCH --cpus-per-task={COLLECT_CPUS}");
    let _ = writeln!(c, "#SBATCH --mem={COLLECT_MEMORY_MB}M");
    let _ = writeln!(c, "#SBATCH --time={}", slurm_time(COLLECT_TIME_S));
    let _ = writeln!(c, "#SBATCH --output={}/collect-%j.out", logs.display());
    let _ = writeln!(
        c,
        "set -euo pipefail\nexport RAYON_NUM_THREADS=\"${{SLURM_CPUS_PER_TASK:-{COLLECT_CPUS}}}\""
    );
    let _ = writeln!(
        c,
        "exec {}",
        command(job, &format!("--collect --tasks {}", job.tasks))
    );

    let dir = quoted(&job.dir);
    let submit = format!(
        "#!/bin/bash\n\
         # Submits the array of plan {name} and its collect job; prints both job ids.\n\
         # Extra arguments go to both sbatch calls (e.g. --partition=debug).\n\
         set -euo pipefail\n\
         array=$(sbatch --parsable \"$@\" {dir}/array.sbatch)\n\
         array=${{array%%;*}}\n\
         collect=$(sbatch --parsable \"$@\" --dependency=afterok:\"$array\" {dir}/collect.sbatch)\n\
         collect=${{collect%%;*}}\n\
         echo \"array job: $array\"\n\
         echo \"collect job: $collect\"\n\
         echo \"report when both are done: {report}\"\n",
        name = job.name,
        report = job.out.join("report.md").display(),
    );
    Scripts {
        array: a,
        collect: c,
        submit,
    }
}

fn absolute(path: &Path) -> anyhow::Result<PathBuf> {
    std::path::absolute(path).with_context(|| format!("cannot make {} absolute", path.display()))
}

/// Writes DIR's scripts for running `plan` into `out` on Slurm with `program` (the facets
/// executable the nodes run).
pub fn write_slurm(
    plan: &Plan,
    photos: Option<&Path>,
    out: &Path,
    dir: &Path,
    program: &Path,
    options: &SlurmOptions,
) -> anyhow::Result<Written> {
    plan.validate()?;
    options.validate()?;
    let real = photos.map(manifest::read_manifest).transpose()?;
    let (out, dir, program) = (absolute(out)?, absolute(dir)?, absolute(program)?);
    for (what, path) in [("--slurm", &dir), ("--out", &out)] {
        anyhow::ensure!(
            estimate::plain(path),
            "{what} {}: Slurm's #SBATCH lines cannot hold a path with spaces",
            path.display()
        );
    }
    let layout = Layout::new(&out);
    let fillings = simulate::fillings(plan, &layout, real.is_none())?;
    let (rate, rate_source) =
        estimate::engine_rate(plan, options.grain_steps_per_second, &fillings)?;
    let units = shard::units(fillings, real);
    let tasks = options.tasks.unwrap_or(units.len());
    let costs = units
        .iter()
        .map(|u: &Unit| estimate::unit_cost(plan, u, rate))
        .collect::<anyhow::Result<Vec<_>>>()?;
    let resources = estimate::resources(&costs, tasks, options.cpus_per_task, rate);
    let job = Job {
        name: plan.name.clone(),
        program,
        dir: dir.clone(),
        out,
        photos: photos.map(absolute).transpose()?,
        units: units.len(),
        tasks,
    };
    let text = scripts(&job, options, &resources, &rate_source);
    std::fs::create_dir_all(dir.join("logs"))
        .with_context(|| format!("cannot create {}", dir.join("logs").display()))?;
    write_atomic(&dir.join("plan.json"), |w| {
        serde_json::to_writer_pretty(&mut *w, plan)?;
        Ok(())
    })?;
    for (name, body) in [
        ("array.sbatch", &text.array),
        ("collect.sbatch", &text.collect),
        ("submit.sh", &text.submit),
    ] {
        let path = dir.join(name);
        write_atomic(&path, |w| {
            use std::io::Write;
            Ok(w.write_all(body.as_bytes())?)
        })?;
        #[cfg(unix)]
        {
            use std::os::unix::fs::PermissionsExt;
            std::fs::set_permissions(&path, std::fs::Permissions::from_mode(0o755))
                .with_context(|| format!("cannot make {} executable", path.display()))?;
        }
    }
    Ok(Written {
        submit: dir.join("submit.sh"),
        job,
        resources,
        rate_source,
    })
}
