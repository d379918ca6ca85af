//! `facets bench vision`: detector accuracy, speed and memory on rendered photographs of
//! simulated deposits and of generated packings, in looks drawn at random.
//!
//! Stages, per seed of the chosen split (`split`), per grain:
//! 1. the sources: windows of the simulated deposits of that grain (`deposits`, the window
//!    drawn from the seed), and an ordered and a disordered packing (`vision::packing`);
//! 2. per source, look range and scale: a look drawn from the seed (`vision::render::Look`),
//!    the photograph rendered and stored as the look asks, detected, and matched to the truth
//!    (`vision::evaluate::bench`);
//! 3. the rows pooled over seeds per source, and over sources (`pool`).

mod deposits;
mod pool;
mod seeds;
mod split;
mod tables;

use std::fmt::Write as _;

use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use vision::evaluate::Tally;
use vision::evaluate::bench::{Outcome, Photo, run_photo, shapes};
use vision::packing::{Packing, generate};
use vision::render::{Look, LookRange};
use vision::{Frame, GrainOutline, GrainShape, Phases, Shortcuts};

use crate::photo::{frame_deposit, photograph_frame};

pub use deposits::{CASES, REGION_E, SILO_WIDTH, SimulatedCase};
pub use seeds::{Seeds, parse_seeds};
pub use split::{SEEDS_PER_SPLIT, Split};
pub use tables::{
    looks_path, markdown, phases_path, where_time_goes, write_looks_csv, write_phases_csv,
    write_results_csv,
};

/// Where the grains of a photograph come from.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum SourceKind {
    /// Windows of the simulated deposits.
    Deposits,
    /// The packing generator's ordered and disordered packings.
    Packings,
}

impl SourceKind {
    pub const ALL: [SourceKind; 2] = [SourceKind::Deposits, SourceKind::Packings];

    pub fn name(self) -> &'static str {
        match self {
            SourceKind::Deposits => "deposits",
            SourceKind::Packings => "packings",
        }
    }
}

impl std::str::FromStr for SourceKind {
    type Err = String;
    fn from_str(s: &str) -> Result<Self, String> {
        SourceKind::ALL
            .into_iter()
            .find(|k| k.name() == s)
            .ok_or_else(|| format!("unknown source `{s}`: expected deposits or packings"))
    }
}

/// What to run.
#[derive(Clone, Debug)]
pub struct VisionBench {
    /// Scales (px/mm).
    pub px_per_mm: Vec<f64>,
    /// Look ranges.
    pub looks: Vec<LookRange>,
    /// Grains, among square, rod53, rod3.
    pub shapes: Vec<String>,
    /// Sources of the grains.
    pub sources: Vec<SourceKind>,
    /// The set the seeds are taken from.
    pub split: Split,
    /// Seeds, numbered within the split.
    pub seeds: Seeds,
    /// Width and height of the photographed window (m): region E's 256 x 120 mm by default.
    pub frame: [f64; 2],
    pub shortcuts: Shortcuts,
}

/// A source of one grain's photographs, by the name the tables use.
#[derive(Clone, Copy, Debug)]
enum Source {
    Deposit(&'static SimulatedCase),
    Packing(Packing),
}

impl Source {
    fn name(&self) -> &'static str {
        match self {
            Source::Deposit(c) => c.name,
            Source::Packing(Packing::Ordered) => "packing-ordered",
            Source::Packing(Packing::Disordered) => "packing-disordered",
        }
    }

    fn fill(&self) -> &'static str {
        match self {
            Source::Deposit(c) => c.fill,
            Source::Packing(Packing::Ordered) => "slow",
            Source::Packing(Packing::Disordered) => "fast",
        }
    }

    /// What tells this source's draws from another's under one seed: fixed per source, so a
    /// seed's look and window stay put when sources are added or left out.
    fn salt(&self) -> u64 {
        match self {
            Source::Packing(Packing::Ordered) => 1,
            Source::Packing(Packing::Disordered) => 2,
            Source::Deposit(c) => {
                10 + CASES.iter().position(|k| k.name == c.name).unwrap_or(0) as u64
            }
        }
    }
}

