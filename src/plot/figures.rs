//! The figures of one analysis (one source) or of a comparison (experiment beside simulation):
//! the same functions draw both, one series per (source, phi0).

use std::path::{Path, PathBuf};

use super::chart::{Chart, Kind, Series, write_chart};
use super::deposit_picture::draw_deposit;
use crate::analysis::summary::{EnsembleSummary, Summary};
use crate::deposit::{LoadOptions, Source, load_realisation};

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

fn colour_of(phi0s: &[f64], phi0: f64) -> usize {
    phi0s
        .iter()
        .position(|p| (p - phi0).abs() < 1e-9)
        .unwrap_or(0)
}

fn tag(phi0: f64) -> String {
    format!("phi0_{phi0:.3}")
}

/// Writes every figure (PNG + CSV) into `out`; returns the PNG paths.
pub fn write_figures(out: &Path, summaries: &[&Summary]) -> anyhow::Result<Vec<PathBuf>> {
    let phi0s = phi0_values(summaries);
    let mut written = Vec::new();
    let emit = |written: &mut Vec<PathBuf>, name: String, chart: Chart| -> anyhow::Result<()> {
        let path = out.join(name);
        write_chart(&path, &chart)?;
        written.push(path);
        Ok(())
    };
    let shape = summaries.first().map_or("grains", |s| s.shape.name());

    // f(theta) per phi0.
    let mut series = Vec::new();
    for s in summaries {
        for e in &s.ensembles {
            let o = &e.orientation;
            series.push(Series {
                label: format!("{} phi0 = {:.3}", source_name(s.source), e.phi0),
                kind: Kind::Measured(s.source),
                colour: colour_of(&phi0s, e.phi0),
                x: o.theta.iter().map(|t| t.to_degrees()).collect(),
                y: o.f.clone(),
                err: Some(o.f_err.clone()),
            });
        }
    }
    emit(
        &mut written,
        "orientation.png".into(),
        Chart {
            title: format!("Orientation distribution, {shape}"),
            x_label: "theta (degrees, folded)".into(),
            y_label: "f(theta) (1/rad)".into(),
            x_column: "theta_deg".into(),
            y_column: "f_per_rad".into(),
            series,
        },
    )?;

    // g(r) per phi0.
    let mut series = Vec::new();
    for s in summaries {
        for e in s.ensembles.iter().filter(|e| !e.rdf.g.is_empty()) {
            series.push(Series {
                label: format!("{} phi0 = {:.3}", source_name(s.source), e.phi0),
                kind: Kind::Measured(s.source),
                colour: colour_of(&phi0s, e.phi0),
                x: e.rdf.r.clone(),
                y: e.rdf.g.clone(),
                err: Some(e.rdf.g_err.clone()),
            });
        }
    }
    emit(
        &mut written,
        "rdf.png".into(),
        Chart {
            title: format!("Radial distribution function, {shape}"),
            x_label: "r / D".into(),
            y_label: "g(r)".into(),
            x_column: "r_over_D".into(),
            y_column: "g".into(),
            series,
        },
    )?;

    // g(1) and phi_f against phi0.
    let per_source = |f: &dyn Fn(&EnsembleSummary) -> (f64, f64)| -> Vec<Series> {
        summaries
            .iter()
            .enumerate()
            .map(|(k, s)| {
                let (y, err): (Vec<f64>, Vec<f64>) = s.ensembles.iter().map(f).unzip();
                Series {
                    label: source_name(s.source).into(),
                    kind: Kind::Measured(s.source),
                    colour: k,
                    x: s.ensembles.iter().map(|e| e.phi0).collect(),
                    y,
                    err: Some(err),
                }
            })
            .collect()
    };
    emit(
        &mut written,
        "g1_vs_phi0.png".into(),
        Chart {
            title: format!("Contact peak g(r = D) against feed fraction, {shape}"),
            x_label: "phi0".into(),
            y_label: "g(1)".into(),
            x_column: "phi0".into(),
            y_column: "g_at_1".into(),
            series: per_source(&|e| (e.rdf.g_at_1.mean, e.rdf.g_at_1.stderr)),
        },
    )?;
    emit(
        &mut written,
        "packing_fraction_vs_phi0.png".into(),
        Chart {
            title: format!("Packing fraction of the analysed area, {shape}"),
            x_label: "phi0".into(),
            y_label: "phi_f".into(),
            x_column: "phi0".into(),
            y_column: "phi_f".into(),
            series: per_source(&|e| (e.rdf.packing_fraction.mean, e.rdf.packing_fraction.stderr)),
        },
    )?;

    for &phi0 in &phi0s {
        let at: Vec<(Source, &EnsembleSummary)> = summaries
            .iter()
            .filter_map(|s| {
                s.ensembles
                    .iter()
                    .find(|e| (e.phi0 - phi0).abs() < 1e-9)
                    .map(|e| (s.source, e))
            })
            .collect();
        // Pressure for several w.
        let mut series = Vec::new();
        for (source, e) in &at {
            for (k, p) in e.w_scan.iter().enumerate() {
                series.push(Series {
                    label: format!("{} w = {:.1} D", source_name(*source), p.w / e.grain_width),
                    kind: Kind::Measured(*source),
                    colour: k,
                    x: p.h_over_w.clone(),
                    y: p.sigma_yy.iter().map(|s| -s).collect(),
                    err: Some(p.sigma_yy_err.clone()),
                });
            }
        }
        if !series.is_empty() {
            emit(
                &mut written,
                format!("pressure_w_scan_{}.png", tag(phi0)),
                Chart {
                    title: format!("-sigma_yy on the centre line, phi0 = {phi0:.3}, scan over w"),
                    x_label: "h / W".into(),
                    y_label: "-sigma_yy (N/m)".into(),
                    x_column: "h_over_W".into(),
                    y_column: "minus_sigma_yy_N_per_m".into(),
                    series,
                },
            )?;
        }
        // Pressure with overburden and Janssen fit.
        let mut series = Vec::new();
        for (source, e) in &at {
            let Some(p) = &e.pressure else { continue };
            let src = source_name(*source);
            let neg = |v: &[f64]| v.iter().map(|s| -s).collect::<Vec<_>>();
            series.push(Series {
                label: format!("{src} -sigma_yy"),
                kind: Kind::Measured(*source),
                colour: 0,
                x: p.h_over_w.clone(),
                y: neg(&p.sigma_yy),
                err: Some(p.sigma_yy_err.clone()),
            });
            series.push(Series {
                label: format!("{src} -sigma_xx"),
                kind: Kind::Measured(*source),
                colour: 1,
                x: p.h_over_w.clone(),
                y: neg(&p.sigma_xx),
                err: Some(p.sigma_xx_err.clone()),
            });
            series.push(Series {
                label: format!("{src} -trace/2"),
                kind: Kind::Measured(*source),
                colour: 4,
                x: p.h_over_w.clone(),
                y: p.trace.iter().map(|t| -0.5 * t).collect(),
                err: Some(p.trace_err.iter().map(|t| 0.5 * t).collect()),
            });
            series.push(Series {
                label: format!("{src} rho g h (phi = 1)"),
                kind: Kind::Model,
                colour: 2,
                x: p.h_over_w.clone(),
                y: p.overburden_full.clone(),
                err: None,
            });
            series.push(Series {
                label: format!("{src} phi_f rho g h (phi_f = {:.3})", p.phi_f.mean),
                kind: Kind::Model,
                colour: 3,
                x: p.h_over_w.clone(),
                y: p.overburden_measured.clone(),
                err: None,
            });
            if let Some(j) = &p.janssen {
                series.push(Series {
                    label: if j.saturates() {
                        format!(
                            "{src} Janssen lambda/W = {:.2}, P_sat = {:.3} N/m",
                            j.lambda_over_w, j.p_sat
                        )
                    } else {
                        format!(
                            "{src} Janssen: not saturated in this depth (lambda/W >= {})",
                            crate::analysis::pressure::JANSSEN_LAMBDA_MAX_OVER_W
                        )
                    },
                    kind: Kind::Model,
                    colour: 5,
                    x: p.h_over_w.clone(),
                    y: p.h_over_w
                        .iter()
                        .map(|h| j.p_sat * (1.0 - (-h / j.lambda_over_w).exp()))
                        .collect(),
                    err: None,
                });
            }
        }
        if !series.is_empty() {
            emit(
                &mut written,
                format!("pressure_{}.png", tag(phi0)),
                Chart {
                    title: format!("Stress on the centre line, phi0 = {phi0:.3}"),
                    x_label: "h / W".into(),
                    y_label: "stress (N/m, compressive positive)".into(),
                    x_column: "h_over_W".into(),
                    y_column: "N_per_m".into(),
                    series,
                },
            )?;
        }
        // The deposit pictures, one per source.
        for (source, e) in &at {
            let path = out.join(format!(
                "deposit_{}_{}.png",
                source_name(*source),
                tag(phi0)
            ));
            draw_example(&path, e)?;
            written.push(path);
        }
    }
    Ok(written)
}

fn draw_example(path: &Path, e: &EnsembleSummary) -> anyhow::Result<()> {
    let options = LoadOptions {
        fallback_meta: Some(e.example_meta.clone()),
        contacts: e.example_contacts.as_ref().map(PathBuf::from),
    };
    let real = load_realisation(Path::new(&e.example_deposit), &options)?;
    draw_deposit(path, &real)
}
