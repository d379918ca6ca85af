//! Diagnostic: how far one ensemble of simulated deposits lies from another, in units of their
//! standard errors, with the measures of `facets bench fill` (phi_f, f(theta) L1, g(r) L1 for
//! r < 4 D, centre-line pressure profile RMS) and the share of the weight the floor carries
//! (the rest is on the side walls: what a frozen deposit would get wrong first).
//!
//! For deposits deeper than `bench fill`'s 150 grains, e.g. a faster setting at paper scale
//! against the integrated runs of the same scene:
//!
//! cargo run --release --example compare_ensembles -- REF/seed-*/deposit.csv -- CAND/seed-*/deposit.csv

use anyhow::{Context, ensure};
use facets::analysis::stats::MeanErr;
use facets::bench::fill::{MeasureInput, Measures, deviations, scalar};
use facets::deposit::{Ensemble, LoadOptions, Partner, Wall, load_realisation};

fn main() -> anyhow::Result<()> {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let split = args
        .iter()
        .position(|a| a == "--")
        .context("usage: compare_ensembles REF.csv... -- CANDIDATE.csv...")?;
    let (reference, candidate) = (&args[..split], &args[split + 1..]);
    ensure!(
        reference.len() >= 2 && candidate.len() >= 2,
        "each side needs at least two deposits (a standard error)"
    );
    let load = |paths: &[String]| -> anyhow::Result<Ensemble> {
        let realisations = paths
            .iter()
            .map(|p| load_realisation(p.as_ref(), &LoadOptions::default()))
            .collect::<anyhow::Result<Vec<_>>>()?;
        Ensemble::new(realisations)
    };
    let (reference, candidate) = (load(reference)?, load(candidate)?);
    let input = MeasureInput::default();
    let (m_ref, m_cand) = (
        Measures::of(&reference, &input)?,
        Measures::of(&candidate, &input)?,
    );
    let d = deviations(&m_cand, &m_ref);
    let (floor_ref, floor_cand) = (floor_share(&reference)?, floor_share(&candidate)?);
    println!(
        "| measure | reference ({} deposits) | candidate ({}) | deviation (SE) |",
        reference.realisations.len(),
        candidate.realisations.len()
    );
    println!("|---|---|---|---|");
    let show = |m: MeanErr| format!("{:.4} +- {:.4}", m.mean, m.stderr);
    println!(
        "| phi_f | {} | {} | {:.2} |",
        show(m_ref.phi_f),
        show(m_cand.phi_f),
        d.phi_f
    );
    println!("| f(theta), L1 | | | {:.2} |", d.orientation);
    println!("| g(r < 4 D), L1 | | | {:.2} |", d.rdf);
    println!("| pressure profile, RMS | | | {:.2} |", d.pressure);
    println!(
        "| floor / (floor + walls) | {} | {} | {:.2} |",
        show(floor_ref),
        show(floor_cand),
        scalar(floor_cand, floor_ref)
    );
    Ok(())
}

/// Vertical load on the floor over the vertical load on floor and walls, per deposit.
fn floor_share(ensemble: &Ensemble) -> anyhow::Result<MeanErr> {
    let shares = ensemble
        .realisations
        .iter()
        .map(|r| {
            let contacts = r
                .contacts
                .as_ref()
                .with_context(|| format!("{}: no contact table beside it", r.name))?;
            let (mut floor, mut all) = (0.0, 0.0);
            for c in contacts {
                if let Partner::Wall(w) = c.partner {
                    all += c.force[1];
                    if w == Wall::Floor {
                        floor += c.force[1];
                    }
                }
            }
            ensure!(all > 0.0, "{}: nothing rests on the walls", r.name);
            Ok(floor / all)
        })
        .collect::<anyhow::Result<Vec<f64>>>()?;
    Ok(MeanErr::of(&shares))
}
