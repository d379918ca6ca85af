//! The figures of one analysis (one source) or of a comparison (experiment beside simulation):
//! the same functions draw both, one series per (source, phi0). One function per figure.

mod against_phi0;
mod deposit;
mod orientation;
mod pressure;
mod rdf;

use std::path::{Path, PathBuf};

use plotters::style::RGBColor;

pub use against_phi0::{g1_figure, packing_fraction_figure};
pub use deposit::deposit_figure;
pub use orientation::orientation_figure;
pub use pressure::{pressure_figure, pressure_w_scan_figure};
pub use rdf::rdf_figure;

use super::chart::palette;
use crate::analysis::summary::{EnsembleSummary, Summary};
use crate::deposit::Source;

/// Writes every figure (PNG + CSV) into `out`; returns the PNG paths.
pub fn write_figures(out: &Path, summaries: &[&Summary]) -> anyhow::Result<Vec<PathBuf>> {
    let mut written = vec![
        orientation_figure(out, summaries)?,
        rdf_figure(out, summaries)?,
        g1_figure(out, summaries)?,
        packing_fraction_figure(out, summaries)?,
    ];
    for phi0 in phi0_values(summaries) {
        written.extend(pressure_w_scan_figure(out, summaries, phi0)?);
        written.extend(pressure_figure(out, summaries, phi0)?);
        for (source, e) in at_phi0(summaries, phi0) {
            written.push(deposit_figure(out, source, e)?);
        }
    }
    Ok(written)
}

/// How file names and legends name a source.
fn source_name(s: Source) -> &'static str {
    match s {
        Source::Experiment => "exp",
        Source::Simulation => "sim",
    }
}

/// All phi0 values across the summaries, ascending: a phi0 keeps its colour in every figure.
fn phi0_values(summaries: &[&Summary]) -> Vec<f64> {
    let mut v: Vec<f64> = summaries
        .iter()
        .flat_map(|s| s.ensembles.iter().map(|e| e.phi0))
        .collect();
    v.sort_by(f64::total_cmp);
    v.dedup_by(|a, b| (*a - *b).abs() < 1e-9);
    v
}

fn same_phi0(a: f64, b: f64) -> bool {
    (a - b).abs() < 1e-9
}

/// The colour of a phi0 among all of the figures' phi0 values.
fn phi0_colour(summaries: &[&Summary], phi0: f64) -> RGBColor {
    palette(
        phi0_values(summaries)
            .iter()
            .position(|&p| same_phi0(p, phi0))
            .unwrap_or(0),
    )
}

/// The ensembles at this phi0, one per source.
fn at_phi0<'a>(summaries: &[&'a Summary], phi0: f64) -> Vec<(Source, &'a EnsembleSummary)> {
    summaries
        .iter()
        .filter_map(|s| {
            s.ensembles
                .iter()
                .find(|e| same_phi0(e.phi0, phi0))
                .map(|e| (s.source, e))
        })
        .collect()
}

/// The grains' name for titles ("squares", ...).
fn shape_name(summaries: &[&Summary]) -> &'static str {
    summaries
        .first()
        .map_or("grains", |s| s.shape.display_name())
}

/// `phi0_0.250`: how file names tag a phi0.
fn tag(phi0: f64) -> String {
    format!("phi0_{phi0:.3}")
}

/// A series' legend text: its source and phi0.
fn source_and_phi0(source: Source, phi0: f64) -> String {
    format!("{} φ₀ = {phi0:.3}", source_name(source))
}
