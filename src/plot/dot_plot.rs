//! A dot plot of measures per named category (a study's cases): one row per category, named
//! in full on the left, the series side by side within the row with horizontal error bars,
//! and no line between rows (categories are not a scale). Its numbers go to a CSV beside it.

use std::path::Path;

use plotters::prelude::*;
use plotters::style::text_anchor::{HPos, Pos, VPos};

use super::axis_range::axis_range;
use super::chart::ascii;
use super::legend::{Line, Look, MARKER_SIZE, Marker, draw_legend, legend_width};
use super::png::{plot_error, render_png, tick_label};
use crate::io::write_atomic;

#[derive(Clone, Debug)]
pub struct DotSeries {
    pub label: String,
    pub colour: RGBColor,
    /// (mean, standard error) per category, in the plot's order; a mean that is not finite
    /// is not drawn.
    pub values: Vec<(f64, f64)>,
}

#[derive(Clone, Debug)]
pub struct DotPlot {
    pub title: String,
    pub value_label: String,
    /// The value's column name in the CSV (with units).
    pub value_column: String,
    /// Rows from the top.
    pub categories: Vec<String>,
    pub series: Vec<DotSeries>,
}

const ROW_HEIGHT: u32 = 46;
const PLOT_WIDTH: u32 = 760;
const FONT: u32 = 16;

/// Writes `png` and the same stem `.csv`: `category,series,<value_column>,stderr`, one row per
/// drawn point.
pub fn write_dot_plot(png: &Path, plot: &DotPlot) -> anyhow::Result<()> {
    write_atomic(&png.with_extension("csv"), |out| {
        let mut w = csv::Writer::from_writer(out);
        w.write_record(["category", "series", &plot.value_column, "stderr"])?;
        for s in &plot.series {
            for (name, &(v, e)) in plot.categories.iter().zip(&s.values) {
                if v.is_finite() {
                    w.write_record([
                        ascii(name),
                        ascii(&s.label),
                        format!("{v:e}"),
                        format!("{e:e}"),
                    ])?;
                }
            }
        }
        w.flush()?;
        Ok(())
    })?;
    draw(png, plot)
}

fn draw(png: &Path, plot: &DotPlot) -> anyhow::Result<()> {
    super::font::ensure_font()?;
    let rows = plot.categories.len().max(1);
    let font = || TextStyle::from(("sans-serif", FONT).into_font());
    let mut names_width = 0;
    for name in &plot.categories {
        names_width = names_width.max(font().font.box_size(name).map_err(plot_error)?.0);
    }
    let entries: Vec<(String, Look)> = plot
        .series
        .iter()
        .map(|s| {
            let look = Look {
                colour: s.colour,
                line: Line::None,
                marker: Marker::Circle,
            };
            (s.label.clone(), look)
        })
        .collect();
    let legend = legend_width(&entries)?;
    let label_area = names_width + 24;
    let width = label_area + PLOT_WIDTH + legend;
    let height = (ROW_HEIGHT * rows as u32 + 150).max(420);
    let (v0, v1) = axis_range(
        plot.series
            .iter()
            .flat_map(|s| s.values.iter().copied())
            .filter(|(v, _)| v.is_finite()),
    );
    render_png(png, (width, height), |root| {
        let (chart_area, side) = root.split_horizontally(label_area + PLOT_WIDTH);
        let y_max = rows as f64 - 0.5;
        let mut ctx = ChartBuilder::on(&chart_area)
            .caption(&plot.title, ("sans-serif", 24))
            .margin(15)
            .x_label_area_size(50)
            .y_label_area_size(label_area - 15)
            .build_cartesian_2d(v0..v1, -0.5..y_max)
            .map_err(plot_error)?;
        ctx.configure_mesh()
            .disable_y_mesh()
            .y_labels(0)
            .x_desc(&plot.value_label)
            .x_label_formatter(&tick_label)
            .label_style(("sans-serif", FONT))
            .axis_desc_style(("sans-serif", 20))
            .bold_line_style(BLACK.mix(0.12))
            .light_line_style(TRANSPARENT)
            .draw()
            .map_err(plot_error)?;
        // Row k (from the top) sits at y = rows - 1 - k; separators between rows.
        let row_y = |k: usize| (rows - 1 - k) as f64;
        ctx.draw_series((1..rows).map(|k| {
            let y = row_y(k) + 0.5;
            PathElement::new(vec![(v0, y), (v1, y)], BLACK.mix(0.15).stroke_width(1))
        }))
        .map_err(plot_error)?;
        let m = plot.series.len().max(1) as f64;
        for (j, s) in plot.series.iter().enumerate() {
            let offset = 0.6 * ((j as f64 + 0.5) / m - 0.5);
            let points: Vec<(f64, f64, f64)> = s
                .values
                .iter()
                .take(plot.categories.len())
                .enumerate()
                .filter(|(_, (v, _))| v.is_finite())
                .map(|(k, &(v, e))| (v, row_y(k) - offset, if e.is_finite() { e } else { 0.0 }))
                .collect();
            let colour = s.colour;
            ctx.draw_series(points.iter().filter(|p| p.2 > 0.0).map(|&(v, y, e)| {
                PathElement::new(vec![(v - e, y), (v + e, y)], colour.stroke_width(2))
            }))
            .map_err(plot_error)?;
            for sign in [-1.0, 1.0] {
                ctx.draw_series(points.iter().filter(|p| p.2 > 0.0).map(|&(v, y, e)| {
                    EmptyElement::at((v + sign * e, y))
                        + PathElement::new(vec![(0, -4), (0, 4)], colour.stroke_width(2))
                }))
                .map_err(plot_error)?;
            }
            ctx.draw_series(
                points
                    .iter()
                    .map(|&(v, y, _)| Circle::new((v, y), MARKER_SIZE + 1, colour.filled())),
            )
            .map_err(plot_error)?;
        }
        let (xs, ys) = ctx.plotting_area().get_pixel_range();
        for (k, name) in plot.categories.iter().enumerate() {
            let (_, py) = ctx.backend_coord(&(v0, row_y(k)));
            root.draw(&Text::new(
                name.clone(),
                (xs.start - 10, py),
                font().pos(Pos::new(HPos::Right, VPos::Center)),
            ))
            .map_err(plot_error)?;
        }
        draw_legend(&side, &entries, ys.start)
    })
}
