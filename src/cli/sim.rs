use std::path::PathBuf;

use clap::Args as ClapArgs;
use indicatif::MultiProgress;

use facets::fill::{FillJob, FillOutcome, Runs, default_out, fill_all, planned_runs};
use facets::scene::load_scene;

/// Fill a silo as a scene file describes, relax the deposit and write it.
///
/// Each run writes into DIR/seed-N/: deposit.csv (grains, mm, x from the left wall, y from the
/// floor), deposit.contacts.csv (one row per sub-contact: i,j,fx_N,fy_N,cx_mm,cy_mm; j = -1
/// left wall, -2 right wall, -3 floor), deposit.meta.json (read by `facets analyse`),
/// grains.vtu (VTK, mm: ParaView, meshio) and run.json (scene, seed, steps, wall time, energies,
/// packing fraction); snapshots/step-N.vtu when the scene asks for them.
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

pub fn run(args: Args) -> anyhow::Result<()> {
    let scene = load_scene(&args.scene)?;
    let runs = if args.resume.is_empty() {
        Runs::Fresh {
            first_seed: args.seed.unwrap_or(scene.run.seed),
            count: args.realisations,
            out: args.out.clone().unwrap_or_else(|| default_out(&args.scene)),
            restart: args.restart,
        }
    } else {
        Runs::Resume {
            checkpoints: args.resume.clone(),
            seed: args.seed,
            out: args.out.clone(),
        }
    };
    let planned = planned_runs(&scene, &args.scene, &runs)?;
    let jobs: Vec<FillJob> = planned
        .iter()
        .map(|r| FillJob {
            label: format!("run seed {} ({})", r.seed, args.scene.display()),
            scene: &scene,
            seed: r.seed,
            dir: r.dir.clone(),
            resume: r.resume.clone(),
        })
        .collect();
    super::progress::stop_fillings_on_ctrl_c()?;
    let bars = MultiProgress::new();
    let fillings = super::progress::FillingBars::new(&bars, 10, true);
    let outcomes = fill_all(&jobs, Some(&super::progress::INTERRUPT), &|k, event| {
        fillings.show(&format!("seed {}", jobs[k].seed), event)
    });
    let mut unrelaxed = Vec::new();
    let mut stopped = Vec::new();
    for (job, outcome) in jobs.iter().zip(outcomes) {
        let (seed, dir) = (job.seed, &job.dir);
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
