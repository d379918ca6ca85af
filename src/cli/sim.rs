use std::path::{Path, PathBuf};

use anyhow::Context;
use clap::Args as ClapArgs;
use indicatif::{MultiProgress, ProgressBar};
use rayon::prelude::*;

use facets::fill::{
    Checkpoint, FillControl, FillOutcome, FillProgress, StopAt, check_writable, clear_earlier_run,
    fill_with, refuse_earlier_runs,
};
use facets::scene::{Scene, load_scene};

/// Fill a silo as a scene file describes, relax the deposit and write it.
///
/// Each run writes into DIR/seed-N/: deposit.csv (grains, mm, x from the left wall, y from the
/// floor), deposit.contacts.csv (one row per sub-contact: i,j,fx_N,fy_N,cx_mm,cy_mm; j = -1
/// left wall, -2 right wall, -3 floor), deposit.meta.json (read by `facets analyse`),
/// grains.vtk (ParaView) and run.json (scene, seed, steps, wall time, energies, packing
/// fraction); snapshots/step-N.vtk when the scene asks for them.
///
/// Ctrl-C stops every run at its next step boundary, writes DIR/seed-N/checkpoint.bin, prints
/// the command that resumes them and exits with status 130 (a second Ctrl-C exits at once).
/// `--resume` continues checkpoints with the same result, bit for bit, as a run that was never
/// stopped. `[output] checkpoint_every_s` in the scene also writes checkpoint.bin on the way.
/// A folder that holds an earlier run (run.json or checkpoint.bin) is refused unless
/// `--restart` says to start over.
#[derive(Debug, ClapArgs)]
#[command(verbatim_doc_comment)]
pub struct Args {
    /// Scene file (TOML); see data-samples/scenes/ for the paper's cases.
    pub scene: PathBuf,
    /// Seed of the first run (default: the scene's `run.seed`); run k uses seed + k. With
    /// --resume: the seed the checkpoint must belong to (default: the checkpoint's).
    #[arg(long)]
    pub seed: Option<u64>,
    /// Output folder (default: runs/SCENE-NAME); each run goes to its seed-N/ subfolder. With
    /// --resume the default is the folder holding each checkpoint.
    #[arg(long)]
    pub out: Option<PathBuf>,
    /// Number of realisations (seeds), run in parallel.
    #[arg(long, default_value_t = 1, conflicts_with = "resume")]
    pub realisations: u64,
    /// Continue checkpoint file(s) (seed-N/checkpoint.bin) written by Ctrl-C or by
    /// `[output] checkpoint_every_s`; several run in parallel. Refused when a checkpoint
    /// belongs to another scene, seed or version of facets.
    #[arg(long, num_args = 1..)]
    pub resume: Vec<PathBuf>,
    /// Start over in folders that hold an earlier run (its run.json or checkpoint.bin),
    /// replacing its files; without it such folders are refused.
    #[arg(long, conflicts_with = "resume")]
    pub restart: bool,
}

/// One run to do: its seed, its folder and the checkpoint it continues.
struct Job {
    seed: u64,
    dir: PathBuf,
    resume: Option<Checkpoint>,
}

