use std::path::PathBuf;

use anyhow::Context;
use clap::Args as ClapArgs;
use indicatif::{MultiProgress, ProgressBar, ProgressStyle};
use rayon::prelude::*;

use facets::fill::{FillProgress, RunRecord, check_writable, fill};
use facets::scene::load_scene;

/// Fill a silo as a scene file describes, relax the deposit and write it.
///
/// Each run writes into DIR/seed-N/: deposit.csv (grains, mm, x from the left wall, y from the
/// floor), deposit.contacts.csv (one row per sub-contact: i,j,fx_N,fy_N,cx_mm,cy_mm; j = -1
/// left wall, -2 right wall, -3 floor), deposit.meta.json (read by `facets analyse`),
/// grains.vtk (ParaView) and run.json (scene, seed, steps, wall time, energies, packing
/// fraction); snapshots/step-N.vtk when the scene asks for them.
#[derive(Debug, ClapArgs)]
#[command(verbatim_doc_comment)]
pub struct Args {
    /// Scene file (TOML); see data-samples/scenes/ for the paper's cases.
    pub scene: PathBuf,
    /// Seed of the first run (default: the scene's `run.seed`); run k uses seed + k.
    #[arg(long)]
    pub seed: Option<u64>,
    /// Output folder (default: runs/SCENE-NAME); each run goes to its seed-N/ subfolder.
    #[arg(long)]
    pub out: Option<PathBuf>,
    /// Number of realisations (seeds), run in parallel.
    #[arg(long, default_value_t = 1)]
    pub realisations: u64,
}

pub fn run(args: Args) -> anyhow::Result<()> {
    anyhow::ensure!(
        args.realisations >= 1,
        "--realisations 0: expected at least one run"
    );
    let scene = load_scene(&args.scene)?;
    let first = args.seed.unwrap_or(scene.run.seed);
    let out = args.out.clone().unwrap_or_else(|| {
        let stem = args.scene.file_stem().unwrap_or_default();
        PathBuf::from("runs").join(stem)
    });
    let seeds: Vec<u64> = (0..args.realisations).map(|k| first + k).collect();
    // Refuse an unwritable folder before any simulating.
    for &seed in &seeds {
        check_writable(&out.join(format!("seed-{seed}")))?;
    }
    let bars = MultiProgress::new();
    let style = ProgressStyle::with_template(
        "{prefix:>10} [{bar:30}] {pos}/{len} ms simulated, {msg} ({elapsed} / ETA {eta})",
    )
    .unwrap_or_else(|_| ProgressStyle::default_bar())
    .progress_chars("=> ");
    let records: Vec<anyhow::Result<RunRecord>> = seeds
        .par_iter()
        .map(|&seed| {
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
            let dir = out.join(format!("seed-{seed}"));
            let record = fill(&scene, seed, &dir, &mut update)
                .with_context(|| format!("run seed {seed} ({})", args.scene.display()));
            bar.finish();
            record
        })
        .collect();
    let mut unrelaxed = Vec::new();
    for (seed, record) in seeds.iter().zip(records) {
        let r = record?;
        println!(
            "seed {seed}: {} grains, {:.3} s simulated in {} steps, {:.1} s wall, packing fraction {:.4}, {} -> {}",
            r.grains,
            r.simulated_time_s,
            r.steps,
            r.wall_time_s,
            r.packing_fraction,
            if r.relaxed { "relaxed" } else { "NOT relaxed" },
            out.join(format!("seed-{seed}")).display()
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
    anyhow::ensure!(
        unrelaxed.is_empty(),
        "seeds {unrelaxed:?} did not relax within run.max_relaxation_time_s = {} s (outputs written, run.json says relaxed: false)",
        scene.run.max_relaxation_time_s
    );
    Ok(())
}
