use std::path::PathBuf;

use clap::Args as ClapArgs;

use facets::reproduce::{Plan, reproduce};

/// Reproduce the whole study: simulations, stand-in photographs, detection, analysis, figures
/// and a report.
///
/// For each shape (squares, rods 5/3, rods 3) and phi0 of the plan: an ensemble of silo
/// fillings (simulation side); photographs of the analysed frame (region E at paper scale,
/// full width) rendered from other fillings, with other seeds (the stand-in experiment);
/// detection; the same analysis on both sides; the figures with both sides on the same axes;
/// and OUT/report.md: per shape and phi0, phi_f, g(1), the peak angle of f(theta), S2/S4,
/// lambda/W, P_sat and the detector's accuracy on these photographs, figures embedded.
///
/// A stopped run continues where it stopped: fillings, photographs and detector tables that
/// exist are not made again (a filling is done when its run.json says the same scene and seed).
#[derive(Debug, ClapArgs)]
#[command(verbatim_doc_comment)]
pub struct Args {
    /// Small silos and ensembles on built-in defaults (the default): minutes on 2 cores.
    #[arg(long, conflicts_with_all = ["paper", "tiny", "plan"])]
    pub quick: bool,
    /// Paper-scale ensembles (256 mm silo; 3000 squares, 9000 short rods, 5000 long rods;
    /// 8 realisations a side): hours. Stop and restart at will.
    #[arg(long, conflicts_with_all = ["tiny", "plan"])]
    pub paper: bool,
    /// The end-to-end test's configuration (a 120 mm silo, tens of grains).
    #[arg(long, hide = true, conflicts_with = "plan")]
    pub tiny: bool,
    /// A plan of your own: the plan.json an earlier run wrote, edited (silo width, grain
    /// counts, phi0 values, realisations, photograph scale and style, g(r) margin, w scan).
    #[arg(long, value_name = "FILE")]
    pub plan: Option<PathBuf>,
    /// Real photographs as the experiment side: a folder with manifest.csv (columns
    /// file,shape,phi0,px_per_mm[,silo_width_mm,frame_y_mm]) or manifest.toml ([[photo]]
    /// tables with the same keys). shape: square, rod53 or rod3; frame_y_mm: height of the
    /// photograph's bottom edge above the floor (default 290, region E); silo_width_mm default
    /// 258. A NAME.truth.csv beside a photograph lets the report score the detector on it.
    #[arg(long, value_name = "DIR")]
    pub photos: Option<PathBuf>,
    /// Output folder (created if missing); report.md is written at its top.
    #[arg(long, default_value = "reproduce-out")]
    pub out: PathBuf,
}

pub fn run(args: Args) -> anyhow::Result<()> {
    let plan = if let Some(path) = &args.plan {
        Plan::load(path)?
    } else if args.paper {
        Plan::paper()
    } else if args.tiny {
        Plan::tiny()
    } else {
        Plan::quick()
    };
    let report = reproduce(&plan, args.photos.as_deref(), &args.out)?;
    for t in &report.stages {
        println!("{:>10}: {:.1} s", t.stage, t.seconds);
    }
    if !report.unrelaxed.is_empty() {
        eprintln!(
            "warning: {} fillings did not relax in time (listed in the report)",
            report.unrelaxed.len()
        );
    }
    println!("report: {}", args.out.join("report.md").display());
    Ok(())
}
