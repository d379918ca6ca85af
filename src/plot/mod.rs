//! Figures (PNG, plotters with an embedded font) with their numbers in CSV files beside them.
//! Every chart keeps each error bar inside its axes and its legend beside the plot area.

mod axis_range;
mod chart;
mod clip;
mod deposit_picture;
mod dot_plot;
mod figures;
mod font;
mod legend;
mod png;
mod speed_error;

pub use axis_range::axis_range;
pub use chart::{Chart, Kind, Series, ascii, palette, write_chart, write_panels};
pub use deposit_picture::draw_deposit;
pub use dot_plot::{DotPlot, DotSeries, write_dot_plot};
pub use figures::{
    deposit_figure, g1_figure, orientation_figure, packing_fraction_figure, pressure_figure,
    pressure_w_scan_figure, rdf_figure, write_figures,
};
pub use font::ensure_font;
pub use speed_error::{SpeedErrorPoint, write_speed_error};
