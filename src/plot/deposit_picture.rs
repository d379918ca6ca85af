//! A deposit drawn to scale: grains coloured by orientation (hue = theta over the symmetry
//! period, so 0 and the period meet), force chains as lines between the centres of touching
//! grains (to the contact point for walls) with width proportional to the force.

use std::path::Path;

use plotters::prelude::*;

use super::png::{plot_error, render_png};
use crate::deposit::{Partner, Realisation};
use crate::io::write_atomic;

/// Line width (px) of a contact carrying the mean force.
const MEAN_FORCE_WIDTH: f64 = 2.0;

/// Writes `png`, its force chains to the same stem `.csv`
/// (`x1_mm,y1_mm,x2_mm,y2_mm,force_N,width_px`) and its grains to `.grains.csv`
/// (`x_mm,y_mm,theta_rad,length_mm,width_mm,hue`).
pub fn draw_deposit(png: &Path, real: &Realisation) -> anyhow::Result<()> {
    let [x0, x1, y0, y1] = real.meta.frame(&real.deposit);
    let period = real.shape.symmetry_period();
    let grains = &real.deposit.grains;
    let chains: Vec<([f64; 2], [f64; 2], f64)> = real
        .contacts
        .iter()
        .flatten()
        .map(|c| {
            let a = [grains[c.i].x, grains[c.i].y];
            let b = match c.partner {
                Partner::Grain(j) => [grains[j].x, grains[j].y],
                Partner::Wall(_) => c.point,
            };
            (a, b, c.magnitude())
        })
        .collect();
    let mean_force = if chains.is_empty() {
        1.0
    } else {
        chains.iter().map(|c| c.2).sum::<f64>() / chains.len() as f64
    };
    let width_px = |f: f64| MEAN_FORCE_WIDTH * f / mean_force.max(f64::MIN_POSITIVE);

    write_atomic(&png.with_extension("csv"), |out| {
        let mut w = csv::Writer::from_writer(out);
        w.write_record(["x1_mm", "y1_mm", "x2_mm", "y2_mm", "force_N", "width_px"])?;
        for (a, b, f) in &chains {
            w.write_record([
                format!("{:.4}", a[0] * 1e3),
                format!("{:.4}", a[1] * 1e3),
                format!("{:.4}", b[0] * 1e3),
                format!("{:.4}", b[1] * 1e3),
                format!("{f:e}"),
                format!("{:.3}", width_px(*f)),
            ])?;
        }
        w.flush()?;
        Ok(())
    })?;
    write_atomic(&png.with_extension("grains.csv"), |out| {
        let mut w = csv::Writer::from_writer(out);
        w.write_record(["x_mm", "y_mm", "theta_rad", "length_mm", "width_mm", "hue"])?;
        for g in grains {
            w.write_record([
                format!("{:.4}", g.x * 1e3),
                format!("{:.4}", g.y * 1e3),
                format!("{:.6}", g.theta),
                format!("{:.4}", g.length * 1e3),
                format!("{:.4}", g.width * 1e3),
                format!("{:.4}", g.theta / period),
            ])?;
        }
        w.flush()?;
        Ok(())
    })?;

    // 4 px per mm, within 600..2400 px across.
    let scale = (4.0e3f64).min(2400.0 / (x1 - x0)).max(600.0 / (x1 - x0));
    let (wpx, hpx) = (
        ((x1 - x0) * scale) as u32 + 120,
        (((y1 - y0) * scale) as u32 + 120).min(6000),
    );
    render_png(png, (wpx, hpx), |root| {
        let mut ctx = ChartBuilder::on(root)
            .caption(
                format!(
                    "{}, phi0 = {:.3}: hue = theta / symmetry period, lines = contact forces (width ~ force)",
                    real.shape.name(),
                    real.meta.phi0
                ),
                ("sans-serif", 18),
            )
            .margin(10)
            .x_label_area_size(40)
            .y_label_area_size(50)
            .build_cartesian_2d(x0 * 1e3..x1 * 1e3, y0 * 1e3..y1 * 1e3)
            .map_err(plot_error)?;
        ctx.configure_mesh()
            .disable_mesh()
            .x_desc("x (mm)")
            .y_desc("y (mm)")
            .label_style(("sans-serif", 14))
            .draw()
            .map_err(plot_error)?;
        ctx.draw_series(grains.iter().map(|g| {
            let (c, s) = (g.theta.cos(), g.theta.sin());
            let (hl, hw) = (0.5 * g.length, 0.5 * g.width);
            let corners: Vec<(f64, f64)> = [(hl, hw), (-hl, hw), (-hl, -hw), (hl, -hw)]
                .iter()
                .map(|(u, v)| ((g.x + u * c - v * s) * 1e3, (g.y + u * s + v * c) * 1e3))
                .collect();
            Polygon::new(corners, HSLColor(g.theta / period, 0.75, 0.7).filled())
        }))
        .map_err(plot_error)?;
        ctx.draw_series(chains.iter().map(|(a, b, f)| {
            let wpx = width_px(*f).round().clamp(1.0, 14.0) as u32;
            PathElement::new(
                vec![(a[0] * 1e3, a[1] * 1e3), (b[0] * 1e3, b[1] * 1e3)],
                BLACK.stroke_width(wpx),
            )
        }))
        .map_err(plot_error)?;
        Ok(())
    })
}
