//! `facets bench vision`: detector accuracy, speed and memory on rendered photographs of
//! simulated deposits and generated packings, in looks drawn at random.

use std::path::PathBuf;

use clap::Args as ClapArgs;
use indicatif::{ProgressBar, ProgressStyle};
use vision::Shortcuts;
use vision::render::LookRange;

use facets::bench::vision::{
    self as bench, REGION_E_FRAME, Seeds, SourceKind, Split, VisionBench, VisionEvent, parse_seeds,
};

use crate::cli::shortcuts::ShortcutArgs;

#[derive(Debug, ClapArgs)]
#[command(
    after_help = "Sources: windows of region E (256 x 120 mm by default) of paper-scale deposits \
of facets' own simulator (slow and fast fills; data-samples/deposits/bench/README.md; no fast \
fill of short rods exists), and the packing generator's ordered and disordered packings of the \
same frame. Each seed draws, per source, the deposit's window (anywhere the cut band holds every \
grain it shows) or the packing, and a look per look range: light level, gradient, vignetting, \
blur, shot and read noise, stray light through the grains, rod highlights, the nuts' bore and \
its chamfer, dust and scratches, and the file (lossless 16-bit or JPEG at a drawn quality); \
the ranges and the reason for each span are in vision/src/render/look.rs. Seeds are numbered \
within a split: tuning seed k is seed k, held-out seed k is 1000000 + k; figures to report \
come from the held-out split, the default. The photograph is rendered at every scale, \
detected, and matched to the truth one-to-one (gate D/2). Recall counts uncut true grains; \
precision counts detections not flagged cut; RMS errors and the median use uncut true grains; \
the orientation RMS is over every matched grain, those turned by more than 10 degrees \
(fitted across their neighbours, also counted apart) included; orientation errors are modulo \
the shape's symmetry. A photograph the detector refuses counts as nothing found, and is \
counted and listed. Times are wall times per photograph of the detector and, apart, of \
rendering and storing the photograph. Peak memory is the process's peak resident memory \
during a detection (Linux: VmHWM, reset before each detection), photograph and bench data \
included. Printed: the figures per shape, scale and look range (every source and seed \
pooled), then per source, then where the detector's time goes step by step, then the \
sources' windows and packings."
)]
pub struct Args {
    /// CSV table of the results: one row per photograph, then per source, shape, scale and
    /// look range pooled over the seeds (seed `all`), then pooled over sources too (source
    /// `all`). Beside it, `<name>-looks.csv`: every look drawn; `<name>-phases.csv`: the
    /// detector's wall time per photograph step by step of its pipeline.
    #[arg(long, default_value = "bench-vision.csv")]
    out: PathBuf,

    /// Scales, pixels per millimetre (comma separated).
    #[arg(long, value_delimiter = ',', default_value = "6,10")]
    px_per_mm: Vec<f64>,

    /// Look ranges (comma separated, among lab-like, hard): lab-like is what a careful lab
    /// rig gives, hard a poor photograph (dim, uneven, blurred, noisy, stray light, dust,
    /// heavy JPEG).
    #[arg(long, value_delimiter = ',', default_value = "lab-like,hard")]
    looks: Vec<LookRange>,

    /// Grains to benchmark (comma separated, among square, rod53, rod3).
    #[arg(long, value_delimiter = ',', default_value = "square,rod53,rod3", value_parser = ["square", "rod53", "rod3"])]
    shapes: Vec<String>,

    /// Sources of the grains (comma separated, among deposits, packings).
    #[arg(long, value_delimiter = ',', default_value = "deposits,packings")]
    sources: Vec<SourceKind>,

    /// The set the seeds come from: held-out (for figures to report) or tuning (for tuning
    /// the detector).
    #[arg(long, default_value = "held-out")]
    split: Split,

    /// Seeds, numbered within the split from 1: one (`1`), a list (`1,4,7`), a range
    /// (`1-10`) or a mix. With several, every figure is pooled over them (grains, not seeds,
    /// weigh equally); the CSV keeps each photograph.
    #[arg(long = "seed", default_value = "1", value_parser = parse_seeds)]
    seeds: Seeds,

    /// Width and height of the photographed window, mm (default region E, 256,120: the full
    /// width of the silo).
    #[arg(long, value_delimiter = ',')]
    frame_mm: Option<Vec<f64>>,

    #[command(flatten)]
    shortcuts: ShortcutArgs,
}

pub fn run(args: Args) -> anyhow::Result<()> {
    let region_e = REGION_E_FRAME.map(|m| m * 1e3);
    let [width, height] = args.frame_mm.as_deref().unwrap_or(&region_e)[..] else {
        anyhow::bail!("--frame-mm: expected a width and a height (mm), e.g. 256,120");
    };
    let config = VisionBench {
        px_per_mm: args.px_per_mm,
        looks: args.looks,
        shapes: args.shapes,
        sources: args.sources,
        split: args.split,
        seeds: args.seeds,
        frame: [width * 1e-3, height * 1e-3],
        shortcuts: args.shortcuts.shortcuts(),
    };
    config.validate()?;
    let bar = ProgressBar::new(config.photographs() as u64).with_style(
        ProgressStyle::with_template("{bar:40} {pos}/{len} photographs, {elapsed} {msg}")
            .unwrap_or_else(|_| ProgressStyle::default_bar()),
    );
    let report = bench::run(&config, &|event| match event {
        VisionEvent::Source {
            shape,
            source,
            seed,
        } => bar.set_message(format!("{shape} {source} seed {seed}")),
        VisionEvent::Photograph {
            shape,
            source,
            px_per_mm,
            look,
        } => bar.set_message(format!(
            "{shape} {source} {px_per_mm} px/mm {}",
            look.name()
        )),
        VisionEvent::Done => bar.inc(1),
    })?;
    bar.finish_and_clear();
    let shortcuts = args.shortcuts.describe();
    let rows = report.rows();
    bench::write_results_csv(&args.out, &rows, config.split, &shortcuts)?;
    let looks_out = bench::looks_path(&args.out);
    bench::write_looks_csv(&looks_out, &report.looks)?;
    let phases_out = bench::phases_path(&args.out);
    bench::write_phases_csv(&phases_out, &report.spent)?;
    if config.shortcuts != Shortcuts::default() {
        println!(
            "Detector shortcuts taken: {shortcuts} (docs/results/detector-bench.md, \"Speed against accuracy\").\n"
        );
    }
    println!(
        "Seeds {} of the {} split, {:.0} x {:.0} mm frames.\n",
        config
            .seeds
            .0
            .iter()
            .map(u64::to_string)
            .collect::<Vec<_>>()
            .join(","),
        config.split.name(),
        width,
        height
    );
    println!("{}", bench::markdown(&report.by_shape, false));
    println!(
        "Per source:\n\n{}",
        bench::markdown(&report.by_source, true)
    );
    if !report.refusals.is_empty() {
        println!(
            "Photographs the detector refused (counted as nothing found):\n\n- {}\n",
            report.refusals.join("\n- ")
        );
    }
    println!("{}", bench::where_time_goes(&report.spent));
    println!("Sources:\n\n{}", report.sources);
    eprintln!(
        "table written to {}, the looks to {}, the detector's time step by step to {}",
        args.out.display(),
        looks_out.display(),
        phases_out.display()
    );
    Ok(())
}
