use std::path::PathBuf;
use std::sync::Mutex;

use clap::Args as ClapArgs;
use indicatif::{MultiProgress, ProgressBar, ProgressStyle};

use facets::reproduce::slurm::{SlurmOptions, write_slurm};
use facets::reproduce::{Event, Plan, Shard, collect, reproduce, reproduce_shard};

use super::progress::FillingBars;

/// Reproduce the whole study: simulations, stand-in photographs, detection, analysis, figures
/// and a report.
///
/// For each shape (squares, rods 5/3, rods 3) and phi0 of the plan: an ensemble of silo
/// fillings (simulation side); photographs of the analysed frame (region E at paper scale,
/// full width) rendered from other fillings, with other seeds (the stand-in experiment);
/// detection; the same analysis on both sides; the figures with both sides on the same axes;
/// and OUT/report.md: per shape and phi0, phi_f, g(1), the peak angle of f(theta), S2/S4,
/// lambda/W, P_sat and the detector's accuracy on these photographs, figures embedded.
///
/// A stopped run continues where it stopped: fillings, photographs and detector tables that
/// exist are not made again (a filling is done when its run.json says the same scene and seed).
///
/// Beyond one machine: `--task K --tasks N` runs the K-th of N shares of the fillings,
/// photographs and detections (any split writes the same files); `--collect` then analyses
/// and reports. `--slurm DIR` writes the scripts that do both on a Slurm cluster.
#[derive(Debug, ClapArgs)]
#[command(verbatim_doc_comment)]
pub struct Args {
    /// Small silos and ensembles on built-in defaults (the default): minutes on 2 cores.
    #[arg(long, conflicts_with_all = ["paper", "tiny", "plan"])]
    pub quick: bool,
    /// Paper-scale ensembles (256 mm silo; 3000 squares, 9000 short rods, 5000 long rods;
    /// 8 realisations a side): hours. Stop and restart at will.
    #[arg(long, conflicts_with_all = ["tiny", "plan"])]
    pub paper: bool,
    /// The end-to-end test's configuration (a 120 mm silo, tens of grains).
    #[arg(long, hide = true, conflicts_with = "plan")]
    pub tiny: bool,
    /// A plan of your own: the plan.json an earlier run wrote, edited (silo width, grain
    /// counts, phi0 values, realisations, photograph scale and style, g(r) margin, w scan).
    #[arg(long, value_name = "FILE")]
    pub plan: Option<PathBuf>,
    /// Real photographs as the experiment side: a folder with manifest.csv (columns
    /// file,shape,phi0,px_per_mm[,silo_width_mm,frame_y_mm]) or manifest.toml ([[photo]]
    /// tables with the same keys). shape: square, rod53 or rod3; frame_y_mm: height of the
    /// photograph's bottom edge above the floor (default 290, region E); silo_width_mm default
    /// 258. A NAME.truth.csv beside a photograph lets the report score the detector on it.
    #[arg(long, value_name = "DIR")]
    pub photos: Option<PathBuf>,
    /// Output folder (created if missing); report.md is written at its top.
    #[arg(long, default_value = "reproduce-out")]
    pub out: PathBuf,
    /// Run only share K (from 0) of the plan's fillings, photographs and detections, the units
    /// k with k mod N = K; then `--collect`.
    #[arg(
        long,
        value_name = "K",
        requires = "tasks",
        conflicts_with_all = ["collect", "slurm"],
        allow_hyphen_values = true
    )]
    pub task: Option<usize>,
    /// The number of shares (with --task, --slurm, or --collect to name the task of each
    /// missing unit). With --slurm, default one unit a task.
    #[arg(long, value_name = "N", allow_hyphen_values = true)]
    pub tasks: Option<usize>,
    /// Analyse and report a plan whose shares are all done; names the missing units otherwise.
    #[arg(long, conflicts_with = "slurm")]
    pub collect: bool,
    /// Write Slurm scripts into DIR: a job array of --tasks shares, a collect job that waits
    /// for it, and submit.sh that submits both and prints their job ids.
    #[arg(long, value_name = "DIR")]
    pub slurm: Option<PathBuf>,
    /// Slurm partition of both jobs.
    #[arg(long, requires = "slurm")]
    pub partition: Option<String>,
    /// Slurm account of both jobs.
    #[arg(long, requires = "slurm")]
    pub account: Option<String>,
    /// At most N array tasks at once (--array=...%N).
    #[arg(long, value_name = "N", requires = "slurm")]
    pub throttle: Option<usize>,
    /// An extra #SBATCH line for both jobs, e.g. --sbatch-line=--qos=long (repeatable).
    #[arg(
        long,
        value_name = "OPTION",
        requires = "slurm",
        allow_hyphen_values = true
    )]
    pub sbatch_line: Vec<String>,
    /// Processors per array task (default: the units of a task, at most 4).
    #[arg(long, value_name = "N", requires = "slurm")]
    pub cpus_per_task: Option<usize>,
    /// The engine's speed for the time estimates (grain-steps per second on one thread);
    /// default: from fillings done in --out, else measured now (about a second).
    #[arg(long, value_name = "RATE", requires = "slurm")]
    pub grain_steps_per_second: Option<f64>,
}

