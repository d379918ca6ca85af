use std::path::Path;

use image::ImageEncoder;
use plotters::prelude::*;

use crate::io::write_atomic;

/// Draws into an RGB buffer and writes it as a PNG atomically (plotters' own file output would
/// leave a half-written file on error).
pub fn render_png<F>(path: &Path, size: (u32, u32), draw: F) -> anyhow::Result<()>
where
    F: FnOnce(&DrawingArea<BitMapBackend<'_>, plotters::coord::Shift>) -> anyhow::Result<()>,
{
    super::font::ensure_font()?;
    let mut buffer = vec![0u8; size.0 as usize * size.1 as usize * 3];
    {
        let root = BitMapBackend::with_buffer(&mut buffer, size).into_drawing_area();
        root.fill(&WHITE).map_err(plot_error)?;
        draw(&root)?;
        root.present().map_err(plot_error)?;
    }
    write_atomic(path, |w| {
        image::codecs::png::PngEncoder::new(w).write_image(
            &buffer,
            size.0,
            size.1,
            image::ExtendedColorType::Rgb8,
        )?;
        Ok(())
    })
}

/// plotters' errors carry the backend's error type; keep their text.
pub fn plot_error<E: std::fmt::Debug>(e: E) -> anyhow::Error {
    anyhow::anyhow!("drawing failed: {e:?}")
}

/// A tick label without trailing zeros (10, 2.5, 0.05), in exponent form for magnitudes below
/// 1e-3 where decimals would read 0.
pub fn tick_label(x: &f64) -> String {
    if *x != 0.0 && x.abs() < 1e-3 {
        return format!("{x:.1e}");
    }
    let s = format!("{x:.4}");
    let s = s.trim_end_matches('0').trim_end_matches('.');
    if s == "-0" { "0".into() } else { s.into() }
}
