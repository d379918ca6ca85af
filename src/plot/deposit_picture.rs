//! A deposit drawn to scale: grains coloured by orientation (hue = folded theta over the
//! symmetry period, so 0 and the period meet) with dark outlines so that neighbours of one hue
//! stay apart, force chains as lines between the centres of touching grains (to the contact
//! point for walls) with width proportional to the force, and beside it a key: the colour bar
//! of theta in degrees over the folding range and line samples of the forces.

use std::path::Path;

use plotters::coord::Shift;
use plotters::prelude::*;
use plotters::style::text_anchor::{HPos, Pos, VPos};

use super::clip::{clip_polygon, clip_segment};
use super::png::{plot_error, render_png, tick_label};
use crate::deposit::{Grain, Partner, Realisation, Source, fold_angle};
use crate::io::write_atomic;

/// Line width (px) of a contact carrying the mean force.
const MEAN_FORCE_WIDTH: f64 = 2.0;
/// The widest force line (px), so that the strongest chains do not hide their grains.
const MAX_FORCE_WIDTH: f64 = 14.0;
/// Width of the key's panel (px).
const KEY_WIDTH: u32 = 190;

/// The fill of a grain at orientation `theta` (rad) for a shape of this folding period.
fn orientation_colour(theta: f64, period: f64) -> HSLColor {
    HSLColor(fold_angle(theta, period) / period, 0.75, 0.68)
}

/// The outline of a grain: its own hue, dark.
fn outline_colour(theta: f64, period: f64) -> HSLColor {
    HSLColor(fold_angle(theta, period) / period, 0.6, 0.25)
}

/// The rectangle's corners (m).
fn corners(g: &Grain) -> Vec<[f64; 2]> {
    let (c, s) = (g.theta.cos(), g.theta.sin());
    let (hl, hw) = (0.5 * g.length, 0.5 * g.width);
    [(hl, hw), (-hl, hw), (-hl, -hw), (hl, -hw)]
        .iter()
        .map(|(u, v)| [g.x + u * c - v * s, g.y + u * s + v * c])
        .collect()
}

/// Writes `png`, its force chains to the same stem `.csv`
/// (`x1_mm,y1_mm,x2_mm,y2_mm,force_N,width_px`) and its grains to `.grains.csv`
/// (`x_mm,y_mm,theta_rad,length_mm,width_mm,hue`, hue = folded theta / period). `source`
/// names the deposit's side in the caption.
pub fn draw_deposit(png: &Path, real: &Realisation, source: Source) -> anyhow::Result<()> {
    let frame = real.meta.frame(&real.deposit);
    let [x0, x1, y0, y1] = frame;
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
                format!("{:.4}", fold_angle(g.theta, period) / period),
            ])?;
        }
        w.flush()?;
        Ok(())
    })?;

    // 4 px per mm, within 600..2400 px across.
    let scale = (4.0e3f64).min(2400.0 / (x1 - x0)).max(600.0 / (x1 - x0));
    let plot_width = ((x1 - x0) * scale) as u32 + 120;
    let height = ((((y1 - y0) * scale) as u32) + 120).clamp(480, 6000);
    let side = match source {
        Source::Experiment => "experiment",
        Source::Simulation => "simulation",
    };
    let mm = |p: [f64; 2]| (p[0] * 1e3, p[1] * 1e3);
    render_png(png, (plot_width + KEY_WIDTH, height), |root| {
        let (plot, key) = root.split_horizontally(plot_width);
        let mut ctx = ChartBuilder::on(&plot)
            .caption(
                format!(
                    "{}, φ₀ = {:.3}, {side}: colour = orientation{}",
                    real.shape.display_name(),
                    real.meta.phi0,
                    if chains.is_empty() {
                        ""
                    } else {
                        ", lines = contact forces"
                    }
                ),
                ("sans-serif", 18),
            )
            .margin(10)
            .x_label_area_size(40)
            .y_label_area_size(60)
            .build_cartesian_2d(x0 * 1e3..x1 * 1e3, y0 * 1e3..y1 * 1e3)
            .map_err(plot_error)?;
        ctx.configure_mesh()
            .disable_mesh()
            .x_desc("x (mm)")
            .y_desc("y (mm)")
            .x_label_formatter(&tick_label)
            .y_label_formatter(&tick_label)
            .label_style(("sans-serif", 14))
            .draw()
            .map_err(plot_error)?;
        let outlines: Vec<(Vec<(f64, f64)>, f64)> = grains
            .iter()
            .map(|g| {
                let cut = clip_polygon(&corners(g), frame);
                (cut.into_iter().map(mm).collect::<Vec<_>>(), g.theta)
            })
            .filter(|(p, _)| p.len() >= 3)
            .collect();
        ctx.draw_series(
            outlines
                .iter()
                .map(|(p, t)| Polygon::new(p.clone(), orientation_colour(*t, period).filled())),
        )
        .map_err(plot_error)?;
        ctx.draw_series(outlines.iter().map(|(p, t)| {
            let mut ring = p.clone();
            ring.push(p[0]);
            PathElement::new(ring, outline_colour(*t, period).stroke_width(1))
        }))
        .map_err(plot_error)?;
        ctx.draw_series(chains.iter().filter_map(|(a, b, f)| {
            let (a, b) = clip_segment(*a, *b, frame)?;
            let wpx = width_px(*f).round().clamp(1.0, MAX_FORCE_WIDTH) as u32;
            Some(PathElement::new(
                vec![mm(a), mm(b)],
                BLACK.stroke_width(wpx),
            ))
        }))
        .map_err(plot_error)?;
        let (_, ys) = ctx.plotting_area().get_pixel_range();
        let top = ys.start;
        let bar_height = ((ys.end - ys.start) / 2).clamp(150, 320);
        draw_orientation_key(&key, period, top, bar_height)?;
        if !chains.is_empty() {
            draw_force_key(&key, mean_force, top + bar_height + 90)?;
        }
        Ok(())
    })
}

