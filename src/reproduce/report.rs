//! Stage 5: `report.md` (a table per shape and phi0, the detector's accuracy, the figures
//! embedded by relative path) and `report.json` (the same numbers, for scripts and tests).

use std::fmt::Write as _;
use std::path::Path;

use serde::Serialize;

use super::analyse::ShapeAnalysis;
use super::detect::{Detected, accuracy};
use super::layout::Layout;
use super::plan::{Plan, phi0_tag};
use super::simulate::Filled;
use crate::analysis::pressure::janssen_saturates;
use crate::analysis::stats::MeanErr;
use crate::analysis::summary::{EnsembleSummary, Summary};
use crate::grains::GrainKind;
use crate::io::write_atomic;

/// One side's numbers at one (shape, phi0).
#[derive(Clone, Debug, Serialize)]
pub struct SideNumbers {
    pub realisations: usize,
    pub phi_f: MeanErr,
    pub g_at_1: MeanErr,
    /// Bin centre of the largest f(theta) (degrees, in [-period/2, period/2): 0 is flat).
    pub peak_angle_deg: f64,
    /// Rods only.
    pub s2: Option<MeanErr>,
    pub s4: MeanErr,
    /// Janssen fit of the pressure profile (simulated deposits: photographs have no forces).
    pub lambda_over_w: Option<f64>,
    pub p_sat_n_per_m: Option<f64>,
    /// Deepest h / W the Janssen fit used: a fit to depths below lambda cannot tell lambda.
    pub janssen_depth_over_w: Option<f64>,
}

/// The detector against the truth on the photographs of one (shape, phi0).
#[derive(Clone, Debug, Serialize)]
pub struct DetectorNumbers {
    pub photographs: usize,
    /// Photographs with a truth table.
    pub scored: usize,
    pub true_grains: usize,
    pub recall: f64,
    pub precision: f64,
    pub centre_rms_mm: f64,
    pub orientation_rms_deg: f64,
    /// Matched grains turned by more than `vision::evaluate::TURNED_DEG`, and the orientation
    /// RMS of the others: a few grains fitted across their neighbours weigh more in the RMS
    /// than every other grain's small error.
    pub turned: usize,
    pub unturned_orientation_rms_deg: f64,
    /// Mean detector wall time per photograph detected in this run (s).
    pub seconds_per_photo: Option<f64>,
}

#[derive(Clone, Debug, Serialize)]
pub struct Row {
    pub phi0: f64,
    pub simulation: Option<SideNumbers>,
    pub experiment: Option<SideNumbers>,
    pub detector: Option<DetectorNumbers>,
}

#[derive(Clone, Debug, Serialize)]
pub struct ShapeReport {
    pub shape: GrainKind,
    pub rows: Vec<Row>,
    /// Figures (PNG) and photographs, relative to the output folder.
    pub figures: Vec<String>,
    pub photographs: Vec<String>,
}

/// Wall time of one stage (s).
#[derive(Clone, Debug, Serialize)]
pub struct StageTime {
    pub stage: String,
    pub seconds: f64,
}

#[derive(Clone, Debug, Serialize)]
pub struct Report {
    pub plan: Plan,
    /// True when the experiment side is real photographs (`--photos`).
    pub real_photographs: bool,
    pub stages: Vec<StageTime>,
    pub fillings_run: usize,
    pub fillings_reused: usize,
    /// Fillings that did not relax within the allowed time (their deposits are used).
    pub unrelaxed: Vec<String>,
    pub shapes: Vec<ShapeReport>,
}

fn numbers(e: &EnsembleSummary) -> SideNumbers {
    let o = &e.orientation;
    let peak =
        o.f.iter()
            .enumerate()
            .max_by(|a, b| a.1.total_cmp(b.1))
            .map_or(f64::NAN, |(k, _)| {
                // Folded to [-period/2, period/2): a peak at 177.5 deg is the 2.5 deg below 0.
                let t = o.theta[k];
                if t >= 0.5 * o.period { t - o.period } else { t }.to_degrees()
            });
    let janssen = e.pressure.as_ref().and_then(|p| p.janssen);
    SideNumbers {
        realisations: e.n_realisations,
        phi_f: e.rdf.packing_fraction,
        g_at_1: e.rdf.g_at_1,
        peak_angle_deg: peak,
        s2: o.s2,
        s4: o.s4,
        lambda_over_w: janssen.map(|j| j.lambda_over_w),
        p_sat_n_per_m: janssen.map(|j| j.p_sat),
        janssen_depth_over_w: janssen.map(|j| j.h_over_w_max),
    }
}

fn at(summary: &Option<Summary>, phi0: f64) -> Option<SideNumbers> {
    summary
        .as_ref()?
        .ensembles
        .iter()
        .find(|e| (e.phi0 - phi0).abs() < 1e-9)
        .map(numbers)
}

