//! `facets bench vision`: detector accuracy and speed on rendered photographs of dense packings.

use std::fmt::Write as _;
use std::path::PathBuf;

use clap::Args as ClapArgs;
use indicatif::{ProgressBar, ProgressStyle};
use vision::Frame;
use vision::evaluate::Tally;
use vision::evaluate::bench::{Case, FRAME_HEIGHT, FRAME_WIDTH, run_case, shapes};
use vision::packing::{Packing, generate};

use facets::io::write_atomic;

#[derive(Debug, ClapArgs)]
#[command(
    after_help = "For each grain (square, rod53, rod3) it generates an ordered (slow-fill) \
and a disordered (fast-fill) dense packing of a 258 x 120 mm frame, renders each at every scale \
and in every style, runs the detector, and matches detections to the truth one-to-one (gate D/2). \
Recall counts uncut true grains; precision counts detections not flagged cut; RMS errors use \
uncut true grains; orientation errors are modulo the shape's symmetry, and the grains turned \
by more than 10 degrees (fitted across their neighbours) are also counted apart, with the RMS \
of the others. Times are wall \
times per photograph of the detector and, apart, of the renderer."
)]
pub struct Args {
    /// CSV table of the results (one row per shape, packing, scale and style, plus the two
    /// packings pooled).
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

    /// Seed of the packings and photographs.
    #[arg(long, default_value_t = 1)]
    seed: u64,
}

#[derive(Clone, Copy)]
struct Row {
    shape: &'static str,
    packing: &'static str,
    px_per_mm: f64,
    style: &'static str,
    photos: usize,
    tally: Tally,
    seconds: f64,
    render_seconds: f64,
}

pub fn run(args: Args) -> anyhow::Result<()> {
    if let Some(bad) = args
        .px_per_mm
        .iter()
        .find(|s| !(s.is_finite() && **s > 0.0))
    {
        anyhow::bail!("--px-per-mm {bad}: expected positive scales");
    }
    let styles: Vec<&'static str> = args
        .styles
        .iter()
        .map(|s| match s.as_str() {
            "clean" => "clean",
            "lab" => "lab",
            _ => "hard",
        })
        .collect();
    let packings = [
        (Packing::Ordered, "ordered"),
        (Packing::Disordered, "disordered"),
    ];
    let chosen: Vec<_> = shapes()
        .into_iter()
        .filter(|(name, _)| args.shapes.iter().any(|s| s == name))
        .collect();
    let total = chosen.len() * packings.len() * args.px_per_mm.len() * styles.len();
    let bar = ProgressBar::new(total as u64).with_style(
        ProgressStyle::with_template("{bar:40} {pos}/{len} photographs, {elapsed} {msg}")
            .expect("valid template"),
    );
    let frame = Frame {
        width: FRAME_WIDTH,
        height: FRAME_HEIGHT,
        scale: 1e4,
    };
    let mut rows = Vec::new();
    let mut packings_table = String::from(
        "| shape | packing | grains in frame | packing fraction | deepest overlap (of D) | touching a neighbour | generation s |\n|---|---|---|---|---|---|---|\n",
    );
    for (shape_name, shape) in chosen {
        let mut pooled: Vec<Row> = Vec::new();
        for (pi, &(packing, packing_name)) in packings.iter().enumerate() {
            bar.set_message(format!("packing {shape_name} {packing_name}"));
            let start = std::time::Instant::now();
            let packed = generate(shape, packing, &frame, args.seed.wrapping_add(pi as u64));
            let _ = writeln!(
                packings_table,
                "| {shape_name} | {packing_name} | {} | {:.3} | {:.2} % | {:.1} % | {:.2} |",
                packed.grains.len(),
                packed.packing_fraction,
                100.0 * packed.max_overlap,
                100.0 * packed.touching_fraction,
                start.elapsed().as_secs_f64()
            );
            for &px_per_mm in &args.px_per_mm {
                for &style in &styles {
                    bar.set_message(format!(
                        "{shape_name} {packing_name} {px_per_mm} px/mm {style}"
                    ));
                    let case = Case {
                        shape_name,
                        shape,
                        packing,
                        px_per_mm,
                        style_name: style,
                        seed: args.seed,
                    };
                    let outcome = run_case(&case, &packed)?;
                    bar.inc(1);
                    let row = Row {
                        shape: shape_name,
                        packing: packing_name,
                        px_per_mm,
                        style,
                        photos: 1,
                        tally: outcome.tally,
                        seconds: outcome.detect_seconds,
                        render_seconds: outcome.render_seconds,
                    };
                    match pooled
                        .iter_mut()
                        .find(|r| r.px_per_mm == px_per_mm && r.style == style)
                    {
                        Some(p) => {
                            p.tally += row.tally;
                            p.photos += 1;
                            p.seconds += row.seconds;
                            p.render_seconds += row.render_seconds;
                        }
                        None => pooled.push(Row {
                            packing: "both",
                            ..row
                        }),
                    }
                    rows.push(row);
                }
            }
        }
        rows.extend(pooled);
    }
    bar.finish_and_clear();
    write_atomic(&args.out, |w| {
        use std::io::Write;
        writeln!(
            w,
            "shape,packing,px_per_mm,style,photos,truth_uncut,recall,precision,centre_rms_mm,orientation_rms_deg,turned_grains,unturned_orientation_rms_deg,cut_detections,cut_matched,seconds_per_photo,render_seconds_per_photo"
        )?;
        for r in &rows {
            let t = &r.tally;
            writeln!(
                w,
                "{},{},{},{},{},{},{:.5},{:.5},{:.4},{:.3},{},{:.3},{},{},{:.4},{:.4}",
                r.shape,
                r.packing,
                r.px_per_mm,
                r.style,
                r.photos,
                t.truth_uncut,
                t.recall(),
                t.precision(),
                t.centre_rms_mm(),
                t.orientation_rms_deg(),
                t.turned,
                t.unturned_orientation_rms_deg(),
                t.detections_cut,
                t.detections_cut_matched,
                r.seconds / r.photos as f64,
                r.render_seconds / r.photos as f64
            )?;
        }
        Ok(())
    })?;
    println!("{}", markdown(&rows));
    println!("Packings (258 x 120 mm frame, one core):\n\n{packings_table}");
    eprintln!("table written to {}", args.out.display());
    Ok(())
}

/// The pooled rows (both packings) as a markdown table.
fn markdown(rows: &[Row]) -> String {
    let mut s = String::from(
        "| shape | px/mm | style | grains | recall | precision | centre RMS (mm) | orientation RMS (deg) | turned > 10 deg | RMS of the rest (deg) | detect s/photo | render s/photo |\n|---|---|---|---|---|---|---|---|---|---|---|---|\n",
    );
    for r in rows.iter().filter(|r| r.packing == "both") {
        let t = &r.tally;
        let _ = writeln!(
            s,
            "| {} | {} | {} | {} | {:.2} % | {:.2} % | {:.3} | {:.2} | {} | {:.2} | {:.3} | {:.3} |",
            r.shape,
            r.px_per_mm,
            r.style,
            t.truth_uncut,
            100.0 * t.recall(),
            100.0 * t.precision(),
            t.centre_rms_mm(),
            t.orientation_rms_deg(),
            t.turned,
            t.unturned_orientation_rms_deg(),
            r.seconds / r.photos as f64,
            r.render_seconds / r.photos as f64
        );
    }
    s
}
