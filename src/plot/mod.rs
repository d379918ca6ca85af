//! Figures (PNG, plotters with an embedded font) with their numbers in CSV files beside them.

mod chart;
mod deposit_picture;
mod figures;
mod font;
mod png;
mod speed_error;

pub use chart::{Chart, Kind, Series, write_chart};
pub use deposit_picture::draw_deposit;
pub use figures::write_figures;
pub use font::ensure_font;
pub use speed_error::{SpeedErrorPoint, write_speed_error};