pub fn run(args: Args) -> anyhow::Result<()> {
    anyhow::ensure!(
        args.realisations >= 1,
        "--realisations 0: expected at least one run"
    );
    let scene = load_scene(&args.scene)?;
    let jobs = if args.resume.is_empty() {
        let first = args.seed.unwrap_or(scene.run.seed);
        let out = args.out.clone().unwrap_or_else(|| {
            let stem = args.scene.file_stem().unwrap_or_default();
            PathBuf::from("runs").join(stem)
        });
        (0..args.realisations)
            .map(|k| Job {
                seed: first + k,
                dir: out.join(format!("seed-{}", first + k)),
                resume: None,
            })
            .collect()
    } else {
        resumed_jobs(&args, &scene)?
    };
    // Refuse an unwritable folder, or one holding an earlier run, before any simulating.
    for job in &jobs {
        check_writable(&job.dir)?;
    }
    if args.resume.is_empty() {
        let dirs: Vec<PathBuf> = jobs.iter().map(|j| j.dir.clone()).collect();
        if args.restart {
            for dir in &dirs {
                clear_earlier_run(dir)?;
            }
        } else {
            refuse_earlier_runs(&dirs)?;
        }
    }
    super::progress::stop_fillings_on_ctrl_c()?;
    let bars = MultiProgress::new();
    let style = super::progress::filling_style(10);
    let outcomes: Vec<(u64, PathBuf, anyhow::Result<FillOutcome>)> = jobs
        .into_par_iter()
        .map(|job| {
            let seed = job.seed;
            let bar = bars.add(ProgressBar::new(1).with_style(style.clone()));
            bar.set_prefix(format!("seed {seed}"));
            let mut update = |p: FillProgress| {
                bar.set_length((p.expected_end.max(p.time) * 1e3) as u64);
                bar.set_position((p.time * 1e3) as u64);
                let phase = if p.relaxing {
                    format!(
                        "relaxing, kinetic/elastic {:.1e}, load/weight off by {:.2} %",
                        p.energy_ratio,
                        100.0 * p.load_imbalance
                    )
                } else {
                    "filling".to_string()
                };
                let asleep = if p.asleep > 0 {
                    format!(", {} asleep", p.asleep)
                } else {
                    String::new()
                };
                bar.set_message(format!(
                    "{}/{} grains in{asleep}, {phase}",
                    p.inserted, p.total
                ));
            };
            let control = FillControl {
                resume: job.resume,
                stop: StopAt::Never,
                interrupt: Some(&super::progress::INTERRUPT),
            };
            let outcome = fill_with(&scene, seed, &job.dir, control, &mut update)
                .with_context(|| format!("run seed {seed} ({})", args.scene.display()));
            bar.finish();
            (seed, job.dir, outcome)
        })
        .collect();
    let mut unrelaxed = Vec::new();
    let mut stopped = Vec::new();
    for (seed, dir, outcome) in outcomes {
        let r = match outcome? {
            FillOutcome::Finished(r) => r,
            FillOutcome::Stopped {
                checkpoint,
                time,
                steps,
                grains,
            } => {
                eprintln!(
                    "seed {seed}: stopped at {time:.4} s simulated ({steps} steps, {grains} grains in), checkpoint {}",
                    checkpoint.display()
                );
                stopped.push(checkpoint);
                continue;
            }
        };
        println!(
            "seed {seed}: {} grains, {:.3} s simulated in {} steps, {:.1} s wall ({:.2e} grain-steps/s), packing fraction {:.4}, {} -> {}",
            r.grains,
            r.simulated_time_s,
            r.steps,
            r.wall_time_s,
            r.grain_steps as f64 / r.wall_time_s,
            r.packing_fraction,
            if r.relaxed { "relaxed" } else { "NOT relaxed" },
            dir.display()
        );
        if r.overflow {
            eprintln!(
                "warning: seed {seed}: the deposit ({:.0} mm) rises above the silo's {} mm",
                r.deposit_height_mm, r.scene.silo.height_mm
            );
        }
        if !r.relaxed {
            unrelaxed.push(seed);
        }
    }
    if !stopped.is_empty() {
        let files: Vec<String> = stopped.iter().map(|p| p.display().to_string()).collect();
        eprintln!(
            "interrupted; resume with:\n  facets sim {} --resume {}",
            args.scene.display(),
            files.join(" ")
        );
        std::process::exit(130);
    }
    anyhow::ensure!(
        unrelaxed.is_empty(),
        "seeds {unrelaxed:?} did not relax within run.max_relaxation_time_s = {} s (outputs written, run.json says relaxed: false)",
        scene.run.max_relaxation_time_s
    );
    Ok(())
}

/// The runs `--resume` continues, each checked against the scene (and `--seed`) before any
/// simulating.
fn resumed_jobs(args: &Args, scene: &Scene) -> anyhow::Result<Vec<Job>> {
    let mut jobs: Vec<Job> = Vec::new();
    for path in &args.resume {
        let checkpoint = Checkpoint::read(path)?;
        let seed = args.seed.unwrap_or(checkpoint.seed());
        checkpoint.check_matches(scene, seed).with_context(|| {
            format!(
                "cannot resume {} with scene {} and seed {seed}",
                path.display(),
                args.scene.display()
            )
        })?;
        anyhow::ensure!(
            jobs.iter().all(|j| j.seed != seed),
            "--resume: two checkpoints of seed {seed}"
        );
        let dir = match &args.out {
            Some(out) => out.join(format!("seed-{seed}")),
            None => path
                .parent()
                .filter(|p| !p.as_os_str().is_empty())
                .map_or_else(|| PathBuf::from("."), Path::to_path_buf),
        };
        jobs.push(Job {
            seed,
            dir,
            resume: Some(checkpoint),
        });
    }
    Ok(jobs)
}