/// One row of the results: a photograph, or photographs pooled.
#[derive(Clone, Debug)]
pub struct Row {
    /// The simulated case or packing, or "all" for a row pooled over every source.
    pub source: &'static str,
    /// "slow" or "fast" fill, or "both".
    pub fill: &'static str,
    pub shape: &'static str,
    /// The seed's number in its split, or none for a row pooled over every seed.
    pub seed: Option<u64>,
    pub px_per_mm: f64,
    pub look: LookRange,
    pub photos: usize,
    pub tally: Tally,
    /// Orientation error of every matched uncut grain (degrees).
    pub orientation_errors_deg: Vec<f64>,
    /// Grains the photographs showed, cut ones included.
    pub grains: usize,
    pub seconds: f64,
    pub render_seconds: f64,
    /// Largest peak resident memory of the process during a detection (bytes), where known.
    pub peak_memory_bytes: Option<u64>,
    /// Photographs the detector refused (they count as nothing found).
    pub refused: usize,
}

/// The detector's time step by step, over every photograph of a shape, scale and look range.
#[derive(Clone, Debug)]
pub struct Spent {
    pub shape: &'static str,
    pub px_per_mm: f64,
    pub look: LookRange,
    pub photos: usize,
    pub phases: Phases,
}

/// The look a photograph was drawn with.
#[derive(Clone, Debug)]
pub struct DrawnLook {
    pub seed: u64,
    pub source: &'static str,
    pub shape: &'static str,
    pub look_range: LookRange,
    pub look: Look,
}

/// What the bench gave.
#[derive(Clone, Debug)]
pub struct VisionReport {
    /// One row per photograph.
    pub photos: Vec<Row>,
    /// Per source, shape, scale and look range, pooled over the seeds.
    pub by_source: Vec<Row>,
    /// Per shape, scale and look range, pooled over sources and seeds.
    pub by_shape: Vec<Row>,
    pub spent: Vec<Spent>,
    pub looks: Vec<DrawnLook>,
    /// The sources' windows and packings, as a markdown table.
    pub sources: String,
    /// Each photograph the detector refused, and why.
    pub refusals: Vec<String>,
}

impl VisionReport {
    /// Every row of the results table, in its order: the photographs, then the sources
    /// pooled, then the shapes pooled.
    pub fn rows(&self) -> Vec<&Row> {
        self.photos
            .iter()
            .chain(&self.by_source)
            .chain(&self.by_shape)
            .collect()
    }
}

/// What the bench reports as it goes.
#[derive(Clone, Copy, Debug)]
pub enum VisionEvent<'a> {
    /// A source's grains are being prepared (a packing generated, a deposit cut).
    Source {
        shape: &'a str,
        source: &'a str,
        seed: u64,
    },
    /// A photograph is being rendered and detected.
    Photograph {
        shape: &'a str,
        source: &'a str,
        px_per_mm: f64,
        look: LookRange,
    },
    /// It is done.
    Done,
}

/// Region E: the silo's full width by the 120 mm band analysed.
pub const REGION_E_FRAME: [f64; 2] = [SILO_WIDTH, REGION_E[1] - REGION_E[0]];

impl VisionBench {
    /// Refuses what the bench cannot run, naming the option.
    pub fn validate(&self) -> anyhow::Result<()> {
        if self.px_per_mm.is_empty() {
            anyhow::bail!("--px-per-mm: expected at least one scale");
        }
        for &s in &self.px_per_mm {
            // The photograph's size is checked as `facets render` checks it.
            photograph_frame(
                &crate::photo::Region {
                    x0: 0.0,
                    y0: 0.0,
                    width: self.frame[0],
                    height: self.frame[1],
                },
                s,
            )?;
        }
        let known = shapes().map(|(name, _)| name);
        if let Some(bad) = self.shapes.iter().find(|s| !known.contains(&s.as_str())) {
            anyhow::bail!("--shapes {bad}: expected square, rod53 or rod3");
        }
        for (option, empty) in [
            ("--looks", self.looks.is_empty()),
            ("--shapes", self.shapes.is_empty()),
            ("--sources", self.sources.is_empty()),
            ("--seed", self.seeds.0.is_empty()),
        ] {
            if empty {
                anyhow::bail!("{option}: expected at least one");
            }
        }
        for &n in &self.seeds.0 {
            self.split.seed(n).map_err(anyhow::Error::msg)?;
        }
        if self.sources.contains(&SourceKind::Deposits) {
            SimulatedCase::window(self.frame[0], self.frame[1], 0)?;
        }
        Ok(())
    }

