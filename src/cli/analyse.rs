use std::path::PathBuf;

use anyhow::Context;
use clap::Args as ClapArgs;

use facets::analysis::summary::AnalysisParameters;
use facets::analysis::tables::{Step, Tables, analyse_tables, write_summary};
use facets::deposit::{DepositMeta, FrameMm, Source, deposit_tables};
use facets::plot::write_figures;

use super::progress::bar;

/// Measure deposits (photographs or simulations) with the shared analysis and draw the figures.
///
/// Each deposit table NAME.csv may have sidecars beside it: NAME.meta.json (silo width, phi0,
/// frame, source; see the deposit module docs) and NAME.contacts.csv (simulated contact forces,
/// needed for the stress and pressure measures). Deposits are grouped by phi0 into ensembles;
/// all must hold one grain shape.
///
/// Writes into --out:
///   summary.json                    every result (read back by `facets compare`)
///   orientation.png/.csv            f(theta) per phi0 in 1/deg against theta in degrees over
///                                   the folding range, ensemble mean +- standard error
///   rdf.png/.csv                    g(r) per phi0 (r in grain widths D, dr = 0.1 D)
///   g1_vs_phi0.png/.csv             g(r = D) against phi0
///   packing_fraction_vs_phi0.png/.csv   phi_f of the analysed area against phi0
///   pressure_phi0_X.png/.csv        -sigma_yy, -sigma_xx, -trace/2 on the centre line against
///                                   h/W with the overburden (phi = 1 and phi_f) and the Janssen
///                                   fit (simulated deposits only)
///   pressure_w_scan_phi0_X.png/.csv -sigma_yy for each coarse-graining width of the scan
///   deposit_SRC_phi0_X.png          the first deposit of each ensemble, grains coloured by
///                                   orientation (colour key in degrees), outlined, force chains
///                                   with width proportional to force (key in N);
///                                   .csv = force chains, .grains.csv = grains
/// Chart CSVs have one row per point: series,<x>,<y>,stderr. Stresses are in N/m (2D); divide by
/// the plate gap for Pa.
#[derive(Debug, ClapArgs)]
#[command(verbatim_doc_comment)]
pub struct Args {
    /// Deposit tables (CSV), or folders: a folder gives its *.csv deposit tables (files named
    /// *.contacts.csv and *.grains.csv are sidecars, not deposits) and those of its seed-N/
    /// folders (an ensemble as `facets sim --realisations` writes it).
    #[arg(required = true)]
    pub deposits: Vec<PathBuf>,
    /// Contact tables, one per deposit in the same order (default: NAME.contacts.csv when it
    /// exists).
    #[arg(long, num_args = 1..)]
    pub contacts: Vec<PathBuf>,
    /// Output folder (created if missing).
    #[arg(long)]
    pub out: PathBuf,
    /// phi0 of deposits without a NAME.meta.json sidecar.
    #[arg(long)]
    pub phi0: Option<f64>,
    /// Silo width W (mm) of deposits without a sidecar.
    #[arg(long)]
    pub silo_width_mm: Option<f64>,
    /// Frame of deposits without a sidecar: x_min,x_max,y_min,y_max in mm, x from the left
    /// wall, y from the floor (as every command's --frame-mm). Default: the whole width, floor
    /// to the top grain.
    #[arg(long, value_name = "X_MIN,X_MAX,Y_MIN,Y_MAX", value_parser = FrameMm::parse, allow_hyphen_values = true)]
    pub frame_mm: Option<FrameMm>,
    /// Source of deposits without a sidecar.
    #[arg(long, value_enum, default_value = "experiment")]
    pub source: SourceArg,
    /// Coarse-graining width w in grain widths D (default: 4 for squares, 3 for rods, as the
    /// paper).
    #[arg(long)]
    pub w_over_d: Option<f64>,
    /// Widths of the scan over w, in D.
    #[arg(long, value_delimiter = ',', default_value = "1,2,3,4,6")]
    pub w_scan: Vec<f64>,
    /// Kernel cut-off in multiples of w (relative error at most exp(-cutoff^2)).
    #[arg(long, default_value_t = facets::analysis::coarse_grain::DEFAULT_CUTOFF)]
    pub cutoff: f64,
}

