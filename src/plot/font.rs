use std::sync::OnceLock;

use plotters::style::FontStyle;

/// Registers the embedded DejaVu Sans as "sans-serif" once per process: the machine may have
/// no system fonts (see DEPENDENCIES.md), and every figure draws text.
pub fn ensure_font() -> anyhow::Result<()> {
    static REGISTERED: OnceLock<Result<(), String>> = OnceLock::new();
    REGISTERED
        .get_or_init(|| {
            plotters::style::register_font("sans-serif", FontStyle::Normal, dejavu::sans::regular())
                .map_err(|_| "the embedded DejaVu Sans font was refused by plotters".to_string())
        })
        .clone()
        .map_err(anyhow::Error::msg)
}