    fn chosen_shapes(&self) -> Vec<(&'static str, GrainShape)> {
        shapes()
            .into_iter()
            .filter(|(name, _)| self.shapes.iter().any(|s| s == name))
            .collect()
    }

    fn sources_of(&self, shape: &str) -> Vec<Source> {
        let mut out = Vec::new();
        if self.sources.contains(&SourceKind::Deposits) {
            out.extend(
                CASES
                    .iter()
                    .filter(|c| c.shape == shape)
                    .map(Source::Deposit),
            );
        }
        if self.sources.contains(&SourceKind::Packings) {
            out.extend([
                Source::Packing(Packing::Ordered),
                Source::Packing(Packing::Disordered),
            ]);
        }
        out
    }

    /// Photographs the bench renders and detects.
    pub fn photographs(&self) -> usize {
        let sources: usize = self
            .chosen_shapes()
            .iter()
            .map(|(name, _)| self.sources_of(name).len())
            .sum();
        sources * self.seeds.0.len() * self.px_per_mm.len() * self.looks.len()
    }
}

/// The seeds one seed of the split gives a source: of its grains (the deposit's window or the
/// packing), of its looks, and of its photographs' noise, dust and light; each source's own,
/// and none of them drawn from another's stream.
fn source_seeds(seed: u64, source: &Source) -> [u64; 3] {
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    rng.set_stream(source.salt());
    [rng.random(), rng.random(), rng.random()]
}

/// A source's grains under one seed, in frame coordinates, and a line about them.
fn grains_of(
    source: Source,
    shape: GrainShape,
    size: [f64; 2],
    seed: u64,
) -> anyhow::Result<(Vec<GrainOutline>, String)> {
    let frame = Frame {
        width: size[0],
        height: size[1],
        scale: 1e4,
    };
    let start = std::time::Instant::now();
    match source {
        Source::Deposit(case) => {
            let deposit = case.deposit()?;
            let region = SimulatedCase::window(size[0], size[1], seed)?;
            let (grains, truth) = frame_deposit(&deposit, &region, &frame);
            // As the packings' fraction counts it: whole outlines, holes included, of the grains
            // whose centre is in the window.
            let covered: f64 = grains
                .iter()
                .filter(|g| (0.0..size[0]).contains(&g.x) && (0.0..size[1]).contains(&g.y))
                .map(|g| g.shape.length() * g.shape.width())
                .sum();
            let line = format!(
                "| {} | window x {:.1}-{:.1} mm, y {:.1}-{:.1} mm | {} ({} cut) | {:.3} (centres in the window) | {:.2} |",
                source.name(),
                region.x0 * 1e3,
                (region.x0 + region.width) * 1e3,
                region.y0 * 1e3,
                (region.y0 + region.height) * 1e3,
                grains.len(),
                truth.grains.iter().filter(|g| g.cut).count(),
                covered / (size[0] * size[1]),
                start.elapsed().as_secs_f64()
            );
            Ok((grains, line))
        }
        Source::Packing(packing) => {
            let packed = generate(shape, packing, &frame, seed);
            let line = format!(
                "| {} | deepest overlap {:.2} % of D, {:.1} % touching | {} ({} cut) | {:.3} (periodic box, holes counted) | {:.2} |",
                source.name(),
                100.0 * packed.max_overlap,
                100.0 * packed.touching_fraction,
                packed.grains.len(),
                packed.grains.iter().filter(|g| g.is_cut_by(&frame)).count(),
                packed.packing_fraction,
                start.elapsed().as_secs_f64()
            );
            Ok((packed.grains, line))
        }
    }
}

