use std::path::{Path, PathBuf};

use super::{at_phi0, source_name, tag};
use crate::analysis::pressure::{JANSSEN_LAMBDA_MAX_OVER_W, PressureProfile};
use crate::analysis::summary::Summary;
use crate::deposit::Source;
use crate::plot::chart::{Chart, Kind, Series, write_chart};
use crate::plot::palette;

/// -sigma_yy on the centre line against depth for each coarse-graining width of the scan:
/// `pressure_w_scan_phi0_X.png/.csv`; None when no ensemble at phi0 has contact forces.
pub fn pressure_w_scan_figure(
    out: &Path,
    summaries: &[&Summary],
    phi0: f64,
) -> anyhow::Result<Option<PathBuf>> {
    let mut series = Vec::new();
    for (source, e) in at_phi0(summaries, phi0) {
        for (k, p) in e.w_scan.iter().enumerate() {
            series.push(Series {
                label: format!("{} w = {:.1} D", source_name(source), p.w / e.grain_width),
                kind: Kind::Measured(source),
                colour: palette(k),
                x: p.h_over_w.clone(),
                y: p.sigma_yy.iter().map(|s| -s).collect(),
                err: Some(p.sigma_yy_err.clone()),
            });
        }
    }
    if series.is_empty() {
        return Ok(None);
    }
    let path = out.join(format!("pressure_w_scan_{}.png", tag(phi0)));
    write_chart(
        &path,
        &Chart {
            title: format!("−σ_yy on the centre line, φ₀ = {phi0:.3}, coarse-graining width w"),
            x_label: "depth below the free surface h / W".into(),
            y_label: "−σ_yy (N/m, compressive positive)".into(),
            x_column: "h_over_W".into(),
            y_column: "minus_sigma_yy_N_per_m".into(),
            x_range: None,
            series,
        },
    )?;
    Ok(Some(path))
}

/// The stresses on the centre line against depth with the overburden (grains filling the
/// column, and at the measured packing fraction) and the Janssen fit:
/// `pressure_phi0_X.png/.csv`; None when no ensemble at phi0 has contact forces.
pub fn pressure_figure(
    out: &Path,
    summaries: &[&Summary],
    phi0: f64,
) -> anyhow::Result<Option<PathBuf>> {
    let mut series = Vec::new();
    for (source, e) in at_phi0(summaries, phi0) {
        let Some(p) = &e.pressure else { continue };
        series.extend(stress_series(source, p));
    }
    if series.is_empty() {
        return Ok(None);
    }
    let path = out.join(format!("pressure_{}.png", tag(phi0)));
    write_chart(
        &path,
        &Chart {
            title: format!("Stress on the centre line, φ₀ = {phi0:.3}"),
            x_label: "depth below the free surface h / W".into(),
            y_label: "stress (N/m, compressive positive)".into(),
            x_column: "h_over_W".into(),
            y_column: "N_per_m".into(),
            x_range: None,
            series,
        },
    )?;
    Ok(Some(path))
}

fn stress_series(source: Source, p: &PressureProfile) -> Vec<Series> {
    let src = source_name(source);
    let neg = |v: &[f64]| v.iter().map(|s| -s).collect::<Vec<_>>();
    let measured = |label: String, colour: usize, y: Vec<f64>, err: Vec<f64>| Series {
        label,
        kind: Kind::Measured(source),
        colour: palette(colour),
        x: p.h_over_w.clone(),
        y,
        err: Some(err),
    };
    let model = |label: String, colour: usize, y: Vec<f64>| Series {
        label,
        kind: Kind::Model,
        colour: palette(colour),
        x: p.h_over_w.clone(),
        y,
        err: None,
    };
    let mut series = vec![
        measured(
            format!("{src} −σ_yy"),
            0,
            neg(&p.sigma_yy),
            p.sigma_yy_err.clone(),
        ),
        measured(
            format!("{src} −σ_xx"),
            1,
            neg(&p.sigma_xx),
            p.sigma_xx_err.clone(),
        ),
        measured(
            format!("{src} −trace/2"),
            4,
            p.trace.iter().map(|t| -0.5 * t).collect(),
            p.trace_err.iter().map(|t| 0.5 * t).collect(),
        ),
        model(format!("{src} ρ g h (φ = 1)"), 2, p.overburden_full.clone()),
        model(
            format!("{src} φ_f ρ g h (φ_f = {:.3})", p.phi_f.mean),
            3,
            p.overburden_measured.clone(),
        ),
    ];
    if let Some(j) = &p.janssen {
        let label = if j.saturates() {
            format!(
                "{src} Janssen λ/W = {:.2}, P_sat = {:.3} N/m",
                j.lambda_over_w, j.p_sat
            )
        } else {
            format!(
                "{src} Janssen: not saturated in this depth (λ/W >= {JANSSEN_LAMBDA_MAX_OVER_W})"
            )
        };
        series.push(model(
            label,
            5,
            p.h_over_w
                .iter()
                .map(|h| j.p_sat * (1.0 - (-h / j.lambda_over_w).exp()))
                .collect(),
        ));
    }
    series
}
