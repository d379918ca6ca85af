//! The report's figures: P / overburden against h/W per case, and the load shares per case.

use std::path::{Path, PathBuf};

use super::measures::{PROFILE_STEP_OVER_W, Q};
use super::results::CaseStats;
use super::study::Study;
use crate::deposit::Source;
use crate::plot::{Chart, Kind, Series, write_chart};

pub const PRESSURE_FIGURE: &str = "pressure_over_overburden.png";
pub const LOAD_FIGURE: &str = "load_shares.png";

/// Writes both figures (PNG with a CSV of their numbers) into `dir`; returns the PNGs.
pub fn write_figures(
    dir: &Path,
    study: &Study,
    stats: &[CaseStats],
) -> anyhow::Result<Vec<PathBuf>> {
    std::fs::create_dir_all(dir)?;
    let measured = || stats.iter().filter(|s| s.seeds_measured > 0);
    let mut series: Vec<Series> = measured()
        .map(|s| {
            let (x, (y, err)): (Vec<f64>, (Vec<f64>, Vec<f64>)) = s
                .profile
                .iter()
                .enumerate()
                .map(|(k, m)| ((k + 1) as f64 * PROFILE_STEP_OVER_W, (m.mean, m.stderr)))
                .unzip();
            Series {
                label: study.cases[s.case].name.clone(),
                kind: Kind::Measured(Source::Simulation),
                colour: s.case,
                x,
                y,
                err: Some(err),
            }
        })
        .collect();
    let depth = series
        .iter()
        .flat_map(|s| {
            s.x.iter()
                .zip(&s.y)
                .filter(|(_, y)| y.is_finite())
                .map(|(x, _)| *x)
        })
        .fold(PROFILE_STEP_OVER_W, f64::max);
    series.push(Series {
        label: "overburden".into(),
        kind: Kind::Model,
        colour: stats.len(),
        x: vec![0.0, depth],
        y: vec![1.0, 1.0],
        err: None,
    });
    let pressure = dir.join(PRESSURE_FIGURE);
    write_chart(
        &pressure,
        &Chart {
            title: "Centre-line pressure (-trace/2) over the overburden".into(),
            x_label: "depth below the free surface h/W".into(),
            y_label: "P / (phi_f rho g h)".into(),
            x_column: "h_over_w".into(),
            y_column: "p_over_overburden".into(),
            series,
        },
    )?;
    let share = |q: Q, colour: usize| {
        let (x, (y, err)): (Vec<f64>, (Vec<f64>, Vec<f64>)) = measured()
            .map(|s| ((s.case + 1) as f64, (s.get(q).mean, s.get(q).stderr)))
            .unzip();
        Series {
            label: q.label().into(),
            kind: Kind::Measured(Source::Simulation),
            colour,
            x,
            y,
            err: Some(err),
        }
    };
    let loads = dir.join(LOAD_FIGURE);
    write_chart(
        &loads,
        &Chart {
            title: "Shares of the deposit's weight".into(),
            x_label: "case (number in the report's case table)".into(),
            y_label: "share of the weight".into(),
            x_column: "case_number".into(),
            y_column: "share".into(),
            series: vec![
                share(Q::FloorShare, 0),
                share(Q::WallsShare, 1),
                share(Q::LeftWallShare, 2),
                share(Q::RightWallShare, 3),
            ],
        },
    )?;
    Ok(vec![pressure, loads])
}