/// A key's title and, under it, what it measures.
fn draw_key_heading<DB: DrawingBackend>(
    area: &DrawingArea<DB, Shift>,
    title: &str,
    subtitle: &str,
    (left, top): (i32, i32),
) -> anyhow::Result<()> {
    let font = |size: u32| TextStyle::from(("sans-serif", size).into_font());
    area.draw(&Text::new(title, (left, top), font(16)))
        .map_err(plot_error)?;
    area.draw(&Text::new(subtitle, (left, top + 20), font(13)))
        .map_err(plot_error)?;
    Ok(())
}

/// The colour bar: theta from 0 (bottom) to the period (top), ticks in degrees.
fn draw_orientation_key<DB: DrawingBackend>(
    area: &DrawingArea<DB, Shift>,
    period: f64,
    top: i32,
    height: i32,
) -> anyhow::Result<()> {
    let font = |size: u32| TextStyle::from(("sans-serif", size).into_font());
    let left = 20;
    let bar = (left, top + 48, 26);
    draw_key_heading(area, "orientation θ", "(deg from horizontal)", (left, top))?;
    let (bx, by, bw) = bar;
    for row in 0..height {
        // Row 0 is the top: theta = period.
        let theta = period * (1.0 - (row as f64 + 0.5) / height as f64);
        area.draw(&Rectangle::new(
            [(bx, by + row), (bx + bw, by + row + 1)],
            orientation_colour(theta, period).filled(),
        ))
        .map_err(plot_error)?;
    }
    area.draw(&Rectangle::new(
        [(bx, by), (bx + bw, by + height)],
        BLACK.stroke_width(1),
    ))
    .map_err(plot_error)?;
    let degrees = period.to_degrees().round();
    let step = if degrees <= 90.0 { 15.0 } else { 30.0 };
    let ticks = (degrees / step).round() as i32;
    for k in 0..=ticks {
        let deg = k as f64 * step;
        let y = by + height - (deg / degrees * height as f64).round() as i32;
        area.draw(&PathElement::new(
            vec![(bx + bw, y), (bx + bw + 6, y)],
            BLACK.stroke_width(1),
        ))
        .map_err(plot_error)?;
        area.draw(&Text::new(
            tick_label(&deg),
            (bx + bw + 10, y),
            font(14).pos(Pos::new(HPos::Left, VPos::Center)),
        ))
        .map_err(plot_error)?;
    }
    Ok(())
}

