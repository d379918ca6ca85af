use std::sync::atomic::{AtomicBool, Ordering};

use anyhow::Context;
use indicatif::{ProgressBar, ProgressStyle};

/// A bar on stderr (hidden when stderr is not a terminal).
pub fn bar(len: usize, what: &str) -> ProgressBar {
    let style = ProgressStyle::with_template("{msg:>12} [{bar:40}] {pos}/{len} ({eta})")
        .unwrap_or_else(|_| ProgressStyle::default_bar())
        .progress_chars("=> ");
    ProgressBar::new(len as u64)
        .with_style(style)
        .with_message(what.to_string())
}

/// Set by Ctrl-C: fillings stop at their next step boundary and write checkpoints.
pub static INTERRUPT: AtomicBool = AtomicBool::new(false);

/// Ctrl-C sets [`INTERRUPT`]; a second Ctrl-C exits at once with status 130.
pub fn stop_fillings_on_ctrl_c() -> anyhow::Result<()> {
    ctrlc::set_handler(|| {
        if INTERRUPT.swap(true, Ordering::SeqCst) {
            std::process::exit(130);
        }
    })
    .context("cannot install the Ctrl-C handler")
}

/// The style of a filling's bar: simulated milliseconds, with the run's name in a column of
/// `name_width` characters.
pub fn filling_style(name_width: usize) -> ProgressStyle {
    let template = format!(
        "{{prefix:>{name_width}}} [{{bar:30}}] {{pos}}/{{len}} ms simulated, {{msg}} ({{elapsed}} / ETA {{eta}})"
    );
    ProgressStyle::with_template(&template)
        .unwrap_or_else(|_| ProgressStyle::default_bar())
        .progress_chars("=> ")
}
