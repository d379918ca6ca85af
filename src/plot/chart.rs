//! Line charts with error bars (experiment and simulation in two styles), alone or stacked in
//! panels, each legend beside its plot area, and their numbers in a CSV beside the PNG.

use std::path::Path;

use plotters::prelude::*;

use super::axis_range::axis_range;
use super::legend::{Line, Look, MARKER_SIZE, Marker, draw_legend, legend_width};
use super::png::{plot_error, render_png, tick_label};
use crate::deposit::Source;
use crate::io::write_atomic;

/// How a series is drawn: measured ensembles by source, model lines (overburden, fits) plain.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Kind {
    /// Experiment: thick line, filled circles; simulation: thin line, open triangles.
    Measured(Source),
    /// Dashed line, no markers.
    Model,
}

#[derive(Clone, Debug)]
pub struct Series {
    /// The legend's text; the CSV's `series` column holds it spelled in ASCII ([`ascii`]).
    pub label: String,
    pub kind: Kind,
    pub colour: RGBColor,
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
    /// The x axis' range when the quantity has a natural one (an angle's folding period);
    /// None: the points' range with a margin.
    pub x_range: Option<(f64, f64)>,
    pub series: Vec<Series>,
}

/// Distinct colours for series; a caller keys them (phi0, case) so that one thing keeps its
/// colour across figures.
pub fn palette(k: usize) -> RGBColor {
    const P: [RGBColor; 10] = [
        RGBColor(31, 119, 180),
        RGBColor(214, 39, 40),
        RGBColor(44, 160, 44),
        RGBColor(255, 127, 14),
        RGBColor(148, 103, 189),
        RGBColor(140, 86, 75),
        RGBColor(227, 119, 194),
        RGBColor(23, 190, 207),
        RGBColor(188, 189, 34),
        RGBColor(127, 127, 127),
    ];
    P[k % P.len()]
}

/// Series with more points than this show their errors as a shaded band: bars that close
/// together would hide the line.
pub const BARS_UP_TO: usize = 40;

/// Plot area (the legend's panel widens the picture).
const PLOT_SIZE: (u32, u32) = (1000, 700);

/// Writes `png` and, beside it, the same stem with `.csv`: one row per point,
/// `series,<x_column>,<y_column>,stderr` (stderr 0 where the series has none). Points that are
/// not finite are not drawn and not written.
pub fn write_chart(png: &Path, chart: &Chart) -> anyhow::Result<()> {
    write_panels(png, std::slice::from_ref(chart))
}

/// Charts of one quantity stacked in one picture (small multiples: one panel per shape, say),
/// on the same axes' ranges so that panels compare at a glance, each with its legend beside
/// it; one CSV of every panel's series, with the first panel's column names.
pub fn write_panels(png: &Path, panels: &[Chart]) -> anyhow::Result<()> {
    anyhow::ensure!(
        !panels.is_empty(),
        "{}: a figure without a chart",
        png.display()
    );
    write_chart_csv(&png.with_extension("csv"), panels)?;
    draw_panels(png, panels)
}

/// A label in ASCII for tables: Greek letters by name, subscripts and the minus sign plain.
pub fn ascii(label: &str) -> String {
    let mut out = String::with_capacity(label.len());
    for c in label.chars() {
        match c {
            'θ' => out.push_str("theta"),
            'φ' => out.push_str("phi"),
            'σ' => out.push_str("sigma"),
            'λ' => out.push_str("lambda"),
            'ρ' => out.push_str("rho"),
            '−' => out.push('-'),
            '±' => out.push_str("+-"),
            '·' => out.push(' '),
            '₀'..='₉' => out.push(char::from(b'0' + (c as u32 - '₀' as u32) as u8)),
            c if c.is_ascii() => out.push(c),
            _ => out.push('?'),
        }
    }
    out
}

fn finite_points(s: &Series) -> Vec<(f64, f64, f64)> {
    (0..s.x.len())
        .map(|k| (s.x[k], s.y[k], s.err.as_ref().map_or(0.0, |e| e[k])))
        .filter(|(x, y, e)| x.is_finite() && y.is_finite() && e.is_finite())
        .collect()
}

