//! `facets render`: a synthetic backlit photograph of a deposit table or a generated packing.

use std::path::PathBuf;

use anyhow::{Context, bail};
use clap::Args as ClapArgs;
use vision::packing::{Packing, generate};
use vision::render::Style;

use facets::deposit::{FrameMm, read_deposit_csv};
use facets::grains::GrainKind;
use facets::photo::{Region, deposit_of, frame_deposit, photograph_frame, write_photograph};

#[derive(Debug, ClapArgs)]
#[command(
    after_help = "Writes the photograph (PNG) and, beside it, its ground truth: \
PHOTO.truth.csv with the grains that show in the frame, coordinates relative to the frame's \
bottom-left corner (mm, y up), angles folded by symmetry, and cut = 1 for grains the frame cuts.\n\n\
Examples:\n  facets render deposit.csv --px-per-mm 10 --frame-mm 0,258,290,410 --out photo.png\n  \
facets render --generate rod3 --packing ordered --px-per-mm 6 --style hard --out rods.png"
)]
pub struct Args {
    /// Deposit table (CSV: x_mm,y_mm,theta_rad,length_mm,width_mm). Grains with equal sides
    /// are drawn as nuts (hole 3.3 mm per 6.9 mm of side), others as rods.
    #[arg(required_unless_present = "generate", conflicts_with = "generate")]
    deposit: Option<PathBuf>,

    /// Instead of a deposit table, photograph a generated dense packing of this grain:
    /// square (6.9 mm nut), rod53 (4.9 x 3 mm), rod3 (8.9 x 3 mm).
    #[arg(long, value_enum)]
    generate: Option<GrainKind>,

    /// How the generated packing was laid down: ordered (slow fill, grains mostly flat) or
    /// disordered (fast fill, random orientations).
    #[arg(long, default_value = "disordered", requires = "generate")]
    packing: Packing,

    /// Image scale, pixels per millimetre.
    #[arg(long)]
    px_per_mm: f64,

    /// Output PNG.
    #[arg(long)]
    out: PathBuf,

    /// Region photographed, x_min,x_max,y_min,y_max in mm of the deposit's coordinates (as
    /// every command's --frame-mm). Default: around all grains of a deposit; 0,258,0,120 for
    /// a generated packing (whose position does not matter: only width and height count).
    #[arg(long, value_name = "X_MIN,X_MAX,Y_MIN,Y_MAX", value_parser = FrameMm::parse, allow_hyphen_values = true)]
    frame_mm: Option<FrameMm>,

    /// Look of the photograph: clean (even light, sharp), lab (uneven light, some blur, noise,
    /// dust, scratches) or hard (strong blur, low contrast, heavy noise, dirty glass).
    #[arg(long, default_value = "lab", value_parser = ["clean", "lab", "hard"])]
    style: String,

    /// Bits per pixel of the PNG: 8 or 16.
    #[arg(long, default_value_t = 16, value_parser = parse_bits)]
    bits: u8,

    /// Seed of the noise, dust, scratches, light (and of the generated packing).
    #[arg(long, default_value_t = 1)]
    seed: u64,
}

/// The frame of a generated packing when none is given (mm).
const GENERATED_FRAME: FrameMm = FrameMm {
    x_min: 0.0,
    x_max: 258.0,
    y_min: 0.0,
    y_max: 120.0,
};

fn parse_bits(text: &str) -> Result<u8, String> {
    match text.trim() {
        "8" => Ok(8),
        "16" => Ok(16),
        other => Err(format!("`{other}`: expected 8 or 16")),
    }
}

pub fn run(args: Args) -> anyhow::Result<()> {
    let style = Style::named(&args.style).context("unknown style")?;
    let (outlines, truth, frame) = match (&args.deposit, args.generate) {
        (Some(path), _) => {
            let deposit = read_deposit_csv(path)?;
            let region = match &args.frame_mm {
                Some(f) => Region::of_frame(f),
                None => Region::around(&deposit).with_context(|| {
                    format!(
                        "{}: the deposit has no grains; give --frame-mm",
                        path.display()
                    )
                })?,
            };
            let frame = photograph_frame(&region, args.px_per_mm)?;
            let (outlines, truth) = frame_deposit(&deposit, &region, &frame);
            (outlines, truth, frame)
        }
        (None, Some(kind)) => {
            let region = Region::of_frame(&args.frame_mm.unwrap_or(GENERATED_FRAME));
            let frame = photograph_frame(&region, args.px_per_mm)?;
            let shape = kind.photographed();
            let packed = generate(shape, args.packing, &frame, args.seed);
            eprintln!(
                "generated packing: fraction {:.3}, deepest overlap {:.2} % of D, {:.1} % of grains touching a neighbour",
                packed.packing_fraction,
                100.0 * packed.max_overlap,
                100.0 * packed.touching_fraction
            );
            let truth = deposit_of(&packed.grains, &frame);
            (packed.grains, truth, frame)
        }
        (None, None) => bail!("give a deposit table or --generate"),
    };
    if outlines.is_empty() {
        eprintln!("warning: no grain of the deposit shows in the frame; the photograph is empty");
    }
    let truth_path = write_photograph(
        &args.out, &outlines, &truth, &frame, &style, args.seed, args.bits,
    )?;
    let cut = truth.grains.iter().filter(|g| g.cut).count();
    eprintln!(
        "{}: {} x {} px, {} grains ({cut} cut by the frame); truth in {}",
        args.out.display(),
        frame.columns(),
        frame.rows(),
        truth.grains.len(),
        truth_path.display()
    );
    Ok(())
}
