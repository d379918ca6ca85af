//! `facets bench vision`: detector accuracy and speed on rendered photographs of dense
//! packings. For each grain, an ordered and a disordered packing per seed, rendered at every
//! scale and in every style, detected, and matched to the truth (`vision::evaluate::bench`);
//! rows per photograph, pooled over both packings of a seed and over every seed.

mod seeds;
mod tables;

use std::fmt::Write as _;

use vision::evaluate::Tally;
use vision::evaluate::bench::{Case, FRAME_HEIGHT, FRAME_WIDTH, run_case, shapes};
use vision::packing::{Packing, generate};
use vision::{Frame, Phases, Shortcuts};

pub use seeds::{Seeds, parse_seeds};
pub use tables::{markdown, phases_path, where_time_goes, write_phases_csv, write_results_csv};

/// What to run.
#[derive(Clone, Debug)]
pub struct VisionBench {
    /// Scales (px/mm).
    pub px_per_mm: Vec<f64>,
    /// Styles, among clean, lab, hard.
    pub styles: Vec<String>,
    /// Grains, among square, rod53, rod3.
    pub shapes: Vec<String>,
    pub seeds: Seeds,
    pub shortcuts: Shortcuts,
}

/// One row of the results: a photograph, or photographs pooled.
#[derive(Clone, Copy, Debug)]
pub struct Row {
    pub shape: &'static str,
    /// "ordered", "disordered", or "both" for a pooled row.
    pub packing: &'static str,
    /// The seed, or none for a row pooled over every seed.
    pub seed: Option<u64>,
    pub px_per_mm: f64,
    pub style: &'static str,
    pub photos: usize,
    pub tally: Tally,
    pub seconds: f64,
    pub render_seconds: f64,
}

/// The detector's time step by step, over every photograph of a shape, scale and style.
#[derive(Clone, Debug)]
pub struct Spent {
    pub shape: &'static str,
    pub px_per_mm: f64,
    pub style: &'static str,
    pub photos: usize,
    pub phases: Phases,
}

/// What the bench gave.
#[derive(Clone, Debug)]
pub struct VisionReport {
    pub rows: Vec<Row>,
    pub spent: Vec<Spent>,
    /// The packings generated, as a markdown table.
    pub packings: String,
    /// More than one seed: rows pooled over every seed exist.
    pub several_seeds: bool,
}

/// What the bench reports as it goes.
#[derive(Clone, Copy, Debug)]
pub enum VisionEvent<'a> {
    /// A packing is being generated.
    Packing {
        shape: &'a str,
        packing: &'a str,
        seed: u64,
    },
    /// A photograph is being rendered and detected.
    Photograph {
        shape: &'a str,
        packing: &'a str,
        px_per_mm: f64,
        style: &'a str,
    },
    /// It is done.
    Done,
}

const PACKINGS: [(Packing, &str); 2] = [
    (Packing::Ordered, "ordered"),
    (Packing::Disordered, "disordered"),
];

const STYLES: [&str; 3] = ["clean", "lab", "hard"];

impl VisionBench {
    /// Refuses scales and names the bench has not, naming the option.
    pub fn validate(&self) -> anyhow::Result<()> {
        if let Some(bad) = self
            .px_per_mm
            .iter()
            .find(|s| !(s.is_finite() && **s > 0.0))
        {
            anyhow::bail!("--px-per-mm {bad}: expected positive scales");
        }
        if let Some(bad) = self.styles.iter().find(|s| !STYLES.contains(&s.as_str())) {
            anyhow::bail!("--styles {bad}: expected clean, lab or hard");
        }
        let known = shapes().map(|(name, _)| name);
        if let Some(bad) = self.shapes.iter().find(|s| !known.contains(&s.as_str())) {
            anyhow::bail!("--shapes {bad}: expected square, rod53 or rod3");
        }
        Ok(())
    }

    /// Photographs the bench renders and detects.
    pub fn photographs(&self) -> usize {
        let chosen = shapes()
            .iter()
            .filter(|(name, _)| self.shapes.iter().any(|s| s == name))
            .count();
        chosen * PACKINGS.len() * self.seeds.0.len() * self.px_per_mm.len() * self.styles.len()
    }
}

/// Runs the bench.
pub fn run(bench: &VisionBench, progress: &dyn Fn(VisionEvent)) -> anyhow::Result<VisionReport> {
    bench.validate()?;
    let styles: Vec<&'static str> = bench
        .styles
        .iter()
        .filter_map(|s| STYLES.iter().copied().find(|k| k == s))
        .collect();
    let chosen: Vec<_> = shapes()
        .into_iter()
        .filter(|(name, _)| bench.shapes.iter().any(|s| s == name))
        .collect();
    let frame = Frame {
        width: FRAME_WIDTH,
        height: FRAME_HEIGHT,
        scale: 1e4,
    };
    let mut rows = Vec::new();
    let mut packings = String::from(
        "| shape | packing | seed | grains in frame | packing fraction | deepest overlap (of D) | touching a neighbour | generation s |\n|---|---|---|---|---|---|---|---|\n",
    );
    let several = bench.seeds.0.len() > 1;
    let mut spent: Vec<Spent> = Vec::new();
    for (shape_name, shape) in chosen {
        let mut pooled: Vec<Row> = Vec::new();
        for (&seed, (pi, &(packing, packing_name))) in bench
            .seeds
            .0
            .iter()
            .flat_map(|s| std::iter::repeat(s).zip(PACKINGS.iter().enumerate()))
        {
            progress(VisionEvent::Packing {
                shape: shape_name,
                packing: packing_name,
                seed,
            });
            let start = std::time::Instant::now();
            let packed = generate(shape, packing, &frame, seed.wrapping_add(pi as u64));
            let _ = writeln!(
                packings,
                "| {shape_name} | {packing_name} | {seed} | {} | {:.3} | {:.2} % | {:.1} % | {:.2} |",
                packed.grains.len(),
                packed.packing_fraction,
                100.0 * packed.max_overlap,
                100.0 * packed.touching_fraction,
                start.elapsed().as_secs_f64()
            );
            for &px_per_mm in &bench.px_per_mm {
                for &style in &styles {
                    progress(VisionEvent::Photograph {
                        shape: shape_name,
                        packing: packing_name,
                        px_per_mm,
                        style,
                    });
                    let case = Case {
                        shape_name,
                        shape,
                        packing,
                        px_per_mm,
                        style_name: style,
                        seed,
                        shortcuts: bench.shortcuts,
                    };
                    let outcome = run_case(&case, &packed)?;
                    progress(VisionEvent::Done);
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
    Ok(VisionReport {
        rows,
        spent,
        packings,
        several_seeds: several,
    })
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
    match spent.iter_mut().find(same) {
        Some(s) => {
            s.photos += 1;
            s.phases.add_all(phases);
        }
        None => {
            let mut s = Spent {
                shape,
                px_per_mm,
                style,
                photos: 1,
                phases: Phases::default(),
            };
            s.phases.add_all(phases);
            spent.push(s);
        }
    }
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
