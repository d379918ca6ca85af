//! The vision bench's results written out: the CSV of every row, the CSV of the looks drawn,
//! the CSV of the detector's steps, and the markdown tables printed.

use std::fmt::Write as _;
use std::path::{Path, PathBuf};

use vision::evaluate::median_abs;

use super::{DrawnLook, Row, Spent, Split};
use crate::io::write_atomic;

/// Writes the rows (photographs, then pooled per source, then pooled over sources), with the
/// split and the shortcuts taken in every row.
pub fn write_results_csv(
    path: &Path,
    rows: &[&Row],
    split: Split,
    shortcuts: &str,
) -> anyhow::Result<()> {
    write_atomic(path, |w| {
        use std::io::Write;
        writeln!(
            w,
            "split,source,fill,shape,seed,px_per_mm,look,photos,grains,truth_uncut,recall,precision,centre_rms_mm,orientation_rms_deg,orientation_median_deg,turned_grains,unturned_orientation_rms_deg,cut_detections,cut_matched,seconds_per_photo,render_seconds_per_photo,peak_memory_mb,refused,shortcuts"
        )?;
        for r in rows {
            let t = &r.tally;
            writeln!(
                w,
                "{},{},{},{},{},{},{},{},{},{},{:.5},{:.5},{:.4},{:.3},{:.3},{},{:.3},{},{},{:.4},{:.4},{},{},{}",
                split.name(),
                r.source,
                r.fill,
                r.shape,
                r.seed.map_or("all".to_string(), |k| k.to_string()),
                r.px_per_mm,
                r.look.name(),
                r.photos,
                r.grains,
                t.truth_uncut,
                t.recall(),
                t.precision(),
                t.centre_rms_mm(),
                t.orientation_rms_deg(),
                median_abs(&r.orientation_errors_deg),
                t.turned,
                t.unturned_orientation_rms_deg(),
                t.detections_cut,
                t.detections_cut_matched,
                r.seconds / r.photos as f64,
                r.render_seconds / r.photos as f64,
                r.peak_memory_bytes
                    .map_or(String::new(), |b| format!("{:.0}", b as f64 / 1e6)),
                r.refused,
                shortcuts
            )?;
        }
        Ok(())
    })
}

/// Writes every look drawn: one row per seed, source and look range, the style's fields and
/// the file's JPEG quality (empty: lossless).
pub fn write_looks_csv(path: &Path, looks: &[DrawnLook]) -> anyhow::Result<()> {
    write_atomic(path, |w| {
        use std::io::Write;
        writeln!(
            w,
            "seed,source,shape,look,field_level,black_level,grain_transmission,rod_highlight,rod_highlight_width,vignetting,gradient,blur_px,full_well,read_noise,dust_per_cm2,dust_radius_mm,dust_opacity,scratches_per_100cm2,scratch_length_mm,scratch_width_mm,scratch_opacity,bore_scale,chamfer_mm,chamfer_glint,jpeg_quality"
        )?;
        for d in looks {
            let s = &d.look.style;
            writeln!(
                w,
                "{},{},{},{},{:.4},{:.4},{:.4},{:.4},{:.4},{:.4},{:.4},{:.3},{:.0},{:.5},{:.3},{:.3},{:.3},{:.3},{:.2},{:.3},{:.3},{:.3},{:.3},{:.3},{}",
                d.seed,
                d.source,
                d.shape,
                d.look_range.name(),
                s.field_level,
                s.black_level,
                s.grain_transmission,
                s.rod_highlight,
                s.rod_highlight_width,
                s.vignetting,
                s.gradient,
                s.blur_px,
                s.full_well,
                s.read_noise,
                s.dust_per_cm2,
                s.dust_radius_mm,
                s.dust_opacity,
                s.scratches_per_100cm2,
                s.scratch_length_mm,
                s.scratch_width_mm,
                s.scratch_opacity,
                s.bore_scale,
                s.chamfer_mm,
                s.chamfer_glint,
                d.look.jpeg_quality.map_or(String::new(), |q| q.to_string())
            )?;
        }
        Ok(())
    })
}

