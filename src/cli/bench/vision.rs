//! `facets bench vision`: detector accuracy and speed on rendered photographs of dense packings.

use std::fmt::Write as _;
use std::path::PathBuf;

use clap::Args as ClapArgs;
use indicatif::{ProgressBar, ProgressStyle};
use vision::evaluate::Tally;
use vision::evaluate::bench::{Case, FRAME_HEIGHT, FRAME_WIDTH, run_case, shapes};
use vision::packing::{Packing, generate};
use vision::{Frame, Phases, Shortcuts};

use facets::io::write_atomic;

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

/// The seeds `--seed` names, in the order given, each once.
#[derive(Clone, Debug)]
struct Seeds(Vec<u64>);

fn parse_seeds(text: &str) -> Result<Seeds, String> {
    let mut seeds: Vec<u64> = Vec::new();
    for part in text.split(',').map(str::trim) {
        let number = |s: &str| {
            s.trim().parse::<u64>().map_err(|_| {
                format!("'{s}' in '{text}': expected a seed (a whole number), a list 1,4,7 or a range 12-21")
            })
        };
        let (first, last) = match part.split_once('-') {
            Some((a, b)) => (number(a)?, number(b)?),
            None => {
                let n = number(part)?;
                (n, n)
            }
        };
        if first > last {
            return Err(format!("range '{part}' in '{text}' runs backwards"));
        }
        if last - first >= 10_000 {
            return Err(format!(
                "range '{part}' in '{text}' names more than 10 000 seeds"
            ));
        }
        for seed in first..=last {
            if !seeds.contains(&seed) {
                seeds.push(seed);
            }
        }
    }
    Ok(Seeds(seeds))
}

#[derive(Clone, Copy)]
struct Row {
    shape: &'static str,
    packing: &'static str,
    /// The seed, or none for a row pooled over every seed.
    seed: Option<u64>,
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
    let total =
        chosen.len() * packings.len() * args.seeds.0.len() * args.px_per_mm.len() * styles.len();
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
        "| shape | packing | seed | grains in frame | packing fraction | deepest overlap (of D) | touching a neighbour | generation s |\n|---|---|---|---|---|---|---|---|\n",
    );
    let several = args.seeds.0.len() > 1;
    let shortcuts = args.shortcuts.shortcuts();
    let mut spent: Vec<Spent> = Vec::new();
    for (shape_name, shape) in chosen {
        let mut pooled: Vec<Row> = Vec::new();
        for (&seed, (pi, &(packing, packing_name))) in args
            .seeds
            .0
            .iter()
            .flat_map(|s| std::iter::repeat(s).zip(packings.iter().enumerate()))
        {
            bar.set_message(format!("packing {shape_name} {packing_name} seed {seed}"));
            let start = std::time::Instant::now();
            let packed = generate(shape, packing, &frame, seed.wrapping_add(pi as u64));
            let _ = writeln!(
                packings_table,
                "| {shape_name} | {packing_name} | {seed} | {} | {:.3} | {:.2} % | {:.1} % | {:.2} |",
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
                        seed,
                        shortcuts,
                    };
                    let outcome = run_case(&case, &packed)?;
                    bar.inc(1);
                    spend(&mut spent, shape_name, px_per_mm, style, &outcome.phases);
                    let row = Row {
                        shape: shape_name,
                        packing: packing_name,
                        seed: Some(seed),
                        px_per_mm,
                        style,
                        photos: 1,
                        tally: outcome.tally,
                        seconds: outcome.detect_seconds,
                        render_seconds: outcome.render_seconds,
                    };
                    // Both packings of this seed, and (with several seeds) of every seed.
                    let pools = [Some(seed)].into_iter().chain(several.then_some(None));
                    for pool in pools {
                        pool_into(&mut pooled, row, pool);
                    }
                    rows.push(row);
                }
            }
        }
        // Each seed's pooled rows, then those of every seed.
        pooled.sort_by_key(|r| r.seed.is_none());
        rows.extend(pooled);
    }
    bar.finish_and_clear();
    write_atomic(&args.out, |w| {
        use std::io::Write;
        writeln!(
            w,
            "shape,packing,seed,px_per_mm,style,photos,truth_uncut,recall,precision,centre_rms_mm,orientation_rms_deg,turned_grains,unturned_orientation_rms_deg,cut_detections,cut_matched,seconds_per_photo,render_seconds_per_photo,shortcuts"
        )?;
        for r in &rows {
            let t = &r.tally;
            writeln!(
                w,
                "{},{},{},{},{},{},{},{:.5},{:.5},{:.4},{:.3},{},{:.3},{},{},{:.4},{:.4},{}",
                r.shape,
                r.packing,
                r.seed.map_or("all".to_string(), |k| k.to_string()),
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
                r.render_seconds / r.photos as f64,
                args.shortcuts.describe()
            )?;
        }
        Ok(())
    })?;
    let phases_out = phases_path(&args.out);
    write_atomic(&phases_out, |w| {
        use std::io::Write;
        writeln!(w, "shape,px_per_mm,style,photos,phase,seconds_per_photo")?;
        for s in &spent {
            for (phase, time) in s.phases.iter() {
                writeln!(
                    w,
                    "{},{},{},{},{phase},{:.4}",
                    s.shape,
                    s.px_per_mm,
                    s.style,
                    s.photos,
                    time.as_secs_f64() / s.photos as f64
                )?;
            }
        }
        Ok(())
    })?;
    if shortcuts != Shortcuts::default() {
        println!(
            "Detector shortcuts taken: {} (docs/results/detector-bench.md, \"Speed against accuracy\").\n",
            args.shortcuts.describe()
        );
    }
    println!("{}", markdown(&rows, several));
    println!("{}", where_time_goes(&spent));
    println!("Packings (258 x 120 mm frame, one core):\n\n{packings_table}");
    eprintln!(
        "table written to {}, the detector's time step by step to {}",
        args.out.display(),
        phases_out.display()
    );
    Ok(())
}