fn write_chart_csv(path: &Path, panels: &[Chart]) -> anyhow::Result<()> {
    write_atomic(path, |out| {
        let mut w = csv::Writer::from_writer(out);
        let first = &panels[0];
        w.write_record(["series", &first.x_column, &first.y_column, "stderr"])?;
        // A series repeated in several panels (a reference line) is written once.
        let mut written: Vec<String> = Vec::new();
        for s in panels.iter().flat_map(|c| &c.series) {
            let name = ascii(&s.label);
            if written.contains(&name) {
                continue;
            }
            written.push(name.clone());
            for (x, y, e) in finite_points(s) {
                w.write_record([
                    name.clone(),
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

/// The x and y ranges: every point with its error bar inside (see [`axis_range`]).
pub fn chart_ranges(chart: &Chart) -> ((f64, f64), (f64, f64)) {
    let points: Vec<(f64, f64, f64)> = chart.series.iter().flat_map(finite_points).collect();
    let x = chart
        .x_range
        .unwrap_or_else(|| axis_range(points.iter().map(|p| (p.0, 0.0))));
    let y = axis_range(points.iter().map(|p| (p.1, p.2)));
    (x, y)
}

fn look(s: &Series) -> Look {
    let dense = s.x.len() > BARS_UP_TO;
    match s.kind {
        Kind::Measured(Source::Experiment) => Look {
            colour: s.colour,
            line: Line::Solid(2),
            marker: Marker::Circle,
        },
        Kind::Measured(Source::Simulation) => Look {
            colour: s.colour,
            line: Line::Solid(if dense { 2 } else { 1 }),
            marker: if dense {
                Marker::None
            } else {
                Marker::Triangle
            },
        },
        Kind::Model => Look {
            colour: s.colour,
            line: Line::Dashed(2),
            marker: Marker::None,
        },
    }
}

/// Height of each panel when several share a picture.
const PANEL_HEIGHT: u32 = 520;

fn legend_entries(chart: &Chart) -> Vec<(String, Look)> {
    chart
        .series
        .iter()
        .filter(|s| !s.label.is_empty())
        .map(|s| (s.label.clone(), look(s)))
        .collect()
}

fn draw_panels(png: &Path, panels: &[Chart]) -> anyhow::Result<()> {
    let ranges: Vec<_> = panels.iter().map(chart_ranges).collect();
    let union = |a: (f64, f64), b: (f64, f64)| (a.0.min(b.0), a.1.max(b.1));
    let (x, y) = ranges[1..]
        .iter()
        .fold(ranges[0], |(x, y), r| (union(x, r.0), union(y, r.1)));
    let entries: Vec<Vec<(String, Look)>> = panels.iter().map(legend_entries).collect();
    let mut legend = 0;
    for e in &entries {
        legend = legend.max(legend_width(e)?);
    }
    let height = if panels.len() == 1 {
        PLOT_SIZE.1
    } else {
        PANEL_HEIGHT * panels.len() as u32
    };
    render_png(png, (PLOT_SIZE.0 + legend, height), |root| {
        let rows = root.split_evenly((panels.len(), 1));
        for ((panel, area), entries) in panels.iter().zip(&rows).zip(&entries) {
            let (plot, side) = area.split_horizontally(PLOT_SIZE.0);
            let top = draw_chart_on(&plot, panel, x, y)?;
            draw_legend(&side, entries, top - area.get_pixel_range().1.start)?;
        }
        Ok(())
    })
}

/// Draws the chart on `area` with these ranges; returns the plot area's top (pixels).
fn draw_chart_on(
    area: &DrawingArea<BitMapBackend<'_>, plotters::coord::Shift>,
    chart: &Chart,
    (x0, x1): (f64, f64),
    (y0, y1): (f64, f64),
) -> anyhow::Result<i32> {
    let mut ctx = ChartBuilder::on(area)
        .caption(&chart.title, ("sans-serif", 26))
        .margin(15)
        .x_label_area_size(50)
        .y_label_area_size(80)
        .build_cartesian_2d(x0..x1, y0..y1)
        .map_err(plot_error)?;
    ctx.configure_mesh()
        .x_desc(&chart.x_label)
        .y_desc(&chart.y_label)
        .x_label_formatter(&tick_label)
        .y_label_formatter(&tick_label)
        .label_style(("sans-serif", 16))
        .axis_desc_style(("sans-serif", 20))
        .bold_line_style(BLACK.mix(0.12))
        .light_line_style(TRANSPARENT)
        .draw()
        .map_err(plot_error)?;
    for s in &chart.series {
        draw_series(&mut ctx, s)?;
    }
    Ok(ctx.plotting_area().get_pixel_range().1.start)
}

type Ctx<'a, 'b> = ChartContext<
    'a,
    BitMapBackend<'b>,
    Cartesian2d<plotters::coord::types::RangedCoordf64, plotters::coord::types::RangedCoordf64>,
>;

fn draw_series(ctx: &mut Ctx<'_, '_>, s: &Series) -> anyhow::Result<()> {
    let look = look(s);
    let colour = look.colour;
    let pts = finite_points(s);
    let line: Vec<(f64, f64)> = pts.iter().map(|p| (p.0, p.1)).collect();
    let dense = s.x.len() > BARS_UP_TO;
    let with_err = s.err.is_some() && pts.iter().any(|p| p.2 > 0.0);
    if with_err && dense {
        // +- one standard error as a band under the line.
        let band: Vec<(f64, f64)> = pts
            .iter()
            .map(|&(x, y, e)| (x, y + e))
            .chain(pts.iter().rev().map(|&(x, y, e)| (x, y - e)))
            .collect();
        ctx.draw_series(std::iter::once(Polygon::new(
            band,
            colour.mix(0.2).filled(),
        )))
        .map_err(plot_error)?;
    }
    match look.line {
        Line::None => {}
        Line::Solid(w) => {
            ctx.draw_series(LineSeries::new(line.clone(), colour.stroke_width(w)))
                .map_err(plot_error)?;
        }
        Line::Dashed(w) => {
            ctx.draw_series(DashedLineSeries::new(
                line.clone(),
                12,
                7,
                colour.stroke_width(w),
            ))
            .map_err(plot_error)?;
        }
    }
    if with_err && !dense {
        // A vertical bar of +- one standard error with 6 px caps.
        let barred = || pts.iter().filter(|p| p.2 > 0.0);
        ctx.draw_series(barred().map(|&(x, y, e)| {
            PathElement::new(vec![(x, y - e), (x, y + e)], colour.stroke_width(1))
        }))
        .map_err(plot_error)?;
        for sign in [-1.0, 1.0] {
            ctx.draw_series(barred().map(|&(x, y, e)| {
                EmptyElement::at((x, y + sign * e))
                    + PathElement::new(vec![(-3, 0), (3, 0)], colour.stroke_width(1))
            }))
            .map_err(plot_error)?;
        }
    }
    match look.marker {
        Marker::None => {}
        Marker::Circle => {
            ctx.draw_series(
                line.iter()
                    .map(|&p| Circle::new(p, MARKER_SIZE, colour.filled())),
            )
            .map_err(plot_error)?;
        }
        Marker::Triangle => {
            ctx.draw_series(
                line.iter()
                    .map(|&p| TriangleMarker::new(p, MARKER_SIZE + 2, colour.stroke_width(2))),
            )
            .map_err(plot_error)?;
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    fn series(y: Vec<f64>, err: Vec<f64>) -> Series {
        Series {
            label: "sim φ₀ = 0.250".into(),
            kind: Kind::Measured(Source::Simulation),
            colour: palette(0),
            x: (0..y.len()).map(|k| k as f64).collect(),
            y,
            err: Some(err),
        }
    }

    #[test]
    fn the_y_axis_holds_every_error_bar_and_the_model_lines() {
        let chart = Chart {
            title: String::new(),
            x_label: String::new(),
            y_label: String::new(),
            x_column: "x".into(),
            y_column: "y".into(),
            x_range: None,
            series: vec![
                series(vec![1.0, 2.0, 0.5], vec![0.1, 3.0, 0.9]),
                Series {
                    kind: Kind::Model,
                    err: None,
                    ..series(vec![-2.0, 0.0], vec![])
                },
            ],
        };
        let ((x0, x1), (y0, y1)) = chart_ranges(&chart);
        assert!(x0 < 0.0 && x1 > 2.0);
        for s in &chart.series {
            for (_, y, e) in finite_points(s) {
                assert!(y - e > y0 && y + e < y1, "{y} +- {e} outside {y0}..{y1}");
            }
        }
    }

    #[test]
    fn a_chart_is_written_with_its_legend_beside_the_plot_and_its_table() {
        let dir = tempfile::tempdir().unwrap();
        let png = dir.path().join("chart.png");
        let chart = Chart {
            title: "f(θ)".into(),
            x_label: "θ (deg)".into(),
            y_label: "f(θ) (1/deg)".into(),
            x_column: "theta_deg".into(),
            y_column: "f_per_deg".into(),
            x_range: Some((0.0, 90.0)),
            series: vec![series(vec![0.01, 0.02, 0.015], vec![0.001, 0.002, 0.0])],
        };
        write_chart(&png, &chart).unwrap();
        let img = image::open(&png).unwrap().to_rgb8();
        assert_eq!(img.height(), PLOT_SIZE.1);
        assert!(img.width() > PLOT_SIZE.0);
        // The legend's text and frame are right of the plot area.
        let dark_beside = img
            .enumerate_pixels()
            .filter(|(x, _, p)| *x >= PLOT_SIZE.0 && p.0.iter().all(|&c| c < 100))
            .count();
        assert!(
            dark_beside > 100,
            "{dark_beside} dark pixels beside the plot"
        );
        let table = std::fs::read_to_string(png.with_extension("csv")).unwrap();
        let mut lines = table.lines();
        assert_eq!(lines.next(), Some("series,theta_deg,f_per_deg,stderr"));
        assert_eq!(lines.count(), 3);
        assert!(table.contains("sim phi0 = 0.250,"));
    }

    #[test]
    fn legend_labels_become_ascii_in_the_tables() {
        assert_eq!(ascii("exp φ₀ = 0.100"), "exp phi0 = 0.100");
        assert_eq!(ascii("−σ_yy, λ/W"), "-sigma_yy, lambda/W");
    }
}
