use std::path::{Path, PathBuf};

use super::{phi0_colour, shape_name, source_and_phi0};
use crate::analysis::summary::Summary;
use crate::plot::chart::{Chart, Kind, Series, write_chart};
use crate::plot::palette;

/// f(theta) per phi0, per degree against theta in degrees over the folding period (the
/// analysis keeps radians; one unit in a figure and its table), with the isotropic level
/// 1/period for reference: `orientation.png/.csv`.
pub fn orientation_figure(out: &Path, summaries: &[&Summary]) -> anyhow::Result<PathBuf> {
    let per_degree = 1f64.to_radians();
    let mut series = Vec::new();
    for s in summaries {
        for e in &s.ensembles {
            let o = &e.orientation;
            series.push(Series {
                label: source_and_phi0(s.source, e.phi0),
                kind: Kind::Measured(s.source),
                colour: phi0_colour(summaries, e.phi0),
                x: o.theta.iter().map(|t| t.to_degrees()).collect(),
                y: o.f.iter().map(|f| f * per_degree).collect(),
                err: Some(o.f_err.iter().map(|f| f * per_degree).collect()),
            });
        }
    }
    let period = summaries
        .first()
        .map_or(180.0, |s| s.shape.symmetry_period().to_degrees());
    series.push(Series {
        label: format!("isotropic, 1/{period:.0} per deg"),
        kind: Kind::Model,
        colour: palette(9),
        x: vec![0.0, period],
        y: vec![1.0 / period; 2],
        err: None,
    });
    let path = out.join("orientation.png");
    write_chart(
        &path,
        &Chart {
            title: format!("Orientation distribution f(θ), {}", shape_name(summaries)),
            x_label: format!("θ, long axis from the horizontal (deg, folded to 0-{period:.0})"),
            y_label: "f(θ) (1/deg)".into(),
            x_column: "theta_deg".into(),
            y_column: "f_per_deg".into(),
            x_range: Some((0.0, period)),
            series,
        },
    )?;
    Ok(path)
}
