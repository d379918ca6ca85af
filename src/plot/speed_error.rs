//! Speed against error: each faster setting as a point (speed-up on a log axis, its largest
//! deviation from the reference in standard errors), one colour per scene, and the line below
//! which a setting is accepted.

use std::path::Path;

use plotters::prelude::*;

use super::chart::palette;
use super::png::{plot_error, render_png};

#[derive(Clone, Debug)]
pub struct SpeedErrorPoint {
    /// Points of one group share a colour (the scene).
    pub group: String,
    /// Written beside the point (the setting).
    pub label: String,
    pub speed_up: f64,
    pub deviation: f64,
}

/// Points whose speed-up is not positive and finite or whose deviation is not finite cannot be
/// placed and are left out (the tables still carry them).
pub fn write_speed_error(
    png: &Path,
    title: &str,
    points: &[SpeedErrorPoint],
    threshold: f64,
) -> anyhow::Result<()> {
    let shown: Vec<&SpeedErrorPoint> = points
        .iter()
        .filter(|p| p.speed_up.is_finite() && p.speed_up > 0.0 && p.deviation.is_finite())
        .collect();
    let mut groups: Vec<&str> = Vec::new();
    for p in &shown {
        if !groups.contains(&p.group.as_str()) {
            groups.push(&p.group);
        }
    }
    let (mut x0, mut x1) = shown.iter().fold((1.0f64, 1.0f64), |(a, b), p| {
        (a.min(p.speed_up), b.max(p.speed_up))
    });
    x0 /= 1.5;
    x1 *= 1.5;
    let y1 = shown
        .iter()
        .fold(1.5 * threshold, |m, p| m.max(1.1 * p.deviation));
    render_png(png, (1000, 700), |root| {
        let mut ctx = ChartBuilder::on(root)
            .caption(title, ("sans-serif", 26))
            .margin(15)
            .x_label_area_size(50)
            .y_label_area_size(80)
            .build_cartesian_2d((x0..x1).log_scale(), 0.0..y1)
            .map_err(plot_error)?;
        ctx.configure_mesh()
            .x_labels(8)
            .x_label_formatter(&|x| tidy(*x))
            .x_desc("speed-up over the paper-faithful settings (CPU time)")
            .y_desc("largest deviation (standard errors)")
            .label_style(("sans-serif", 16))
            .axis_desc_style(("sans-serif", 20))
            .draw()
            .map_err(plot_error)?;
        ctx.draw_series(DashedLineSeries::new(
            vec![(x0, threshold), (x1, threshold)],
            8,
            5,
            BLACK.stroke_width(2),
        ))
        .map_err(plot_error)?
        .label(format!("{threshold} standard errors"))
        .legend(|(x, y)| PathElement::new(vec![(x, y), (x + 20, y)], BLACK.stroke_width(2)));
        for (k, group) in groups.iter().enumerate() {
            let colour = palette(k);
            let mine: Vec<&&SpeedErrorPoint> = shown.iter().filter(|p| p.group == *group).collect();
            ctx.draw_series(
                mine.iter()
                    .map(|p| Circle::new((p.speed_up, p.deviation), 6, colour.filled())),
            )
            .map_err(plot_error)?
            .label(*group)
            .legend(move |(x, y)| Circle::new((x + 10, y), 6, colour.filled()));
            ctx.draw_series(mine.iter().map(|p| {
                EmptyElement::at((p.speed_up, p.deviation))
                    + Text::new(p.label.clone(), (8, -8), ("sans-serif", 14).into_font())
            }))
            .map_err(plot_error)?;
        }
        ctx.configure_series_labels()
            .background_style(WHITE.mix(0.85))
            .border_style(BLACK)
            .label_font(("sans-serif", 16))
            .position(SeriesLabelPosition::UpperLeft)
            .draw()
            .map_err(plot_error)?;
        Ok(())
    })
}

/// A tick value without trailing zeros (10, 2.5, 0.75).
fn tidy(x: f64) -> String {
    let s = format!("{x:.2}");
    s.trim_end_matches('0').trim_end_matches('.').to_string()
}