/// Writes the detector's wall time per photograph, step by step, per shape, scale and look
/// range.
pub fn write_phases_csv(path: &Path, spent: &[Spent]) -> anyhow::Result<()> {
    write_atomic(path, |w| {
        use std::io::Write;
        writeln!(w, "shape,px_per_mm,look,photos,phase,seconds_per_photo")?;
        for s in spent {
            for (phase, time) in s.phases.iter() {
                writeln!(
                    w,
                    "{},{},{},{},{phase},{:.4}",
                    s.shape,
                    s.px_per_mm,
                    s.look.name(),
                    s.photos,
                    time.as_secs_f64() / s.photos as f64
                )?;
            }
        }
        Ok(())
    })
}

/// A CSV beside the results' (`bench-vision.csv`, `phases`: `bench-vision-phases.csv`).
fn beside(out: &Path, what: &str) -> PathBuf {
    let stem = out
        .file_stem()
        .map_or("bench-vision".into(), |s| s.to_string_lossy().into_owned());
    out.with_file_name(format!("{stem}-{what}.csv"))
}

/// The CSV of the detector's steps beside the results'.
pub fn phases_path(out: &Path) -> PathBuf {
    beside(out, "phases")
}

/// The CSV of the looks drawn beside the results'.
pub fn looks_path(out: &Path) -> PathBuf {
    beside(out, "looks")
}

/// Each shape, scale and look range's time per photograph step by step, with each step's share.
pub fn where_time_goes(spent: &[Spent]) -> String {
    let mut s = String::from(
        "Where the detector's time goes (wall seconds per photograph, every source and seed \
         pooled; steps in pipeline order, a step's share in brackets when 5 % or more):\n\n",
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
            sp.look.name(),
            total / n,
            steps.join(", ")
        );
    }
    s
}

/// Rows as a markdown table; with the source and fill columns when `by_source`.
pub fn markdown(rows: &[Row], by_source: bool) -> String {
    let (head, rule) = if by_source {
        ("| source | fill ", "|---|---")
    } else {
        ("", "")
    };
    let mut s = format!(
        "| shape {head}| px/mm | look | photos (refused) | uncut grains | recall | precision | centre RMS (mm) | orientation RMS, all matched (deg) | median (deg) | turned > 10 deg | detect s/photo | render s/photo | peak memory (MB) |\n|---{rule}|---|---|---|---|---|---|---|---|---|---|---|---|---|\n",
    );
    for r in rows {
        let t = &r.tally;
        let _ = write!(s, "| {} ", r.shape);
        if by_source {
            let _ = write!(s, "| {} | {} ", r.source, r.fill);
        }
        let _ = writeln!(
            s,
            "| {} | {} | {} ({}) | {} | {:.2} % | {:.2} % | {:.3} | {:.2} | {:.2} | {} | {:.2} | {:.2} | {} |",
            r.px_per_mm,
            r.look.name(),
            r.photos,
            r.refused,
            t.truth_uncut,
            100.0 * t.recall(),
            100.0 * t.precision(),
            t.centre_rms_mm(),
            t.orientation_rms_deg(),
            median_abs(&r.orientation_errors_deg),
            t.turned,
            r.seconds / r.photos as f64,
            r.render_seconds / r.photos as f64,
            r.peak_memory_bytes
                .map_or("-".to_string(), |b| format!("{:.0}", b as f64 / 1e6))
        );
    }
    s
}

#[cfg(test)]
mod tests {
    use super::{looks_path, phases_path};
    use std::path::Path;

    #[test]
    fn the_steps_and_looks_are_written_beside_the_table() {
        assert_eq!(
            phases_path(Path::new("runs/bench-vision.csv")),
            Path::new("runs/bench-vision-phases.csv")
        );
        assert_eq!(phases_path(Path::new("b")), Path::new("b-phases.csv"));
        assert_eq!(
            looks_path(Path::new("runs/b.csv")),
            Path::new("runs/b-looks.csv")
        );
    }
}
