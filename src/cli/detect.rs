use std::path::PathBuf;

use anyhow::bail;
use clap::Args as ClapArgs;
use indicatif::{ProgressBar, ProgressStyle};

use facets::deposit::FrameMm;
use facets::detection::{self, Framing, InSilo, ShapeName, Sought};
use vision::{DetectParams, ScaleCheck};

use super::shortcuts::ShortcutArgs;

#[derive(Debug, ClapArgs)]
#[command(
    after_help = "Writes into --out, per photograph NAME: NAME.csv (the grains, mm, angles \
folded by symmetry, with confidence and cut columns), NAME_overlay.png with --overlay, and \
NAME.meta.json (the sidecar `facets analyse` reads) when --phi0 and --silo-width-mm are given. \
Photographs of the same name (c1/p.png, c2/p.png) would write the same table: such a batch is \
refused, and so is a batch whose tables exist already in --out (an earlier run may have written \
them from another photograph of the same name) unless --overwrite is given; detect them into \
different --out folders.\n\n\
A frame that is no backlit photograph of grains (black, white, saturated, uniform: no bright \
background, no dark grains, or no contrast above its noise) gets an empty table and a warning \
saying why, never invented grains.\n\n\
Examples:\n  facets detect photos/ --shape square --px-per-mm 8 --out detected/ --overlay\n  \
facets detect p.png --shape rod3 --px-per-mm 10 --phi0 0.25 --silo-width-mm 256 \
--frame-mm 0,256,290,410 --out detected/"
)]
pub struct Args {
    /// Photographs (8/16-bit PNG, TIFF, JPEG) or folders of them.
    #[arg(required = true)]
    pub photos: Vec<PathBuf>,
    /// Grain outline in the photographs: square, rod53, rod3 (the experiment's grains, as in
    /// every command), or rod with --length-mm (and --width-mm) for other rods: `rod` alone
    /// is refused.
    #[arg(long, value_enum)]
    pub shape: ShapeName,
    /// Length of the rods of --shape rod (mm), 1 to 20 widths.
    #[arg(long)]
    pub length_mm: Option<f64>,
    /// Width of the rods of --shape rod (mm; default 3).
    #[arg(long)]
    pub width_mm: Option<f64>,
    /// Scale of the photographs in pixels per millimetre.
    #[arg(long)]
    pub px_per_mm: f64,
    /// Folder for the tables (NAME.csv), sidecars and overlays.
    #[arg(long, default_value = ".")]
    pub out: PathBuf,
    /// Also write the detected outlines drawn over each photograph.
    #[arg(long)]
    pub overlay: bool,
    /// Refuse fits whose agreement with the photograph is below this (0..1).
    #[arg(long, default_value_t = 0.5)]
    pub min_confidence: f64,
    /// When the scale measured in a photograph (its nuts' holes, its rods' thickness)
    /// disagrees with --px-per-mm: warn (detect at --px-per-mm and say so, naming both
    /// scales), refuse (the photograph fails), or off (measure nothing). The default warns:
    /// blur and low contrast make the measurement err (a blurred 6 px/mm photograph measured
    /// 1.8 px/mm), and a correct photograph must not be refused.
    #[arg(long, default_value = "warn", value_name = "warn|refuse|off",
          value_parser = parse_scale_check)]
    pub scale_check: ScaleCheck,
    /// Replace tables, sidecars and overlays that exist already in --out.
    #[arg(long)]
    pub overwrite: bool,
    /// phi0 of the rain that built the deposits photographed; with --silo-width-mm, each table
    /// gets its sidecar NAME.meta.json.
    #[arg(long, requires = "silo_width_mm")]
    pub phi0: Option<f64>,
    /// Silo width W (mm) of the deposits photographed; with --phi0.
    #[arg(long, requires = "phi0")]
    pub silo_width_mm: Option<f64>,
    /// Where the photographs lie in the silo: x_min,x_max,y_min,y_max in mm, x from the left
    /// wall, y from the floor (as every command's --frame-mm); the tables are written in the
    /// silo's coordinates. Default: the photograph's bottom-left corner at the left wall and
    /// the floor. Needs --phi0 and --silo-width-mm.
    #[arg(long, value_name = "X_MIN,X_MAX,Y_MIN,Y_MAX", value_parser = FrameMm::parse,
          allow_hyphen_values = true, requires = "phi0")]
    pub frame_mm: Option<FrameMm>,
    #[command(flatten)]
    pub shortcuts: ShortcutArgs,
    /// Also print, for each photograph, where the detector's time went: the wall time of
    /// each step of its pipeline (normalise, seeds, fits, acceptance, each repair, settle).
    #[arg(long)]
    pub timings: bool,
}

pub fn run(args: Args) -> anyhow::Result<()> {
    let sought = Sought::new(args.shape, args.length_mm, args.width_mm)?;
    let mut params = args
        .shortcuts
        .shortcuts()
        .apply(DetectParams::new(sought.shape()?, args.px_per_mm * 1e3));
    params.min_confidence = args.min_confidence;
    params.scale_check = args.scale_check;
    params.validate()?;
    let in_silo = match (args.phi0, args.silo_width_mm) {
        (Some(phi0), Some(silo_width_mm)) => {
            let place = InSilo {
                silo_width_mm,
                phi0,
                framing: args
                    .frame_mm
                    .map_or(Framing::Corner([0.0, 0.0]), Framing::Frame),
            };
            place.validate_options()?;
            Some(place)
        }
        _ => None,
    };
    let photos = detection::collect_photos(&args.photos)?;
    if photos.is_empty() {
        bail!("no PNG, TIFF or JPEG photographs found in the paths given");
    }
    let tables = detection::table_paths(&photos, &args.out)?;
    detection::refuse_existing(&tables, args.overwrite)?;
    std::fs::create_dir_all(&args.out)?;
    let bar = ProgressBar::new(photos.len() as u64).with_style(ProgressStyle::with_template(
        "{bar:40} {pos}/{len} photographs {elapsed_precise}",
    )?);
    let results = detection::detect_all(
        &photos,
        &tables,
        &params,
        args.overlay,
        in_silo.as_ref(),
        &|| bar.inc(1),
    );
    bar.finish_and_clear();
    let check = format!(
        "{} and --px-per-mm ({}), or look at --overlay",
        sought.options(),
        args.px_per_mm
    );
    let mut failed = 0;
    for (photo, result) in photos.iter().zip(results) {
        match result {
            Ok(r) => {
                for warning in &r.warnings {
                    eprintln!("warning: {}: {warning}", photo.display());
                }
                if r.grains == 0 && r.warnings.is_empty() {
                    eprintln!("warning: {}: no grains found", photo.display());
                }
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
    if in_silo.is_none() {
        eprintln!(
            "note: no sidecars written (NAME.meta.json): give --phi0 and --silo-width-mm (and \
             --frame-mm) for `facets analyse` to read the tables without options"
        );
    }
    if failed > 0 {
        bail!("{failed} of {} photographs failed", photos.len());
    }
    Ok(())
}

/// `--scale-check`, read by the library (which names the option and its values).
fn parse_scale_check(s: &str) -> Result<ScaleCheck, String> {
    s.parse().map_err(|e: vision::DetectError| e.to_string())
}
