use std::path::{Path, PathBuf};

use super::{shape_name, source_name};
use crate::analysis::summary::{EnsembleSummary, Summary};
use crate::deposit::Source;
use crate::plot::chart::{Chart, Kind, Series, write_chart};
use crate::plot::palette;

/// One series per source of a measure (mean, standard error) against phi0.
fn per_source(
    summaries: &[&Summary],
    measure: &dyn Fn(&EnsembleSummary) -> (f64, f64),
) -> Vec<Series> {
    summaries
        .iter()
        .map(|s| {
            let (y, err): (Vec<f64>, Vec<f64>) = s.ensembles.iter().map(measure).unzip();
            Series {
                label: source_name(s.source).into(),
                kind: Kind::Measured(s.source),
                colour: palette(match s.source {
                    Source::Experiment => 0,
                    Source::Simulation => 1,
                }),
                x: s.ensembles.iter().map(|e| e.phi0).collect(),
                y,
                err: Some(err),
            }
        })
        .collect()
}

/// The contact peak g(r = D) against phi0: `g1_vs_phi0.png/.csv`.
pub fn g1_figure(out: &Path, summaries: &[&Summary]) -> anyhow::Result<PathBuf> {
    let path = out.join("g1_vs_phi0.png");
    write_chart(
        &path,
        &Chart {
            title: format!(
                "Contact peak g(r = D) against feed fraction, {}",
                shape_name(summaries)
            ),
            x_label: "feed packing fraction φ₀".into(),
            y_label: "g(1)".into(),
            x_column: "phi0".into(),
            y_column: "g_at_1".into(),
            x_range: None,
            series: per_source(summaries, &|e| (e.rdf.g_at_1.mean, e.rdf.g_at_1.stderr)),
        },
    )?;
    Ok(path)
}

/// The packing fraction of the analysed area against phi0:
/// `packing_fraction_vs_phi0.png/.csv`.
pub fn packing_fraction_figure(out: &Path, summaries: &[&Summary]) -> anyhow::Result<PathBuf> {
    let path = out.join("packing_fraction_vs_phi0.png");
    write_chart(
        &path,
        &Chart {
            title: format!(
                "Packing fraction of the analysed area, {}",
                shape_name(summaries)
            ),
            x_label: "feed packing fraction φ₀".into(),
            y_label: "packing fraction φ_f".into(),
            x_column: "phi0".into(),
            y_column: "phi_f".into(),
            x_range: None,
            series: per_source(summaries, &|e| {
                (e.rdf.packing_fraction.mean, e.rdf.packing_fraction.stderr)
            }),
        },
    )?;
    Ok(path)
}
