use std::path::PathBuf;

use anyhow::bail;
use clap::{Args as ClapArgs, ValueEnum};
use indicatif::{ProgressBar, ProgressStyle};
use rayon::prelude::*;

use facets::detection;
use vision::DetectParams;

use super::shortcuts::ShortcutArgs;

#[derive(Clone, Copy, Debug, ValueEnum)]
pub enum Shape {
    /// Square nuts (6.9 mm side, 3.3 mm hole).
    Square,
    /// Cylinders seen from the side (3 mm wide; length from --aspect).
    Rod,
}

#[derive(Debug, ClapArgs)]
pub struct Args {
    /// Photographs (8/16-bit PNG, TIFF, JPEG) or folders of them.
    #[arg(required = true)]
    pub photos: Vec<PathBuf>,
    /// Grain outline in the photographs.
    #[arg(long, value_enum)]
    pub shape: Shape,
    /// Rod length / width: "5/3" (4.9 mm rods), "3" (8.9 mm rods), or any d >= 1 (length
    /// d x 3 mm). Ignored for squares.
    #[arg(long, default_value = "1", value_parser = detection::parse_aspect)]
    pub aspect: f64,
    /// Scale of the photographs in pixels per millimetre.
    #[arg(long)]
    pub px_per_mm: f64,
    /// Folder for the tables (<photo>.csv) and overlays (<photo>_overlay.png).
    #[arg(long, default_value = ".")]
    pub out: PathBuf,
    /// Also write the detected outlines drawn over each photograph.
    #[arg(long)]
    pub overlay: bool,
    /// Refuse fits whose agreement with the photograph is below this (0..1).
    #[arg(long, default_value_t = 0.5)]
    pub min_confidence: f64,
    #[command(flatten)]
    pub shortcuts: ShortcutArgs,
    /// Also print, for each photograph, where the detector's time went: the wall time of
    /// each step of its pipeline (normalise, seeds, fits, acceptance, each repair, settle).
    #[arg(long)]
    pub timings: bool,
}

pub fn run(args: Args) -> anyhow::Result<()> {
    let shape = detection::grain_shape(matches!(args.shape, Shape::Square), args.aspect)?;
    let mut params = args
        .shortcuts
        .shortcuts()
        .apply(DetectParams::new(shape, args.px_per_mm * 1e3));
    params.min_confidence = args.min_confidence;
    params.validate()?;
    let list = detection::collect_photos(&args.photos)?;
    if list.is_empty() {
        bail!("no PNG, TIFF or JPEG photographs found in the paths given");
    }
    std::fs::create_dir_all(&args.out)?;
    let bar = ProgressBar::new(list.len() as u64).with_style(ProgressStyle::with_template(
        "{bar:40} {pos}/{len} photographs {elapsed_precise}",
    )?);
    let results: Vec<_> = list
        .par_iter()
        .map(|p| {
            let r = detection::detect_photo(p, &params, &args.out, args.overlay);
            bar.inc(1);
            (p, r)
        })
        .collect();
    bar.finish_and_clear();
    let mut failed = 0;
    for (photo, result) in results {
        match result {
            Ok(r) if r.grains == 0 => {
                eprintln!("warning: no grains found in {}", photo.display())
            }
            Ok(r) => {
                println!(
                    "{}: {} grains ({} cut by the frame) -> {}",
                    photo.display(),
                    r.grains,
                    r.cut,
                    r.table.display()
                );
                if args.timings {
                    println!("  steps (s): {}", detection::steps_line(&r.phases));
                }
                let check = what_to_check(&args);
                if let Some(warning) = detection::poorly_explained(photo, r.explained, &check) {
                    eprintln!("warning: {warning}");
                }
            }
            Err(e) => {
                failed += 1;
                eprintln!("error: {e:#}");
            }
        }
    }
    if failed > 0 {
        bail!("{failed} of {} photographs failed", list.len());
    }
    Ok(())
}

/// What to check when a photograph's dark area is left largely unexplained.
fn what_to_check(args: &Args) -> String {
    let shape = match args.shape {
        Shape::Square => "--shape".to_string(),
        Shape::Rod => {
            let aspect = format!("{:.3}", args.aspect);
            let aspect = aspect.trim_end_matches('0').trim_end_matches('.');
            format!("--shape and --aspect (given {aspect})")
        }
    };
    format!(
        "{shape} and --px-per-mm ({}), or look at --overlay",
        args.px_per_mm
    )
}
