use std::path::PathBuf;

use clap::Args as ClapArgs;
use clap::builder::{PossibleValue, PossibleValuesParser};

use facets::bench::fill::{
    self, BenchConfig, MeasureInput, ReferenceScene, SCENES, SETTINGS, Setting,
};

use crate::cli::progress::bar;

/// Speed against error of the filling's settings: every setting fills the reference scenes
/// with the same seeds as the paper-faithful one, and each observable's deviation from the
/// faithful ensemble is given in standard errors (formulas: module facets::bench::fill).
///
/// Scenes: the small scenes of data-samples/scenes/ (160 mm silo), grain count set by --grains.
/// Settings: see --settings (faithful, the reference, is always run).
///
/// Writes into --out: fill.csv, fill.md (the table of docs/results/speed-vs-error.md), speed_vs_error.png, report.json
/// (every measure with its standard errors), and the runs in runs/SCENE/SETTING/seed-N/.
/// Seeds run in parallel (RAYON_NUM_THREADS sets the threads); the deposits and deviations do
/// not depend on it, the times do.
#[derive(Debug, ClapArgs)]
#[command(verbatim_doc_comment)]
pub struct Args {
    /// Grains per run.
    #[arg(long, default_value_t = 150)]
    pub grains: usize,
    /// Seeds (realisations) per scene and setting; at least 2.
    #[arg(long, default_value_t = 8)]
    pub seeds: u64,
    /// First seed; the runs use seed, seed + 1, ...
    #[arg(long, default_value_t = 1)]
    pub first_seed: u64,
    /// Settings to compare, by name (faithful is added when missing).
    #[arg(long, value_delimiter = ',', default_values = SETTINGS.map(|s| s.name),
          value_parser = setting_names())]
    pub settings: Vec<String>,
    /// Reference scenes, by name.
    #[arg(long, value_delimiter = ',', default_values = SCENES.map(|s| s.name),
          value_parser = scene_names())]
    pub scenes: Vec<String>,
    /// Simulated time allowed for relaxation after the last grain (s); runs that do not relax
    /// in it are counted in the table.
    #[arg(long, default_value_t = 1.0)]
    pub max_relaxation_s: f64,
    /// Margin of the g(r) centres inside the analysed area, in grain widths D (the small
    /// scenes' analysed strip is 16 mm wide: the analysis's 4 D would leave no centre).
    #[arg(long, default_value_t = 0.0)]
    pub rdf_margin: f64,
    /// Output folder.
    #[arg(long, default_value = "bench-fill")]
    pub out: PathBuf,
    /// Keep the groups (scene x setting) already in --out that were run by the same version
    /// of facets from the same scene and seeds, with their recorded times, instead of running
    /// them again: adding a setting to a finished bench then costs only its own runs. Only
    /// valid while the engine has not changed since those runs.
    #[arg(long)]
    pub reuse: bool,
}

/// The names of the settings table, each with its description (shown by --help).
fn setting_names() -> PossibleValuesParser {
    PossibleValuesParser::new(
        SETTINGS
            .iter()
            .map(|s| PossibleValue::new(s.name).help(s.what)),
    )
}

fn scene_names() -> PossibleValuesParser {
    PossibleValuesParser::new(
        SCENES
            .iter()
            .map(|s| PossibleValue::new(s.name).help(s.file)),
    )
}

pub fn run(args: Args) -> anyhow::Result<()> {
    let settings = args
        .settings
        .iter()
        .map(|s| Setting::by_name(s))
        .collect::<anyhow::Result<Vec<_>>>()?;
    let scenes = args
        .scenes
        .iter()
        .map(|s| ReferenceScene::by_name(s))
        .collect::<anyhow::Result<Vec<_>>>()?;
    let config = BenchConfig {
        scenes,
        settings,
        grains: args.grains,
        seeds: args.seeds,
        first_seed: args.first_seed,
        max_relaxation_time_s: args.max_relaxation_s,
        measure: MeasureInput {
            rdf_margin_d: args.rdf_margin,
            ..MeasureInput::default()
        },
        out: args.out.clone(),
        reuse: args.reuse,
    };
    let runs = fill::total_runs(&config);
    let progress = bar(runs, "runs");
    let report = fill::run_bench(&config, &|scene, setting, seed| {
        progress.set_message(format!("{scene} {setting} {seed}"));
        progress.inc(1);
    })?;
    progress.finish_and_clear();
    let written = fill::write_all(&args.out, &report)?;
    print!("{}", std::fs::read_to_string(args.out.join("fill.md"))?);
    for path in written {
        println!("wrote {}", path.display());
    }
    Ok(())
}
