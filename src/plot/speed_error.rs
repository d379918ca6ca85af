//! Speed against error: each faster setting as a point (speed-up on a log axis, its largest
//! deviation from the reference in standard errors), one colour per scene, and the line below
//! which a setting is accepted.

use std::path::Path;

use plotters::coord::combinators::{BindKeyPoints, LogCoord, WithKeyPoints};
use plotters::prelude::*;

use super::chart::palette;
use super::legend::{Line, Look, Marker, draw_legend, legend_width};
use super::png::{plot_error, render_png, tick_label};

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
    let mut entries = vec![(
        format!("{threshold} standard errors"),
        Look {
            colour: BLACK,
            line: Line::Dashed(2),
            marker: Marker::None,
        },
    )];
    entries.extend(groups.iter().enumerate().map(|(k, g)| {
        let look = Look {
            colour: palette(k),
            line: Line::None,
            marker: Marker::Circle,
        };
        (g.to_string(), look)
    }));
    let legend = legend_width(&entries)?;
    render_png(png, (1000 + legend, 700), |root| {
        let (plot, side) = root.split_horizontally(1000);
        let mut ctx = ChartBuilder::on(&plot)
            .caption(title, ("sans-serif", 26))
            .margin(15)
            .x_label_area_size(50)
            .y_label_area_size(80)
            .build_cartesian_2d(speed_axis(x0, x1), 0.0..y1)
            .map_err(plot_error)?;
        ctx.configure_mesh()
            .x_label_formatter(&|x| tick_label(x))
            .y_label_formatter(&|y| tick_label(y))
            .x_desc("speed-up over the paper-faithful settings (CPU time)")
            .y_desc("largest deviation (standard errors)")
            .label_style(("sans-serif", 16))
            .axis_desc_style(("sans-serif", 20))
            .bold_line_style(BLACK.mix(0.12))
            .light_line_style(TRANSPARENT)
            .draw()
            .map_err(plot_error)?;
        ctx.draw_series(DashedLineSeries::new(
            vec![(x0, threshold), (x1, threshold)],
            12,
            7,
            BLACK.stroke_width(2),
        ))
        .map_err(plot_error)?;
        for (k, group) in groups.iter().enumerate() {
            let colour = palette(k);
            let mine: Vec<&&SpeedErrorPoint> = shown.iter().filter(|p| p.group == *group).collect();
            ctx.draw_series(
                mine.iter()
                    .map(|p| Circle::new((p.speed_up, p.deviation), 6, colour.filled())),
            )
            .map_err(plot_error)?;
            ctx.draw_series(mine.iter().map(|p| {
                EmptyElement::at((p.speed_up, p.deviation))
                    + Text::new(p.label.clone(), (8, -8), ("sans-serif", 14).into_font())
            }))
            .map_err(plot_error)?;
        }
        let top = ctx.plotting_area().get_pixel_range().1.start;
        draw_legend(&side, &entries, top)
    })
}

/// The log axis of speed-ups with ticks at 1, 2, 5 times the powers of ten within it (the
/// powers of ten alone leave a narrow range with one tick).
fn speed_axis(x0: f64, x1: f64) -> WithKeyPoints<LogCoord<f64>> {
    let ticks: Vec<f64> = (-3..=4)
        .flat_map(|p| [1.0, 2.0, 5.0].map(|m| m * 10f64.powi(p)))
        .filter(|t| (x0..=x1).contains(t))
        .collect();
    LogCoord::from((x0..x1).log_scale()).with_key_points(ticks)
}