/// Runs the bench.
pub fn run(bench: &VisionBench, progress: &dyn Fn(VisionEvent)) -> anyhow::Result<VisionReport> {
    bench.validate()?;
    let mut photos = Vec::new();
    let mut spent: Vec<Spent> = Vec::new();
    let mut looks = Vec::new();
    let mut refusals = Vec::new();
    let mut sources = String::from(
        "| shape | seed | source | window or packing | grains (cut) | area fraction | seconds |\n|---|---|---|---|---|---|---|\n",
    );
    for (shape_name, shape) in bench.chosen_shapes() {
        for &number in &bench.seeds.0 {
            let seed = bench.split.seed(number).map_err(anyhow::Error::msg)?;
            for source in bench.sources_of(shape_name) {
                progress(VisionEvent::Source {
                    shape: shape_name,
                    source: source.name(),
                    seed: number,
                });
                let [grains_seed, look_seed, photo_seed] = source_seeds(seed, &source);
                let (grains, line) = grains_of(source, shape, bench.frame, grains_seed)?;
                let _ = writeln!(sources, "| {shape_name} | {number} {line}");
                for &look_range in &bench.looks {
                    let look = Look::draw(look_range, look_seed);
                    for &px_per_mm in &bench.px_per_mm {
                        progress(VisionEvent::Photograph {
                            shape: shape_name,
                            source: source.name(),
                            px_per_mm,
                            look: look_range,
                        });
                        let photo = Photo {
                            grains: &grains,
                            frame: Frame {
                                width: bench.frame[0],
                                height: bench.frame[1],
                                scale: px_per_mm * 1e3,
                            },
                            shape,
                            look: &look,
                            seed: photo_seed,
                            shortcuts: bench.shortcuts,
                        };
                        let outcome = run_photo(&photo).map_err(|e| {
                            anyhow::anyhow!(
                                "{shape_name} {} seed {number} of the {} split, {px_per_mm} px/mm, {} look: {e}",
                                source.name(),
                                bench.split.name(),
                                look_range.name()
                            )
                        })?;
                        progress(VisionEvent::Done);
                        if let Some(why) = &outcome.refused {
                            refusals.push(format!(
                                "{shape_name} {} seed {number}, {px_per_mm} px/mm, {}: {why}",
                                source.name(),
                                look_range.name()
                            ));
                        }
                        pool::spend(
                            &mut spent,
                            shape_name,
                            px_per_mm,
                            look_range,
                            &outcome.phases,
                        );
                        photos.push(row_of(
                            source,
                            shape_name,
                            number,
                            px_per_mm,
                            look_range,
                            grains.len(),
                            outcome,
                        ));
                    }
                    looks.push(DrawnLook {
                        seed: number,
                        source: source.name(),
                        shape: shape_name,
                        look_range,
                        look,
                    });
                }
            }
        }
    }
    Ok(VisionReport {
        by_source: pool::pooled(&photos, false),
        by_shape: pool::pooled(&photos, true),
        photos,
        spent,
        looks,
        sources,
        refusals,
    })
}

fn row_of(
    source: Source,
    shape: &'static str,
    seed: u64,
    px_per_mm: f64,
    look: LookRange,
    grains: usize,
    outcome: Outcome,
) -> Row {
    Row {
        source: source.name(),
        fill: source.fill(),
        shape,
        seed: Some(seed),
        px_per_mm,
        look,
        photos: 1,
        tally: outcome.tally,
        orientation_errors_deg: outcome.orientation_errors_deg,
        grains,
        seconds: outcome.detect_seconds,
        render_seconds: outcome.render_seconds,
        peak_memory_bytes: outcome.peak_memory_bytes,
        refused: usize::from(outcome.refused.is_some()),
    }
}