/// Line samples of 1, 2 and 4 times the mean contact force with their forces in N.
fn draw_force_key<DB: DrawingBackend>(
    area: &DrawingArea<DB, Shift>,
    mean_force: f64,
    top: i32,
) -> anyhow::Result<()> {
    let font = |size: u32| TextStyle::from(("sans-serif", size).into_font());
    let left = 20;
    draw_key_heading(area, "contact force", "(line width ∝ force)", (left, top))?;
    for (k, times) in [1.0, 2.0, 4.0].into_iter().enumerate() {
        let y = top + 56 + 26 * k as i32;
        let width = (MEAN_FORCE_WIDTH * times).min(MAX_FORCE_WIDTH) as u32;
        area.draw(&PathElement::new(
            vec![(left, y), (left + 36, y)],
            BLACK.stroke_width(width),
        ))
        .map_err(plot_error)?;
        let text = if times == 1.0 {
            format!("{} N (mean)", significant(mean_force))
        } else {
            format!("{} N", significant(times * mean_force))
        };
        area.draw(&Text::new(
            text,
            (left + 46, y),
            font(14).pos(Pos::new(HPos::Left, VPos::Center)),
        ))
        .map_err(plot_error)?;
    }
    Ok(())
}

/// Three significant digits.
fn significant(x: f64) -> String {
    if x == 0.0 || !x.is_finite() {
        return format!("{x}");
    }
    let decimals = (2 - x.abs().log10().floor() as i32).max(0) as usize;
    format!("{x:.decimals$}")
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::deposit::SquareStack;
    use crate::grains::GrainKind;

    fn rgb(c: HSLColor) -> [u8; 3] {
        let (r, g, b) = c.to_backend_color().rgb;
        [r, g, b]
    }

    fn near(p: &[u8; 3], q: [u8; 3], tolerance: u8) -> bool {
        p.iter().zip(q).all(|(&a, b)| a.abs_diff(b) <= tolerance)
    }

    /// A stack of squares all at theta = 0: every grain has one hue, so other hues can only
    /// come from the key, and touching grains stay apart only by their outlines.
    #[test]
    fn a_deposit_of_one_hue_shows_its_key_and_its_outlines() {
        let stack = SquareStack {
            columns: 12,
            rows: 6,
            ..SquareStack::default()
        };
        let (deposit, contacts, meta) = stack.build(0.1);
        let real = Realisation {
            name: "stack".into(),
            deposit,
            contacts: Some(contacts),
            meta,
            shape: GrainKind::Square,
        };
        let dir = tempfile::tempdir().unwrap();
        let png = dir.path().join("deposit.png");
        draw_deposit(&png, &real, Source::Simulation).unwrap();
        let img = image::open(&png).unwrap().to_rgb8();
        let period = real.shape.symmetry_period();
        let pixels: Vec<[u8; 3]> = img.pixels().map(|p| p.0).collect();
        let count = |c: [u8; 3], tolerance| pixels.iter().filter(|p| near(p, c, tolerance)).count();
        // The outlines: a ring of some 100 px per grain, less what the chains cover.
        let outline = count(rgb(outline_colour(0.0, period)), 3);
        assert!(outline > 20 * 72, "{outline} outline pixels for 72 grains");
        // The key's bar: each of the folding range's quarter hues, none of which is a grain's
        // (a row of the bar is within 12 levels of it: the hue steps by at most 1/150 a row).
        for quarter in [0.25, 0.5, 0.75] {
            let hue = rgb(orientation_colour(quarter * period, period));
            assert!(
                count(hue, 12) >= 20,
                "no bar pixel of theta = {quarter} period"
            );
        }
        // The grains' tables beside it.
        let grains = std::fs::read_to_string(png.with_extension("grains.csv")).unwrap();
        assert_eq!(grains.lines().count(), 1 + 72);
    }
}
