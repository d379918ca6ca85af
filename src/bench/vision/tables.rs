//! The vision bench's results written out: the CSV of every row, the CSV of the detector's
//! steps, and the markdown tables printed.

use std::fmt::Write as _;
use std::path::{Path, PathBuf};

use super::{Row, Spent};
use crate::io::write_atomic;

/// Writes one row per shape, packing, seed, scale and style (and the pooled rows), with the
/// shortcuts taken in the last column.
pub fn write_results_csv(path: &Path, rows: &[Row], shortcuts: &str) -> anyhow::Result<()> {
    write_atomic(path, |w| {
        use std::io::Write;
        writeln!(
            w,
            "shape,packing,seed,px_per_mm,style,photos,truth_uncut,recall,precision,centre_rms_mm,orientation_rms_deg,turned_grains,unturned_orientation_rms_deg,cut_detections,cut_matched,seconds_per_photo,render_seconds_per_photo,shortcuts"
        )?;
        for r in rows {
            let t = &r.tally;
            writeln!(
                w,
                "{},{},{},{},{},{},{},{:.5},{:.5},{:.4},{:.3},{},{:.3},{},{},{:.4},{:.4},{}",
                r.shape,
                r.packing,
                r.seed.map_or("all".to_string(), |k| k.to_string()),
                r.px_per_mm,
                r.style,
                r.photos,
                t.truth_uncut,
                t.recall(),
                t.precision(),
                t.centre_rms_mm(),
                t.orientation_rms_deg(),
                t.turned,
                t.unturned_orientation_rms_deg(),
                t.detections_cut,
                t.detections_cut_matched,
                r.seconds / r.photos as f64,
                r.render_seconds / r.photos as f64,
                shortcuts
            )?;
        }
        Ok(())
    })
}

/// Writes the detector's wall time per photograph, step by step, per shape, scale and style.
pub fn write_phases_csv(path: &Path, spent: &[Spent]) -> anyhow::Result<()> {
    write_atomic(path, |w| {
        use std::io::Write;
        writeln!(w, "shape,px_per_mm,style,photos,phase,seconds_per_photo")?;
        for s in spent {
            for (phase, time) in s.phases.iter() {
                writeln!(
                    w,
                    "{},{},{},{},{phase},{:.4}",
                    s.shape,
                    s.px_per_mm,
                    s.style,
                    s.photos,
                    time.as_secs_f64() / s.photos as f64
                )?;
            }
        }
        Ok(())
    })
}

/// The CSV of the detector's steps beside the results' (`bench-vision.csv`:
/// `bench-vision-phases.csv`).
pub fn phases_path(out: &Path) -> PathBuf {
    let stem = out
        .file_stem()
        .map_or("bench-vision".into(), |s| s.to_string_lossy().into_owned());
    out.with_file_name(format!("{stem}-phases.csv"))
}

/// Each shape, scale and style's time per photograph step by step, with each step's share.
pub fn where_time_goes(spent: &[Spent]) -> String {
    let mut s = String::from(
        "Where the detector's time goes (wall seconds per photograph, both packings and every \
         seed pooled; steps in pipeline order, a step's share in brackets when 5 % or more):\n\n",
    );
    for sp in spent {
        let n = sp.photos as f64;
        let total = sp.phases.total().as_secs_f64();
        let steps: Vec<String> = sp
            .phases
            .iter()
            .map(|(name, time)| {
                let t = time.as_secs_f64();
                let share = if total > 0.0 { t / total } else { 0.0 };
                if share >= 0.05 {
                    format!("{name} {:.3} ({:.0} %)", t / n, 100.0 * share)
                } else {
                    format!("{name} {:.3}", t / n)
                }
            })
            .collect();
        let _ = writeln!(
            s,
            "- {} {} px/mm {} ({:.3} s): {}",
            sp.shape,
            sp.px_per_mm,
            sp.style,
            total / n,
            steps.join(", ")
        );
    }
    s
}

/// The pooled rows (both packings) as markdown: with several seeds, those pooled over all of
/// them, then one table per seed; with one, that seed's.
pub fn markdown(rows: &[Row], several: bool) -> String {
    let both = |r: &&Row| r.packing == "both";
    if !several {
        return table(rows.iter().filter(both), false);
    }
    let mut s = table(rows.iter().filter(both).filter(|r| r.seed.is_none()), false);
    s.push_str("\nPer seed:\n\n");
    s.push_str(&table(
        rows.iter().filter(both).filter(|r| r.seed.is_some()),
        true,
    ));
    s
}

/// Rows as a markdown table, with a seed column when `by_seed`.
fn table<'r>(rows: impl Iterator<Item = &'r Row>, by_seed: bool) -> String {
    let (head, rule) = if by_seed {
        ("| seed ", "|---")
    } else {
        ("", "")
    };
    let mut s = format!(
        "{head}| shape | px/mm | style | grains | recall | precision | centre RMS (mm) | orientation RMS (deg) | turned > 10 deg | RMS of the rest (deg) | detect s/photo | render s/photo |\n{rule}|---|---|---|---|---|---|---|---|---|---|---|---|\n",
    );
    for r in rows {
        let t = &r.tally;
        if by_seed {
            let _ = write!(s, "| {} ", r.seed.map_or(String::new(), |k| k.to_string()));
        }
        let _ = writeln!(
            s,
            "| {} | {} | {} | {} | {:.2} % | {:.2} % | {:.3} | {:.2} | {} | {:.2} | {:.3} | {:.3} |",
            r.shape,
            r.px_per_mm,
            r.style,
            t.truth_uncut,
            100.0 * t.recall(),
            100.0 * t.precision(),
            t.centre_rms_mm(),
            t.orientation_rms_deg(),
            t.turned,
            t.unturned_orientation_rms_deg(),
            r.seconds / r.photos as f64,
            r.render_seconds / r.photos as f64
        );
    }
    s
}

#[cfg(test)]
mod tests {
    use super::phases_path;
    use std::path::Path;

    #[test]
    fn the_steps_are_written_beside_the_table() {
        assert_eq!(
            phases_path(Path::new("runs/bench-vision.csv")),
            Path::new("runs/bench-vision-phases.csv")
        );
        assert_eq!(phases_path(Path::new("b")), Path::new("b-phases.csv"));
    }
}
