use std::collections::HashMap;
use std::sync::Mutex;
use std::sync::atomic::{AtomicBool, Ordering};

use anyhow::Context;
use indicatif::{MultiProgress, ProgressBar, ProgressStyle};

use facets::fill::{FillEvent, FillProgress};

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

/// One bar per running filling, under `bars`: added when a filling starts, updated as it
/// goes, taken off when it ends (or, with `keep_finished`, left at its last state).
pub struct FillingBars {
    bars: MultiProgress,
    style: ProgressStyle,
    keep_finished: bool,
    running: Mutex<HashMap<String, ProgressBar>>,
}

impl FillingBars {
    /// Bars under `bars` whose names fill a column of `name_width` characters.
    pub fn new(bars: &MultiProgress, name_width: usize, keep_finished: bool) -> Self {
        Self {
            bars: bars.clone(),
            style: filling_style(name_width),
            keep_finished,
            running: Mutex::new(HashMap::new()),
        }
    }

    /// Draws the event of the filling called `name` (unique among those running).
    pub fn show(&self, name: &str, event: FillEvent) {
        let Ok(mut running) = self.running.lock() else {
            return;
        };
        match event {
            FillEvent::Reused => {}
            FillEvent::Started { resumed } => {
                let bar = self
                    .bars
                    .add(ProgressBar::new(1).with_style(self.style.clone()));
                bar.set_prefix(name.to_string());
                if resumed {
                    bar.set_message("resuming");
                }
                running.insert(name.to_string(), bar);
            }
            FillEvent::Filling(p) => {
                if let Some(bar) = running.get(name) {
                    bar.set_length((p.expected_end.max(p.time) * 1e3) as u64);
                    bar.set_position((p.time * 1e3) as u64);
                    bar.set_message(describe(&p));
                }
            }
            FillEvent::Finished { .. } | FillEvent::Stopped => {
                if let Some(bar) = running.remove(name) {
                    if self.keep_finished {
                        bar.finish();
                    } else {
                        bar.finish_and_clear();
                        self.bars.remove(&bar);
                    }
                }
            }
        }
    }
}

/// Where a filling stands, in words.
fn describe(p: &FillProgress) -> String {
    let phase = if p.relaxing {
        format!(
            "relaxing, kinetic/elastic {:.1e}, load/weight off by {:.2} %",
            p.energy_ratio,
            100.0 * p.load_imbalance
        )
    } else {
        "filling".to_string()
    };
    let asleep = if p.asleep > 0 {
        format!(", {} asleep", p.asleep)
    } else {
        String::new()
    };
    format!("{}/{} grains in{asleep}, {phase}", p.inserted, p.total)
}
