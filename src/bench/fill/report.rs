//! The bench's outputs: a CSV, a Markdown table and the speed-against-error plot, each written
//! atomically.

use std::io::Write;
use std::path::Path;

use super::deviation::WITHIN;
use super::{BenchReport, Row, compared_settings, fastest_within, pooled_phi_shift};
use crate::io::write_atomic;
use crate::plot::{SpeedErrorPoint, write_speed_error};

fn deviation_cells(row: &Row) -> [f64; 5] {
    match &row.deviations {
        Some(d) => [d.phi_f, d.orientation, d.rdf, d.pressure, d.largest()],
        None => [f64::NAN; 5],
    }
}

/// One row per scene x setting; deviations empty for the reference.
pub fn write_csv(path: &Path, report: &BenchReport) -> anyhow::Result<()> {
    write_atomic(path, |w| {
        writeln!(
            w,
            "scene,setting,runs,time_step_s,mean_steps,wall_s,cpu_s,speed_up,phi_f_dev,f_theta_dev,g_r_dev,pressure_dev,largest_dev,within_2se,not_relaxed"
        )?;
        for row in &report.rows {
            let cells = deviation_cells(row);
            let devs: Vec<String> = cells
                .iter()
                .map(|d| match row.deviations {
                    Some(_) => format!("{d:.4}"),
                    None => String::new(),
                })
                .collect();
            let within = row
                .deviations
                .map_or(String::new(), |d| d.within().to_string());
            writeln!(
                w,
                "{},{},{},{:e},{:.0},{:.3},{:.3},{:.4},{},{},{}",
                row.scene,
                row.setting,
                row.runs,
                row.time_step_s,
                row.mean_steps,
                row.wall_s,
                row.cpu_s,
                row.speed_up,
                devs.join(","),
                within,
                row.not_relaxed
            )?;
        }
        Ok(())
    })
}

fn cell(d: f64) -> String {
    if d.is_nan() {
        "n/a".into()
    } else {
        format!("{d:.2}")
    }
}

/// The table for docs/results/speed-vs-error.md, with a line saying how it was made.
pub fn write_markdown(path: &Path, report: &BenchReport) -> anyhow::Result<()> {
    write_atomic(path, |w| {
        writeln!(
            w,
            "{} grains, {} seeds per scene and setting, {} threads, relaxation at most {} s. \
             Deviations from the faithful ensemble in standard errors; within 2 SE: all <= {WITHIN}. \
             Speed-up: faithful CPU time over the setting's.\n",
            report.grains, report.seeds, report.threads, report.max_relaxation_time_s
        )?;
        writeln!(
            w,
            "| scene | setting | wall s | CPU s | speed-up | phi_f dev | f(theta) dev | g(r) dev | pressure dev | within 2 SE | runs not relaxed |"
        )?;
        writeln!(w, "|---|---|---|---|---|---|---|---|---|---|---|")?;
        for row in &report.rows {
            let [phi, f, g, p, _] = deviation_cells(row);
            let (devs, within) = match row.deviations {
                Some(d) => (
                    format!("{} | {} | {} | {}", cell(phi), cell(f), cell(g), cell(p)),
                    if d.within() { "yes" } else { "no" }.to_string(),
                ),
                None => ("reference | | | ".to_string(), String::new()),
            };
            writeln!(
                w,
                "| {} | {} | {:.1} | {:.1} | {:.2} | {devs} | {within} | {}/{} |",
                row.scene,
                row.setting,
                row.wall_s,
                row.cpu_s,
                row.speed_up,
                row.not_relaxed,
                row.runs
            )?;
        }
        let shifts: Vec<String> = compared_settings(report)
            .iter()
            .map(|name| format!("{name} {:+.2}", pooled_phi_shift(report, name)))
            .collect();
        writeln!(
            w,
            "\nPacking fraction shift pooled over the scenes (signed, in standard errors): {}.",
            shifts.join(", ")
        )?;
        match fastest_within(report) {
            Some((name, speed_up)) => writeln!(
                w,
                "\nFastest setting within {WITHIN} standard errors on every scene and pooled: {name} (speed-up at least {speed_up:.1})."
            )?,
            None => writeln!(
                w,
                "\nNo setting stays within {WITHIN} standard errors on every scene and pooled."
            )?,
        }
        Ok(())
    })
}

/// Speed-up (log x) against the largest deviation, one colour per scene, the 2-SE line.
pub fn write_plot(path: &Path, report: &BenchReport) -> anyhow::Result<()> {
    let points: Vec<SpeedErrorPoint> = report
        .rows
        .iter()
        .filter_map(|row| {
            let d = row.deviations?;
            Some(SpeedErrorPoint {
                group: row.scene.clone(),
                label: row.setting.clone(),
                speed_up: row.speed_up,
                deviation: d.largest(),
            })
        })
        .collect();
    write_speed_error(
        path,
        &format!(
            "Speed against error ({} grains, {} seeds)",
            report.grains, report.seeds
        ),
        &points,
        WITHIN,
    )
}
