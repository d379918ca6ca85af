//! The report's figures, one function each: the centre-line pressure over the overburden
//! against depth per case (a panel per shape), and the shares of the deposit's weight per
//! case. The study holds
//! simulations only, so every series is simulated.

use std::path::{Path, PathBuf};

use plotters::style::colors::BLACK;

use super::measures::{PROFILE_STEP_OVER_W, Q};
use super::results::CaseStats;
use super::study::Study;
use crate::deposit::Source;
use crate::grains::GrainKind;
use crate::plot::{Chart, DotPlot, DotSeries, Kind, Series, palette, write_dot_plot, write_panels};

pub const PRESSURE_FIGURE: &str = "pressure_over_overburden.png";
pub const LOAD_FIGURE: &str = "load_shares.png";

/// Writes both figures (PNG with a CSV of their numbers) into `dir`; returns the PNGs.
pub fn write_figures(
    dir: &Path,
    study: &Study,
    stats: &[CaseStats],
) -> anyhow::Result<Vec<PathBuf>> {
    std::fs::create_dir_all(dir)?;
    Ok(vec![
        pressure_over_overburden_figure(dir, study, stats)?,
        load_shares_figure(dir, study, stats)?,
    ])
}

fn measured(stats: &[CaseStats]) -> impl Iterator<Item = &CaseStats> {
    stats.iter().filter(|s| s.seeds_measured > 0)
}

/// P / (phi_f rho g h) on the centre line against h/W, one curve per measured case (mean with
/// a band of one standard error over its seeds) and the overburden's level 1; one panel per
/// shape, on the same axes.
pub fn pressure_over_overburden_figure(
    dir: &Path,
    study: &Study,
    stats: &[CaseStats],
) -> anyhow::Result<PathBuf> {
    let profile = |s: &CaseStats| {
        let (x, (y, err)): (Vec<f64>, (Vec<f64>, Vec<f64>)) = s
            .profile
            .iter()
            .enumerate()
            .map(|(k, m)| ((k + 1) as f64 * PROFILE_STEP_OVER_W, (m.mean, m.stderr)))
            .unzip();
        Series {
            label: study.cases[s.case].name.clone(),
            kind: Kind::Measured(Source::Simulation),
            colour: palette(s.case),
            x,
            y,
            err: Some(err),
        }
    };
    let depth = measured(stats)
        .flat_map(|s| {
            s.profile
                .iter()
                .enumerate()
                .filter(|(_, m)| m.mean.is_finite())
                .map(|(k, _)| (k + 1) as f64 * PROFILE_STEP_OVER_W)
        })
        .fold(PROFILE_STEP_OVER_W, f64::max);
    let overburden = Series {
        label: "overburden φ_f ρ g h".into(),
        kind: Kind::Model,
        colour: BLACK,
        x: vec![0.0, depth],
        y: vec![1.0, 1.0],
        err: None,
    };
    let panel = |shape: Option<GrainKind>| {
        let mut series: Vec<Series> = measured(stats)
            .filter(|s| s.shape == shape)
            .map(profile)
            .collect();
        series.push(overburden.clone());
        Chart {
            title: format!(
                "Centre-line pressure over the overburden, {} (band: ± 1 SE over seeds)",
                shape.map_or("grains", |s| s.display_name())
            ),
            x_label: "depth below the free surface h / W".into(),
            y_label: "P / (φ_f ρ g h), P = −trace(σ)/2".into(),
            x_column: "h_over_w".into(),
            y_column: "p_over_overburden".into(),
            x_range: None,
            series,
        }
    };
    let mut panels: Vec<Chart> = [GrainKind::Square, GrainKind::ShortRod, GrainKind::LongRod]
        .into_iter()
        .filter(|&shape| measured(stats).any(|s| s.shape == Some(shape)))
        .map(|shape| panel(Some(shape)))
        .collect();
    if panels.is_empty() {
        panels.push(panel(None));
    }
    let path = dir.join(PRESSURE_FIGURE);
    write_panels(&path, &panels)?;
    Ok(path)
}

/// The floor's and the walls' shares of the deposit's weight, one row per measured case
/// (numbered as the report's case table), mean and standard error over its seeds.
pub fn load_shares_figure(
    dir: &Path,
    study: &Study,
    stats: &[CaseStats],
) -> anyhow::Result<PathBuf> {
    let cases: Vec<&CaseStats> = measured(stats).collect();
    let share = |q: Q, colour: usize| DotSeries {
        label: q.label().into(),
        colour: palette(colour),
        values: cases
            .iter()
            .map(|s| (s.get(q).mean, s.get(q).stderr))
            .collect(),
    };
    let path = dir.join(LOAD_FIGURE);
    write_dot_plot(
        &path,
        &DotPlot {
            title: "Shares of the deposit's weight (mean ± SE over seeds)".into(),
            value_label: "share of the deposit's weight".into(),
            value_column: "share".into(),
            categories: cases
                .iter()
                .map(|s| format!("#{} {}", s.case + 1, study.cases[s.case].name))
                .collect(),
            series: vec![
                share(Q::FloorShare, 0),
                share(Q::WallsShare, 1),
                share(Q::LeftWallShare, 2),
                share(Q::RightWallShare, 3),
            ],
        },
    )?;
    Ok(path)
}