#[derive(Debug, Clone, Copy, clap::ValueEnum)]
pub enum SourceArg {
    Experiment,
    Simulation,
}

pub fn run(args: Args) -> anyhow::Result<()> {
    let parameters = AnalysisParameters {
        w_over_d: args.w_over_d,
        w_scan_over_d: args.w_scan.clone(),
        cutoff: args.cutoff,
        ..AnalysisParameters::default()
    };
    parameters.validate()?;
    let source = match args.source {
        SourceArg::Experiment => Source::Experiment,
        SourceArg::Simulation => Source::Simulation,
    };
    let input = Tables {
        tables: deposit_tables(&args.deposits)?,
        contacts: args.contacts.clone(),
        fallback_meta: DepositMeta::from_options(
            args.phi0,
            args.silo_width_mm,
            args.frame_mm,
            source,
        )?,
    };
    std::fs::create_dir_all(&args.out)
        .with_context(|| format!("cannot create {}", args.out.display()))?;

    let loading = bar(input.tables.len(), "loading");
    let analysing = std::cell::OnceCell::new();
    let summary = analyse_tables(&input, &parameters, &|step| match step {
        Step::Loaded { done, .. } => loading.set_position(done as u64),
        Step::Analysed { done, total } => {
            let analysed = analysing.get_or_init(|| {
                loading.finish_and_clear();
                bar(total, "analysing")
            });
            analysed.set_position(done as u64);
        }
    })?;
    loading.finish_and_clear();
    if let Some(analysed) = analysing.get() {
        analysed.finish_and_clear();
    }

    write_summary(&args.out, &summary)?;
    let figures = write_figures(&args.out, &[&summary])?;
    println!(
        "{} deposits of {} in {} ensembles; summary.json and {} figures in {}",
        input.tables.len(),
        summary.shape.display_name(),
        summary.ensembles.len(),
        figures.len(),
        args.out.display()
    );
    let margin = summary.parameters.rdf.margin;
    for e in &summary.ensembles {
        let g1 = if e.rdf.n_used == 0 {
            eprintln!(
                "warning: phi0 = {:.3}: in none of its {} deposits does a grain lie {margin} D \
                 ({:.1} mm) inside the analysed area (the frame less {:.0} mm at each side wall), \
                 so g(r) and g(1) cannot be measured (rdf.png and rdf.csv have no curve for it): \
                 the area must be wider and taller than {:.1} mm (a silo of 160 mm or more leaves \
                 an 80 mm wide strip)",
                e.phi0,
                e.n_realisations,
                margin * e.grain_width * 1e3,
                facets::deposit::WALL_MARGIN * 1e3,
                2.0 * margin * e.grain_width * 1e3,
            );
            format!("n/a (no grain {margin} D from the analysed area's edges)")
        } else {
            format!("{:.2} +- {:.2}", e.rdf.g_at_1.mean, e.rdf.g_at_1.stderr)
        };
        let j = e.pressure.as_ref().and_then(|p| p.janssen);
        println!(
            "  phi0 = {:.3}: {} deposits, phi_f = {:.3} +- {:.3}, g(1) = {g1}, S4 = {:.3}{}",
            e.phi0,
            e.n_realisations,
            e.rdf.packing_fraction.mean,
            e.rdf.packing_fraction.stderr,
            e.orientation.s4.mean,
            match j {
                Some(j) if j.saturates() => format!(
                    ", Janssen lambda/W = {:.3}, P_sat = {:.4} N/m",
                    j.lambda_over_w, j.p_sat
                ),
                Some(_) => format!(
                    ", Janssen: not saturated in this depth (lambda/W >= {})",
                    facets::analysis::pressure::JANSSEN_LAMBDA_MAX_OVER_W
                ),
                None => String::new(),
            }
        );
    }
    Ok(())
}
