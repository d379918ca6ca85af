//! A figure's legend in a panel of its own beside the plot area: it can never cover a line or
//! a bar, whatever the data, at the cost of a wider picture.

use plotters::coord::Shift;
use plotters::prelude::*;
use plotters::style::text_anchor::{HPos, Pos, VPos};

use super::png::plot_error;

/// How a series is drawn, and so its sample in the legend.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Look {
    pub colour: RGBColor,
    pub line: Line,
    pub marker: Marker,
}

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Line {
    None,
    /// Width in pixels.
    Solid(u32),
    Dashed(u32),
}

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Marker {
    None,
    /// Filled circle (experiment).
    Circle,
    /// Open triangle (simulation).
    Triangle,
}

pub const MARKER_SIZE: i32 = 4;
const FONT_SIZE: u32 = 16;
const ROW: i32 = 24;
const SAMPLE: i32 = 34;
const PAD: i32 = 10;

fn font() -> TextStyle<'static> {
    ("sans-serif", FONT_SIZE).into_font().into()
}

/// The panel's width in pixels for these entries (0 without entries).
pub fn legend_width(entries: &[(String, Look)]) -> anyhow::Result<u32> {
    super::font::ensure_font()?;
    let mut widest = 0;
    for (label, _) in entries {
        let (w, _) = font().font.box_size(label).map_err(plot_error)?;
        widest = widest.max(w);
    }
    Ok(if entries.is_empty() {
        0
    } else {
        // The box's pads, the sample, the gap to the text and a margin for the estimate.
        widest + widest / 20 + (SAMPLE + 6 * PAD) as u32
    })
}

/// Draws the entries in a framed box from `top` (pixels from the area's top) down.
pub fn draw_legend<DB: DrawingBackend>(
    area: &DrawingArea<DB, Shift>,
    entries: &[(String, Look)],
    top: i32,
) -> anyhow::Result<()> {
    if entries.is_empty() {
        return Ok(());
    }
    let (width, _) = area.dim_in_pixel();
    let left = PAD;
    let bottom = top + ROW * entries.len() as i32 + PAD;
    area.draw(&Rectangle::new(
        [(left, top), (width as i32 - PAD, bottom)],
        BLACK.stroke_width(1),
    ))
    .map_err(plot_error)?;
    for (k, (label, look)) in entries.iter().enumerate() {
        let y = top + PAD / 2 + ROW * k as i32 + ROW / 2;
        let x = left + PAD;
        draw_sample(area, look, (x, y), SAMPLE)?;
        area.draw(&Text::new(
            label.clone(),
            (x + SAMPLE + PAD, y),
            font().pos(Pos::new(HPos::Left, VPos::Center)),
        ))
        .map_err(plot_error)?;
    }
    Ok(())
}

/// A line `length` pixels long from `(x, y)`, its marker in the middle.
pub fn draw_sample<DB: DrawingBackend>(
    area: &DrawingArea<DB, Shift>,
    look: &Look,
    (x, y): (i32, i32),
    length: i32,
) -> anyhow::Result<()> {
    let ends = vec![(x, y), (x + length, y)];
    match look.line {
        Line::None => {}
        Line::Solid(w) => area
            .draw(&PathElement::new(ends, look.colour.stroke_width(w)))
            .map_err(plot_error)?,
        Line::Dashed(w) => {
            // Two dashes and a gap, as the chart's dashes.
            for (a, b) in [(0, 12), (19, length)] {
                area.draw(&PathElement::new(
                    vec![(x + a, y), (x + b, y)],
                    look.colour.stroke_width(w),
                ))
                .map_err(plot_error)?;
            }
        }
    }
    let mid = (x + length / 2, y);
    match look.marker {
        Marker::None => {}
        Marker::Circle => area
            .draw(&Circle::new(mid, MARKER_SIZE, look.colour.filled()))
            .map_err(plot_error)?,
        Marker::Triangle => area
            .draw(&TriangleMarker::new(
                mid,
                MARKER_SIZE + 2,
                look.colour.stroke_width(2),
            ))
            .map_err(plot_error)?,
    }
    Ok(())
}
