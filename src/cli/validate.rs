use std::path::PathBuf;

use clap::Args as ClapArgs;
use indicatif::MultiProgress;

use facets::validate::{Options, Progress, validate};

/// Run a study's cases as ensembles and judge them against the study's findings F1-F5.
///
/// The study file (TOML) lists `[[case]]` entries: `name`, `scene` (relative to the study
/// file), `seeds` (a count from the scene's run.seed, or a list), and optionally
/// `[case.overrides]` (merged into the scene: `[case.overrides.contact] friction = 0.6`),
/// `group` and `baseline` (a variant reported beside its baseline case). Without --study:
/// the built-in data-samples/studies/paper.toml (the paper-scale cases; hours of CPU).
///
/// Every seed not yet done is filled, in parallel, into OUT/CASE/seed-N/ (the files of
/// `facets sim`, and scene.toml); seeds done are not run again, a checkpoint.bin is
/// continued. Ctrl-C stops the runs with checkpoints (exit status 130); the same command
/// resumes them. Then every seed is measured: OUT/results.csv and OUT/results.json (one row
/// per case and seed), and the report (--report) with its figures in REPORT-STEM-figures/.
#[derive(Debug, ClapArgs)]
#[command(verbatim_doc_comment)]
pub struct Args {
    /// Study file (TOML); default: the built-in paper study.
    #[arg(long)]
    pub study: Option<PathBuf>,
    /// Folder of the runs and the raw results.
    #[arg(long, default_value = "runs/validate")]
    pub out: PathBuf,
    /// The report (markdown).
    #[arg(long, default_value = "docs/validation.md")]
    pub report: PathBuf,
    /// Run nothing: measure the runs that exist and write the results and the report.
    #[arg(long)]
    pub report_only: bool,
}

pub fn run(args: Args) -> anyhow::Result<()> {
    let options = Options {
        study: args.study,
        out: args.out,
        report: args.report,
        report_only: args.report_only,
    };
    if !options.report_only {
        super::progress::stop_fillings_on_ctrl_c()?;
    }
    let bars = MultiProgress::new();
    let fillings = super::progress::FillingBars::new(&bars, 24, false);
    let measuring = bars.add(super::progress::bar(0, "measuring"));
    let progress = |p: Progress| match p {
        Progress::Run(job, event) => {
            fillings.show(&format!("{} seed {}", job.case_name, job.seed), event)
        }
        Progress::Measured { done, total } => {
            measuring.set_length(total as u64);
            measuring.set_position(done as u64);
        }
    };
    let outcome = validate(&options, Some(&super::progress::INTERRUPT), &progress)?;
    measuring.finish_and_clear();
    let runs = &outcome.runs;
    if !runs.stopped.is_empty() {
        let files: Vec<String> = runs
            .stopped
            .iter()
            .map(|p| p.display().to_string())
            .collect();
        eprintln!(
            "interrupted; checkpoints {}\nthe same command resumes them",
            files.join(" ")
        );
        std::process::exit(130);
    }
    println!(
        "{} seeds run, {} found done; {} of {} realisations measured; results in {}",
        runs.ran,
        runs.reused,
        outcome.measured,
        outcome.asked,
        options.out.display()
    );
    for (case, seed) in &runs.unrelaxed {
        eprintln!("warning: case `{case}` seed {seed} did not relax within its scene's time");
    }
    if let Some(report) = &outcome.report {
        let verdicts: Vec<String> = outcome
            .verdicts
            .iter()
            .map(|(id, v)| format!("{id} {}", v.text()))
            .collect();
        println!("report {}: {}", report.display(), verdicts.join(", "));
    }
    Ok(())
}