/// Collects the report's numbers.
pub fn build(
    plan: &Plan,
    layout: &Layout,
    filled: &[Filled],
    detected: &[Detected],
    analyses: &[ShapeAnalysis],
    stages: Vec<StageTime>,
    real_photographs: bool,
) -> Report {
    let shapes = analyses
        .iter()
        .map(|a| {
            let mut phi0s: Vec<f64> = [&a.simulation, &a.experiment]
                .into_iter()
                .flatten()
                .flat_map(|s| s.ensembles.iter().map(|e| e.phi0))
                .collect();
            phi0s.sort_by(f64::total_cmp);
            phi0s.dedup_by(|x, y| (*x - *y).abs() < 1e-9);
            let rows = phi0s
                .iter()
                .map(|&phi0| {
                    let acc = accuracy(detected, a.kind, phi0);
                    let detector = (acc.photographs > 0).then(|| DetectorNumbers {
                        photographs: acc.photographs,
                        scored: acc.scored,
                        true_grains: acc.tally.truth_uncut,
                        recall: acc.tally.recall(),
                        precision: acc.tally.precision(),
                        centre_rms_mm: acc.tally.centre_rms_mm(),
                        orientation_rms_deg: acc.tally.orientation_rms_deg(),
                        turned: acc.tally.turned,
                        unturned_orientation_rms_deg: acc.tally.unturned_orientation_rms_deg(),
                        seconds_per_photo: acc.seconds_per_photo,
                    });
                    Row {
                        phi0,
                        simulation: at(&a.simulation, phi0),
                        experiment: at(&a.experiment, phi0),
                        detector,
                    }
                })
                .collect();
            let mut photographs = Vec::new();
            for phi0 in &phi0s {
                if let Some(d) = detected
                    .iter()
                    .find(|d| d.kind == a.kind && (d.phi0 - phi0).abs() < 1e-9)
                {
                    photographs.push(layout.relative(&d.photo));
                    if let Some(o) = &d.overlay {
                        photographs.push(layout.relative(o));
                    }
                }
            }
            ShapeReport {
                shape: a.kind,
                rows,
                figures: a.figures.iter().map(|f| layout.relative(f)).collect(),
                photographs,
            }
        })
        .collect();
    Report {
        plan: plan.clone(),
        real_photographs,
        stages,
        fillings_run: filled.iter().filter(|f| !f.reused).count(),
        fillings_reused: filled.iter().filter(|f| f.reused).count(),
        unrelaxed: filled
            .iter()
            .filter(|f| !f.record.relaxed)
            .map(|f| layout.relative(&f.filling.dir))
            .collect(),
        shapes,
    }
}

fn pm(m: &MeanErr, digits: usize) -> String {
    if m.mean.is_finite() {
        format!("{:.*} ± {:.*}", digits, m.mean, digits, m.stderr)
    } else {
        "—".into()
    }
}

fn num(v: Option<f64>, digits: usize) -> String {
    match v {
        Some(v) if v.is_finite() => format!("{v:.digits$}"),
        _ => "—".into(),
    }
}

fn side_cell(side: &Option<SideNumbers>, f: &dyn Fn(&SideNumbers) -> String) -> String {
    side.as_ref().map_or("—".into(), f)
}

/// Writes report.md and report.json into the output folder.
pub fn write(report: &Report, out: &Path) -> anyhow::Result<()> {
    write_atomic(&out.join("report.json"), |w| {
        serde_json::to_writer_pretty(&mut *w, report)?;
        Ok(())
    })?;
    let text = markdown(report);
    write_atomic(&out.join("report.md"), |w| {
        use std::io::Write;
        Ok(w.write_all(text.as_bytes())?)
    })
}

