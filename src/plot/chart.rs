//! One line chart with error bars, experiment and simulation in two styles, and its numbers in a
//! CSV beside the PNG.

use std::path::Path;

use plotters::prelude::*;

use super::png::{plot_error, render_png};
use crate::deposit::Source;
use crate::io::write_atomic;

/// How a series is drawn: measured ensembles by source, model lines (overburden, fits) plain.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Kind {
    /// Solid line, filled circles.
    Measured(Source),
    /// Dashed line, no markers.
    Model,
}

#[derive(Clone, Debug)]
pub struct Series {
    pub label: String,
    pub kind: Kind,
    /// Index into the palette; series of one phi0 share a colour across sources.
    pub colour: usize,
    pub x: Vec<f64>,
    pub y: Vec<f64>,
    /// Standard error of y (error bars), if measured over an ensemble.
    pub err: Option<Vec<f64>>,
}

#[derive(Clone, Debug)]
pub struct Chart {
    pub title: String,
    pub x_label: String,
    pub y_label: String,
    /// Column names for the CSV (with units).
    pub x_column: String,
    pub y_column: String,
    pub series: Vec<Series>,
}

pub fn palette(k: usize) -> RGBColor {
    const P: [RGBColor; 8] = [
        RGBColor(31, 119, 180),
        RGBColor(214, 39, 40),
        RGBColor(44, 160, 44),
        RGBColor(255, 127, 14),
        RGBColor(148, 103, 189),
        RGBColor(140, 86, 75),
        RGBColor(227, 119, 194),
        RGBColor(23, 190, 207),
    ];
    P[k % P.len()]
}

/// Writes `png` and, beside it, the same stem with `.csv`: one row per point,
/// `series,<x_column>,<y_column>,stderr` (stderr 0 where the series has none). Points that are
/// not finite are not drawn and not written.
pub fn write_chart(png: &Path, chart: &Chart) -> anyhow::Result<()> {
    write_chart_csv(&png.with_extension("csv"), chart)?;
    draw_chart(png, chart)
}

fn finite_points(s: &Series) -> Vec<(f64, f64, f64)> {
    (0..s.x.len())
        .map(|k| (s.x[k], s.y[k], s.err.as_ref().map_or(0.0, |e| e[k])))
        .filter(|(x, y, e)| x.is_finite() && y.is_finite() && e.is_finite())
        .collect()
}

fn write_chart_csv(path: &Path, chart: &Chart) -> anyhow::Result<()> {
    write_atomic(path, |out| {
        let mut w = csv::Writer::from_writer(out);
        w.write_record(["series", &chart.x_column, &chart.y_column, "stderr"])?;
        for s in &chart.series {
            for (x, y, e) in finite_points(s) {
                w.write_record([
                    s.label.clone(),
                    format!("{x:e}"),
                    format!("{y:e}"),
                    format!("{e:e}"),
                ])?;
            }
        }
        w.flush()?;
        Ok(())
    })
}

fn bounds(chart: &Chart) -> ((f64, f64), (f64, f64)) {
    let (mut x0, mut x1, mut y0, mut y1) = (f64::MAX, f64::MIN, f64::MAX, f64::MIN);
    for s in &chart.series {
        for (x, y, e) in finite_points(s) {
            x0 = x0.min(x);
            x1 = x1.max(x);
            y0 = y0.min(y - e);
            y1 = y1.max(y + e);
        }
    }
    if x0 > x1 {
        return ((0.0, 1.0), (0.0, 1.0));
    }
    let pad = |lo: f64, hi: f64| {
        let span = if hi > lo { hi - lo } else { lo.abs().max(1.0) };
        (lo - 0.04 * span, hi + 0.04 * span)
    };
    (pad(x0, x1), pad(y0, y1))
}

fn draw_chart(png: &Path, chart: &Chart) -> anyhow::Result<()> {
    let ((x0, x1), (y0, y1)) = bounds(chart);
    render_png(png, (1000, 700), |root| {
        let mut ctx = ChartBuilder::on(root)
            .caption(&chart.title, ("sans-serif", 26))
            .margin(15)
            .x_label_area_size(50)
            .y_label_area_size(80)
            .build_cartesian_2d(x0..x1, y0..y1)
            .map_err(plot_error)?;
        ctx.configure_mesh()
            .x_desc(&chart.x_label)
            .y_desc(&chart.y_label)
            .label_style(("sans-serif", 16))
            .axis_desc_style(("sans-serif", 20))
            .draw()
            .map_err(plot_error)?;
        for s in &chart.series {
            let colour = palette(s.colour);
            let pts = finite_points(s);
            let line: Vec<(f64, f64)> = pts.iter().map(|p| (p.0, p.1)).collect();
            match s.kind {
                Kind::Measured(source) => {
                    let experiment = source == Source::Experiment;
                    let width = if experiment { 2 } else { 1 };
                    let anno = ctx
                        .draw_series(LineSeries::new(line.clone(), colour.stroke_width(width)))
                        .map_err(plot_error)?;
                    anno.label(&s.label);
                    if experiment {
                        anno.legend(move |(x, y)| {
                            EmptyElement::at((x + 10, y))
                                + PathElement::new(vec![(-10, 0), (10, 0)], colour.stroke_width(2))
                                + Circle::new((0, 0), 4, colour.filled())
                        });
                        ctx.draw_series(
                            line.iter()
                                .map(|&(x, y)| Circle::new((x, y), 4, colour.filled())),
                        )
                        .map_err(plot_error)?;
                    } else {
                        anno.legend(move |(x, y)| {
                            EmptyElement::at((x + 10, y))
                                + PathElement::new(vec![(-10, 0), (10, 0)], colour.stroke_width(1))
                                + TriangleMarker::new((0, 0), 6, colour.stroke_width(2))
                        });
                        ctx.draw_series(
                            line.iter().map(|&(x, y)| {
                                TriangleMarker::new((x, y), 6, colour.stroke_width(2))
                            }),
                        )
                        .map_err(plot_error)?;
                    }
                    if s.err.is_some() {
                        // A vertical bar of +- one standard error with 6 px caps.
                        ctx.draw_series(pts.iter().filter(|p| p.2 > 0.0).map(|&(x, y, e)| {
                            EmptyElement::at((x, y - e))
                                + PathElement::new(vec![(-3, 0), (3, 0)], colour.stroke_width(1))
                        }))
                        .map_err(plot_error)?;
                        ctx.draw_series(pts.iter().filter(|p| p.2 > 0.0).map(|&(x, y, e)| {
                            EmptyElement::at((x, y + e))
                                + PathElement::new(vec![(-3, 0), (3, 0)], colour.stroke_width(1))
                        }))
                        .map_err(plot_error)?;
                        ctx.draw_series(pts.iter().filter(|p| p.2 > 0.0).map(|&(x, y, e)| {
                            PathElement::new(vec![(x, y - e), (x, y + e)], colour.stroke_width(1))
                        }))
                        .map_err(plot_error)?;
                    }
                }
                Kind::Model => {
                    ctx.draw_series(DashedLineSeries::new(line, 8, 5, colour.stroke_width(2)))
                        .map_err(plot_error)?
                        .label(&s.label)
                        .legend(move |(x, y)| {
                            PathElement::new(vec![(x, y), (x + 20, y)], colour.stroke_width(2))
                        });
                }
            }
        }
        ctx.configure_series_labels()
            .background_style(WHITE.mix(0.85))
            .border_style(BLACK)
            .label_font(("sans-serif", 16))
            .position(SeriesLabelPosition::UpperRight)
            .draw()
            .map_err(plot_error)?;
        Ok(())
    })
}
