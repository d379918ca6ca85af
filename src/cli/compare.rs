use std::path::PathBuf;

use anyhow::Context;
use clap::Args as ClapArgs;

use facets::analysis::compare::{compare, write_comparison};
use facets::analysis::tables::read_summary;
use facets::deposit::Source;
use facets::plot::write_figures;

/// Draw experiment and simulation on the same axes, from two `facets analyse` outputs.
///
/// Reads DIR/summary.json of each side (same grain shape) and writes into --out the figures of
/// `facets analyse` (orientation, rdf, g1_vs_phi0, packing_fraction_vs_phi0, pressure_phi0_X,
/// pressure_w_scan_phi0_X: each PNG with its CSV), every one with both sources overlaid:
/// experiment as solid lines with filled circles, simulation as thin lines with open
/// triangles, error bars = standard error over each ensemble; a deposit picture per source and
/// phi0; and comparison.json: for each phi0 both sides have, phi_f, g(1), S4 (and S2 for rods)
/// of each side and their difference in units of the combined standard error (z).
#[derive(Debug, ClapArgs)]
#[command(verbatim_doc_comment)]
pub struct Args {
    /// Output folder of `facets analyse` run on photographs.
    #[arg(long)]
    pub experiment: PathBuf,
    /// Output folder of `facets analyse` run on simulated deposits.
    #[arg(long)]
    pub simulation: PathBuf,
    /// Output folder (created if missing).
    #[arg(long)]
    pub out: PathBuf,
}

pub fn run(args: Args) -> anyhow::Result<()> {
    let experiment = read_summary(&args.experiment, Source::Experiment)?;
    let simulation = read_summary(&args.simulation, Source::Simulation)?;
    let comparison = compare(&experiment, &simulation)?;
    std::fs::create_dir_all(&args.out)
        .with_context(|| format!("cannot create {}", args.out.display()))?;
    write_comparison(&args.out, &comparison)?;
    let figures = write_figures(&args.out, &[&experiment, &simulation])?;
    println!(
        "{} figures and comparison.json in {}",
        figures.len(),
        args.out.display()
    );
    for p in &comparison.per_phi0 {
        let line: Vec<String> = p
            .differences
            .iter()
            .map(|d| match d.z {
                Some(z) => format!("{} z = {z:+.2}", d.observable),
                None => format!("{} (no error)", d.observable),
            })
            .collect();
        println!("  phi0 = {:.3}: {}", p.phi0, line.join(", "));
    }
    Ok(())
}