pub fn run(args: Args) -> anyhow::Result<()> {
    let plan = if let Some(path) = &args.plan {
        Plan::load(path)?
    } else if args.paper {
        Plan::paper()
    } else if args.tiny {
        Plan::tiny()
    } else {
        Plan::quick()
    };
    let photos = args.photos.as_deref();
    if let Some(dir) = &args.slurm {
        let options = SlurmOptions {
            tasks: args.tasks,
            partition: args.partition,
            account: args.account,
            throttle: args.throttle,
            sbatch_lines: args.sbatch_line,
            cpus_per_task: args.cpus_per_task,
            grain_steps_per_second: args.grain_steps_per_second,
        };
        let program = std::env::current_exe()?;
        let w = write_slurm(&plan, photos, &args.out, dir, &program, &options)?;
        let r = &w.resources;
        println!(
            "{} units in {} tasks of {} processors, {} MB, time limit {} each (estimates in {})",
            w.job.units,
            w.job.tasks,
            r.cpus,
            r.memory_mb,
            facets::reproduce::slurm::slurm_time(r.time_limit_s),
            dir.join("array.sbatch").display()
        );
        println!("submit: {}", w.submit.display());
        return Ok(());
    }
    if let Some(task) = args.task {
        let tasks = args.tasks.unwrap_or(0);
        let shard = Shard::new(task, tasks)?;
        let display = StageBars::new();
        let done = reproduce_shard(&plan, photos, &args.out, shard, &|e| display.show(e))?;
        for t in &done.stages {
            println!("{:>10}: {:.1} s", t.stage, t.seconds);
        }
        println!(
            "task {task} of {tasks}: {} of {} units ({} fillings run, {} found done); then --collect",
            done.units.len(),
            done.of,
            done.fillings_run,
            done.fillings_reused
        );
        return Ok(());
    }
    let display = StageBars::new();
    let progress = |e: Event| display.show(e);
    let report = if args.collect {
        collect(&plan, photos, &args.out, args.tasks, &progress)?
    } else {
        anyhow::ensure!(
            args.tasks.is_none(),
            "--tasks needs --task, --collect or --slurm"
        );
        reproduce(&plan, photos, &args.out, &progress)?
    };
    for t in &report.stages {
        println!("{:>10}: {:.1} s", t.stage, t.seconds);
    }
    if !report.unrelaxed.is_empty() {
        eprintln!(
            "warning: {} fillings did not relax in time (listed in the report)",
            report.unrelaxed.len()
        );
    }
    println!("report: {}", args.out.join("report.md").display());
    Ok(())
}

/// The reproduction's progress: a bar per stage, a bar per running filling under it, and
/// warnings printed between the bars.
struct StageBars {
    bars: MultiProgress,
    stage: Mutex<Option<ProgressBar>>,
    fillings: FillingBars,
}

impl StageBars {
    fn new() -> Self {
        let bars = MultiProgress::new();
        let fillings = FillingBars::new(&bars, 30, false);
        Self {
            bars,
            stage: Mutex::new(None),
            fillings,
        }
    }

    fn show(&self, event: Event) {
        let Ok(mut stage) = self.stage.lock() else {
            return;
        };
        match event {
            Event::Stage {
                stage: name,
                counts,
                total,
            } => {
                let style = ProgressStyle::with_template(
                    "{prefix:>12} [{bar:40}] {pos}/{len} {msg} ({elapsed} / ETA {eta})",
                )
                .unwrap_or_else(|_| ProgressStyle::default_bar())
                .progress_chars("=> ");
                let bar = self
                    .bars
                    .add(ProgressBar::new(total as u64).with_style(style));
                bar.set_prefix(name);
                bar.set_message(counts);
                *stage = Some(bar);
            }
            Event::Working(item) => {
                if let Some(bar) = stage.as_ref() {
                    bar.set_message(item.to_string());
                }
            }
            Event::Done => {
                if let Some(bar) = stage.as_ref() {
                    bar.inc(1);
                }
            }
            Event::StageEnd => {
                if let Some(bar) = stage.take() {
                    bar.finish();
                }
            }
            Event::Filling(name, event) => self.fillings.show(name, event),
            // Not `println` on a bar: a bar hidden (stderr not a terminal: a log, a pipe)
            // prints nothing, and the warning would be lost where it is most read.
            Event::Warning(text) => self.bars.suspend(|| eprintln!("warning: {text}")),
        }
    }
}
