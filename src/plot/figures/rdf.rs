use std::path::{Path, PathBuf};

use super::{phi0_colour, shape_name, source_and_phi0};
use crate::analysis::summary::Summary;
use crate::plot::chart::{Chart, Kind, Series, write_chart};

/// g(r) per phi0, r in grain widths: `rdf.png/.csv`. Ensembles without g(r) (no grain far
/// enough inside the analysed area) have no curve.
pub fn rdf_figure(out: &Path, summaries: &[&Summary]) -> anyhow::Result<PathBuf> {
    let mut series = Vec::new();
    for s in summaries {
        for e in s.ensembles.iter().filter(|e| !e.rdf.g.is_empty()) {
            series.push(Series {
                label: source_and_phi0(s.source, e.phi0),
                kind: Kind::Measured(s.source),
                colour: phi0_colour(summaries, e.phi0),
                x: e.rdf.r.clone(),
                y: e.rdf.g.clone(),
                err: Some(e.rdf.g_err.clone()),
            });
        }
    }
    let path = out.join("rdf.png");
    write_chart(
        &path,
        &Chart {
            title: format!("Radial distribution function, {}", shape_name(summaries)),
            x_label: "r / D (centre distance in grain widths)".into(),
            y_label: "g(r)".into(),
            x_column: "r_over_D".into(),
            y_column: "g".into(),
            x_range: None,
            series,
        },
    )?;
    Ok(path)
}
