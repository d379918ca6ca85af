//! `facets bench vision`: detector accuracy and speed on rendered photographs of dense packings.

use std::path::PathBuf;

use clap::Args as ClapArgs;
use indicatif::{ProgressBar, ProgressStyle};
use vision::Shortcuts;

use facets::bench::vision::{self as bench, Seeds, VisionBench, VisionEvent, parse_seeds};

use crate::cli::shortcuts::ShortcutArgs;

#[derive(Debug, ClapArgs)]
#[command(
    after_help = "For each grain (square, rod53, rod3) it generates an ordered (slow-fill) \
and a disordered (fast-fill) dense packing of a 258 x 120 mm frame, renders each at every scale \
and in every style, runs the detector, and matches detections to the truth one-to-one (gate D/2). \
Recall counts uncut true grains; precision counts detections not flagged cut; RMS errors use \
uncut true grains; orientation errors are modulo the shape's symmetry, and the grains turned \
by more than 10 degrees (fitted across their neighbours) are also counted apart, with the RMS \
of the others. Times are wall \
times per photograph of the detector and, apart, of the renderer; a list under the table (and \
the CSV beside it) says where the detector's time goes, step by step of its pipeline."
)]
pub struct Args {
    /// CSV table of the results (one row per shape, packing, seed, scale and style, plus the
    /// two packings of each seed pooled and, with several seeds, everything pooled: seed
    /// `all`). Beside it, `<name>-phases.csv`: the detector's wall time per photograph step
    /// by step of its pipeline, per shape, scale and style.
    #[arg(long, default_value = "bench-vision.csv")]
    out: PathBuf,

    /// Scales, pixels per millimetre (comma separated).
    #[arg(long, value_delimiter = ',', default_value = "6,10")]
    px_per_mm: Vec<f64>,

    /// Styles (comma separated, among clean, lab, hard).
    #[arg(long, value_delimiter = ',', default_value = "clean,lab,hard", value_parser = ["clean", "lab", "hard"])]
    styles: Vec<String>,

    /// Grains to benchmark (comma separated, among square, rod53, rod3).
    #[arg(long, value_delimiter = ',', default_value = "square,rod53,rod3", value_parser = ["square", "rod53", "rod3"])]
    shapes: Vec<String>,

    /// Seeds of the packings and photographs: one (`1`), a list (`1,4,7`), a range
    /// (`12-21`) or a mix. With several, every figure is pooled over them (grains, not seeds,
    /// weigh equally) and a table per seed follows the pooled one: a target met on one seed
    /// may not be on the next, since an RMS over a photograph is set by its few grains fitted
    /// turned.
    #[arg(long = "seed", default_value = "1", value_parser = parse_seeds)]
    seeds: Seeds,

    #[command(flatten)]
    shortcuts: ShortcutArgs,
}

pub fn run(args: Args) -> anyhow::Result<()> {
    let config = VisionBench {
        px_per_mm: args.px_per_mm,
        styles: args.styles,
        shapes: args.shapes,
        seeds: args.seeds,
        shortcuts: args.shortcuts.shortcuts(),
    };
    config.validate()?;
    let bar = ProgressBar::new(config.photographs() as u64).with_style(
        ProgressStyle::with_template("{bar:40} {pos}/{len} photographs, {elapsed} {msg}")
            .unwrap_or_else(|_| ProgressStyle::default_bar()),
    );
    let report = bench::run(&config, &|event| match event {
        VisionEvent::Packing {
            shape,
            packing,
            seed,
        } => bar.set_message(format!("packing {shape} {packing} seed {seed}")),
        VisionEvent::Photograph {
            shape,
            packing,
            px_per_mm,
            style,
        } => bar.set_message(format!("{shape} {packing} {px_per_mm} px/mm {style}")),
        VisionEvent::Done => bar.inc(1),
    })?;
    bar.finish_and_clear();
    let shortcuts = args.shortcuts.describe();
    bench::write_results_csv(&args.out, &report.rows, &shortcuts)?;
    let phases_out = bench::phases_path(&args.out);
    bench::write_phases_csv(&phases_out, &report.spent)?;
    if config.shortcuts != Shortcuts::default() {
        println!(
            "Detector shortcuts taken: {shortcuts} (docs/results/detector-bench.md, \"Speed against accuracy\").\n"
        );
    }
    println!("{}", bench::markdown(&report.rows, report.several_seeds));
    println!("{}", bench::where_time_goes(&report.spent));
    println!(
        "Packings (258 x 120 mm frame, one core):\n\n{}",
        report.packings
    );
    eprintln!(
        "table written to {}, the detector's time step by step to {}",
        args.out.display(),
        phases_out.display()
    );
    Ok(())
}