/// The detector's time step by step, over every photograph of a shape, scale and style.
struct Spent {
    shape: &'static str,
    px_per_mm: f64,
    style: &'static str,
    photos: usize,
    phases: Phases,
}

/// Adds a photograph's steps to those of its shape, scale and style.
fn spend(
    spent: &mut Vec<Spent>,
    shape: &'static str,
    px_per_mm: f64,
    style: &'static str,
    phases: &Phases,
) {
    let same = |s: &&mut Spent| s.shape == shape && s.px_per_mm == px_per_mm && s.style == style;
    let s = match spent.iter_mut().find(same) {
        Some(s) => s,
        None => {
            spent.push(Spent {
                shape,
                px_per_mm,
                style,
                photos: 0,
                phases: Phases::default(),
            });
            spent.last_mut().expect("just pushed")
        }
    };
    s.photos += 1;
    s.phases.add_all(phases);
}

/// The CSV of the detector's steps beside the results' (`bench-vision.csv`:
/// `bench-vision-phases.csv`).
fn phases_path(out: &std::path::Path) -> PathBuf {
    let stem = out
        .file_stem()
        .map_or("bench-vision".into(), |s| s.to_string_lossy().into_owned());
    out.with_file_name(format!("{stem}-phases.csv"))
}

/// Each shape, scale and style's time per photograph step by step, with each step's share.
fn where_time_goes(spent: &[Spent]) -> String {
    let mut s = String::from(
        "Where the detector's time goes (wall seconds per photograph, both packings and every \
         seed pooled; steps in pipeline order, a step's share in brackets when 5 % or more):\n\n",
    );
    for sp in spent {
        let n = sp.photos as f64;
        let total = sp.phases.total().as_secs_f64();
        let steps: Vec<String> = sp
            .phases
            .iter()
            .map(|(name, time)| {
                let t = time.as_secs_f64();
                let share = if total > 0.0 { t / total } else { 0.0 };
                if share >= 0.05 {
                    format!("{name} {:.3} ({:.0} %)", t / n, 100.0 * share)
                } else {
                    format!("{name} {:.3}", t / n)
                }
            })
            .collect();
        let _ = writeln!(
            s,
            "- {} {} px/mm {} ({:.3} s): {}",
            sp.shape,
            sp.px_per_mm,
            sp.style,
            total / n,
            steps.join(", ")
        );
    }
    s
}

/// Adds a photograph's row to the row of `pooled` that pools both packings of `seed` (none:
/// of every seed) at its scale and style, started when there is none yet.
fn pool_into(pooled: &mut Vec<Row>, row: Row, seed: Option<u64>) {
    let same =
        |r: &&mut Row| r.seed == seed && r.px_per_mm == row.px_per_mm && r.style == row.style;
    match pooled.iter_mut().find(same) {
        Some(p) => {
            p.tally += row.tally;
            p.photos += 1;
            p.seconds += row.seconds;
            p.render_seconds += row.render_seconds;
        }
        None => pooled.push(Row {
            packing: "both",
            seed,
            ..row
        }),
    }
}

/// The pooled rows (both packings) as markdown: with several seeds, those pooled over all of
/// them, then one table per seed; with one, that seed's.
fn markdown(rows: &[Row], several: bool) -> String {
    let both = |r: &&Row| r.packing == "both";
    if !several {
        return table(rows.iter().filter(both), false);
    }
    let mut s = table(rows.iter().filter(both).filter(|r| r.seed.is_none()), false);
    s.push_str("\nPer seed:\n\n");
    s.push_str(&table(
        rows.iter().filter(both).filter(|r| r.seed.is_some()),
        true,
    ));
    s
}

/// Rows as a markdown table, with a seed column when `by_seed`.
fn table<'r>(rows: impl Iterator<Item = &'r Row>, by_seed: bool) -> String {
    let (head, rule) = if by_seed {
        ("| seed ", "|---")
    } else {
        ("", "")
    };
    let mut s = format!(
        "{head}| shape | px/mm | style | grains | recall | precision | centre RMS (mm) | orientation RMS (deg) | turned > 10 deg | RMS of the rest (deg) | detect s/photo | render s/photo |\n{rule}|---|---|---|---|---|---|---|---|---|---|---|---|\n",
    );
    for r in rows {
        let t = &r.tally;
        if by_seed {
            let _ = write!(s, "| {} ", r.seed.map_or(String::new(), |k| k.to_string()));
        }
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

#[cfg(test)]
mod tests {
    use super::{parse_seeds, phases_path};
    use std::path::Path;

    #[test]
    fn the_steps_are_written_beside_the_table() {
        assert_eq!(
            phases_path(Path::new("runs/bench-vision.csv")),
            Path::new("runs/bench-vision-phases.csv")
        );
        assert_eq!(phases_path(Path::new("b")), Path::new("b-phases.csv"));
    }

    #[test]
    fn seeds_are_read_as_lists_and_ranges_each_once() {
        assert_eq!(parse_seeds("1").unwrap().0, [1]);
        assert_eq!(parse_seeds("12-14, 3,13").unwrap().0, [12, 13, 14, 3]);
        let backwards = parse_seeds("5-3").unwrap_err();
        assert!(backwards.contains("'5-3'"), "{backwards}");
        let word = parse_seeds("1,x").unwrap_err();
        assert!(word.contains("'x'") && word.contains("'1,x'"), "{word}");
    }
}