fn markdown(r: &Report) -> String {
    let p = &r.plan;
    let mut s = String::new();
    let _ = writeln!(s, "# facets reproduce: plan `{}`\n", p.name);
    let experiment = if r.real_photographs {
        "real photographs (`--photos`), detected".to_string()
    } else {
        format!(
            "synthetic photographs ({} style, {} px/mm) of {} other fillings per (shape, phi0) (seeds {}..), detected",
            p.photo_style,
            p.photo_px_per_mm,
            p.photo_realisations,
            super::plan::PHOTO_SEED_OFFSET + 1
        )
    };
    let _ = writeln!(
        s,
        "Silo {} mm wide; simulation side: {} fillings per (shape, phi0); experiment side: {experiment}. \
         Analysed frame: {}, less 40 mm at each side wall; g(r) from centres at least {} D inside it.\n",
        p.silo_width_mm,
        p.simulation_realisations,
        match p.frame {
            crate::scene::FrameChoice::RegionE => "region E (290-410 mm)",
            _ => "the whole deposit",
        },
        p.rdf_margin_over_d,
    );
    let _ = writeln!(
        s,
        "Fillings run now: {}, found done from an earlier run: {}. Wall time per stage: {}.\n",
        r.fillings_run,
        r.fillings_reused,
        r.stages
            .iter()
            .map(|t| format!("{} {:.0} s", t.stage, t.seconds))
            .collect::<Vec<_>>()
            .join(", ")
    );
    if !r.unrelaxed.is_empty() {
        let _ = writeln!(
            s,
            "**Not relaxed** within {} s (used as they are): {}\n",
            p.max_relaxation_time_s,
            r.unrelaxed.join(", ")
        );
    }
    let _ = writeln!(
        s,
        "Values are ensemble means ± standard errors over realisations (± 0 with one). \
         lambda/W and P_sat come from the Janssen fit of -sigma_yy on the centre line (N/m, 2D \
         stress: divide by the plate gap for Pa); photographs carry no forces. The fit is \
         meaningful only when the deposit is deeper than lambda (of order W): small silos' \
         shallow deposits give fits to a few h/W tenths, shown beside lambda / W.\n"
    );
    for shape in &r.shapes {
        let grains = p
            .shapes
            .iter()
            .find(|x| x.kind == shape.shape)
            .map_or(String::new(), |x| {
                format!(", {} grains per filling", x.grains)
            });
        let _ = writeln!(s, "## {}{grains}\n", shape.shape.display_name());
        for row in &shape.rows {
            let _ = writeln!(s, "### phi0 = {:.3}\n", row.phi0);
            let _ = writeln!(s, "| quantity | simulation | photographs |");
            let _ = writeln!(s, "|---|---|---|");
            let line = |s: &mut String, name: &str, f: &dyn Fn(&SideNumbers) -> String| {
                let _ = writeln!(
                    s,
                    "| {name} | {} | {} |",
                    side_cell(&row.simulation, f),
                    side_cell(&row.experiment, f)
                );
            };
            line(&mut s, "realisations", &|n| n.realisations.to_string());
            line(&mut s, "phi_f", &|n| pm(&n.phi_f, 3));
            line(&mut s, "g(1)", &|n| pm(&n.g_at_1, 2));
            line(&mut s, "peak of f(theta) (deg from horizontal)", &|n| {
                num(Some(n.peak_angle_deg), 1)
            });
            if row
                .simulation
                .iter()
                .chain(row.experiment.iter())
                .any(|n| n.s2.is_some())
            {
                line(&mut s, "S2", &|n| {
                    n.s2.as_ref().map_or("—".into(), |m| pm(m, 3))
                });
            }
            line(&mut s, "S4", &|n| pm(&n.s4, 3));
            // The fit searches lambda up to 100 W: there, the profile is still straight (a
            // deposit shallower than lambda) and P_sat is only the slope times 100 W.
            line(
                &mut s,
                "lambda / W",
                &|n| match (n.lambda_over_w, n.janssen_depth_over_w) {
                    (Some(l), _) if !janssen_saturates(l) => {
                        "≥ 100 (no saturation in this depth)".into()
                    }
                    (Some(l), Some(h)) => format!("{l:.2} (fitted to h/W ≤ {h:.2})"),
                    (l, _) => num(l, 2),
                },
            );
            line(&mut s, "P_sat (N/m)", &|n| match n.lambda_over_w {
                Some(l) if !janssen_saturates(l) => "— (not saturated)".into(),
                _ => num(n.p_sat_n_per_m, 3),
            });
            if let Some(d) = &row.detector {
                if d.scored > 0 {
                    let _ = writeln!(
                        s,
                        "\nDetector on these {} photographs ({} true grains not cut by the frame): \
                         recall {:.1} %, precision {:.1} %, centre RMS {:.3} mm, orientation RMS {:.2} deg \
                         ({} turned by more than {} deg, the rest {:.2} deg){}.",
                        d.scored,
                        d.true_grains,
                        100.0 * d.recall,
                        100.0 * d.precision,
                        d.centre_rms_mm,
                        d.orientation_rms_deg,
                        d.turned,
                        vision::evaluate::TURNED_DEG,
                        d.unturned_orientation_rms_deg,
                        d.seconds_per_photo
                            .map_or(String::new(), |t| format!(", {t:.1} s per photograph"))
                    );
                } else {
                    let _ = writeln!(
                        s,
                        "\nDetector: {} photographs, no truth tables, accuracy not measured.",
                        d.photographs
                    );
                }
            }
            let _ = writeln!(s);
        }
        if !shape.photographs.is_empty() {
            let _ = writeln!(s, "### Photographs (first of each phi0) and detections\n");
            for ph in &shape.photographs {
                let _ = writeln!(s, "![{ph}]({ph})\n");
            }
        }
        let _ = writeln!(
            s,
            "### Figures (experiment: solid lines and filled circles; simulation: thin lines and open triangles)\n"
        );
        for f in &shape.figures {
            let _ = writeln!(s, "![{f}]({f})\n");
        }
    }
    let _ = writeln!(
        s,
        "Each shape's folder holds the fillings (`runs/`), photographs, detector tables, both \
         sides' `summary.json` (`analysis/`) and the figures with their CSV and \
         `comparison.json` (`figures/`). Phi0 folders are named `{}`-style.",
        phi0_tag(0.1)
    );
    s
}
