//! The report: how it was made, the cases, one section per finding (table, checks, verdict),
//! one per group of variants (each beside its baseline, the difference in standard errors),
//! and the figures.

use std::fmt::Write;

use super::figures::{LOAD_FIGURE, PRESSURE_FIGURE};
use super::findings::{Finding, find, mean_err, short};
use super::measures::{Q, STUDY_ROD53_ANGLE_DEG, WINDOW_DEG};
use super::results::CaseStats;
use super::study::{Case, Study};
use crate::analysis::stats::MeanErr;

/// What the header says of how the report was produced.
#[derive(Clone, Debug)]
pub struct Provenance {
    /// The command that runs (or resumes) the study and writes this report.
    pub command: String,
    /// The newest run's date (YYYY-MM-DD, UTC), None without runs.
    pub date: Option<String>,
    /// The report's figures, relative to the report.
    pub figures_dir: String,
}

fn cell(m: MeanErr, asked: usize) -> String {
    let text = mean_err(m);
    if m.mean.is_finite() && m.n < asked {
        format!("{text} (n = {})", m.n)
    } else {
        text
    }
}

fn grains(case: &Case) -> String {
    format!(
        "{} {}",
        case.scene.grains.count,
        case.scene.grains.kind.name()
    )
}

/// The report's markdown.
pub fn render(
    study: &Study,
    stats: &[CaseStats],
    findings: &[Finding],
    provenance: &Provenance,
) -> String {
    let mut md = String::new();
    let asked: usize = study.cases.iter().map(|c| c.seeds.len()).sum();
    let measured: usize = stats.iter().map(|s| s.seeds_measured).sum();
    let unrelaxed: usize = stats.iter().map(|s| s.unrelaxed).sum();
    let _ = writeln!(md, "# Validation against the study (Acevedo et al. 2014)\n");
    let _ = writeln!(
        md,
        "Produced by `{}` from the study file `{}`: {measured} of {asked} realisations measured{}; runs of {}. \
         Regenerate from the same runs with `--report-only`; the raw measures of every realisation \
         are in `results.csv` and `results.json` beside the runs.\n",
        provenance.command,
        study.file,
        if unrelaxed > 0 {
            format!(" ({unrelaxed} not relaxed within their scene's time)")
        } else {
            String::new()
        },
        provenance
            .date
            .as_deref()
            .unwrap_or("no date (no run measured)")
    );
    let verdicts: Vec<String> = findings
        .iter()
        .map(|f| format!("{} {}", f.id, f.verdict().text()))
        .collect();
    let _ = writeln!(md, "Verdicts: {}.\n", verdicts.join(", "));
    let _ = writeln!(md, "## How the quantities are measured\n");
    let _ = writeln!(
        md,
        "Every quantity is measured on each realisation (seed) and given as mean +- standard error \
         over the seeds (n = seeds where it could be measured, when fewer than the case's). As \
         `facets analyse`: grains in the frame the run wrote, less 40 mm at each side wall; \
         stresses coarse-grained (Goldhirsch) with w = 4 D for squares, 3 D for rods.\n\n\
         - Load shares: the upward force each boundary exerts on the grains (deposit.contacts.csv, \
         j = -1 left wall, -2 right, -3 floor), over the three together; support/weight is that \
         total over the deposit's weight (1 at rest).\n\
         - Orientation: shares of the grains within {WINDOW_DEG} deg of 45 deg and of flat (0 or 90 deg) for \
         squares; of horizontal, vertical and 2 pi/11 = {STUDY_ROD53_ANGLE_DEG:.1} deg (angle from the horizontal, \
         0-90 deg) for rods; the rods' preferred angle is the mode of that angle in 5-degree bins.\n\
         - g(r), r in grain widths D, read at the bin (width `analysis.rdf_bin_over_d` = {} D) nearest the \
         named distance; centres at least {} D inside the analysed area.\n\
         - Pressure P = -trace/2 on the centre line against the depth h below the free surface; \
         overburden phi_f rho g h with the analysed area's packing fraction phi_f; the Janssen fit \
         P = P_sat (1 - exp(-h/lambda)) down to 2 w above the floor; `saturates` is the fraction of \
         seeds whose lambda lies below the fit's bound of 100 W.\n\
         - A difference counts when it exceeds twice its standard error, sqrt(SE_a^2 + SE_b^2). \
         A finding is reproduced when each of its checks is, not reproduced when one fails, and \
         not measured otherwise (a case or a quantity missing).\n",
        study.analysis.rdf_bin_over_d, study.analysis.rdf_margin_over_d
    );
    cases_table(&mut md, study, stats);
    for f in findings {
        finding_section(&mut md, study, stats, f);
    }
    groups(&mut md, study, stats);
    let _ = writeln!(md, "## Figures\n");
    let _ = writeln!(
        md,
        "![P / overburden against h/W]({}/{PRESSURE_FIGURE})\n\n![Load shares]({}/{LOAD_FIGURE})\n\n\
         Their numbers are in the CSV files beside them.",
        provenance.figures_dir, provenance.figures_dir
    );
    md
}

fn cases_table(md: &mut String, study: &Study, stats: &[CaseStats]) {
    let _ = writeln!(md, "## Cases\n");
    let _ = writeln!(
        md,
        "| # | case | scene | grains | phi0 | silo width (mm) | seeds measured / asked | baseline |"
    );
    let _ = writeln!(md, "|---|---|---|---|---|---|---|---|");
    for (k, (case, s)) in study.cases.iter().zip(stats).enumerate() {
        let _ = writeln!(
            md,
            "| {} | {} | {}{} | {} | {} | {} | {} / {} | {} |",
            k + 1,
            case.name,
            case.scene_file,
            if case.overridden {
                " (with overrides)"
            } else {
                ""
            },
            grains(case),
            case.scene.feed.phi0,
            case.scene.silo.width_mm,
            s.seeds_measured,
            case.seeds.len(),
            case.baseline.as_deref().unwrap_or("")
        );
    }
    let _ = writeln!(md);
}

fn finding_section(md: &mut String, study: &Study, stats: &[CaseStats], f: &Finding) {
    let _ = writeln!(md, "## {} {}\n", f.id, f.title);
    let _ = writeln!(md, "The study: {}\n", f.study_says);
    let labels: Vec<&str> = f.columns.iter().map(|q| q.label()).collect();
    let _ = writeln!(md, "| case | {} |", labels.join(" | "));
    let _ = writeln!(md, "|---|{}", "---|".repeat(f.columns.len()));
    for &(shape, phi0) in &f.rows {
        match find(study, stats, shape, phi0) {
            Some(s) => {
                let asked = study.cases[s.case].seeds.len();
                let cells: Vec<String> = f
                    .columns
                    .iter()
                    .map(|&q| cell(s.get(q), s.seeds_measured.min(asked)))
                    .collect();
                let _ = writeln!(
                    md,
                    "| {} ({} {phi0}, {} seeds) | {} |",
                    study.cases[s.case].name,
                    shape.display_name(),
                    s.seeds_measured,
                    cells.join(" | ")
                );
            }
            None => {
                let _ = writeln!(
                    md,
                    "| {} {phi0}: not measured |{}",
                    shape.display_name(),
                    " |".repeat(f.columns.len())
                );
            }
        }
    }
    let _ = writeln!(md);
    for c in &f.checks {
        let _ = writeln!(
            md,
            "- {}: **{}** ({})",
            c.criterion,
            c.verdict.text(),
            c.evidence
        );
    }
    let _ = writeln!(md, "\n**{} verdict: {}.**\n", f.id, f.verdict().text());
}

/// A section per group of variants: each variant beside its baseline.
fn groups(md: &mut String, study: &Study, stats: &[CaseStats]) {
    let mut names: Vec<String> = Vec::new();
    for case in study.cases.iter().filter(|c| c.is_variant()) {
        let name = group_of(case);
        if !names.contains(&name) {
            names.push(name);
        }
    }
    for name in names {
        let variants: Vec<usize> = (0..study.cases.len())
            .filter(|&k| study.cases[k].is_variant() && group_of(&study.cases[k]) == name)
            .collect();
        let _ = writeln!(md, "## Variants: {name}\n");
        let _ = writeln!(
            md,
            "Each variant beside its baseline; delta/SE is the difference over its standard error.\n"
        );
        // One table per baseline of the group.
        let mut baselines: Vec<usize> = Vec::new();
        for &v in &variants {
            let b = baseline_index(study, v);
            if !baselines.contains(&b) {
                baselines.push(b);
            }
        }
        for b in baselines {
            let mine: Vec<usize> = variants
                .iter()
                .copied()
                .filter(|&v| baseline_index(study, v) == b)
                .collect();
            let base = &stats[b];
            let mut header = format!("| quantity | {} (baseline) |", study.cases[b].name);
            let mut rule = "|---|---|".to_string();
            for &v in &mine {
                let _ = write!(header, " {} | delta/SE |", study.cases[v].name);
                rule.push_str("---|---|");
            }
            let _ = writeln!(md, "{header}\n{rule}");
            let shape = base
                .shape
                .or_else(|| mine.iter().find_map(|&v| stats[v].shape));
            for q in Q::ALL {
                if shape.is_some_and(|s| !q.applies(s)) {
                    continue;
                }
                let mut row = format!(
                    "| {} | {} |",
                    q.label(),
                    cell(base.get(q), study.cases[b].seeds.len())
                );
                for &v in &mine {
                    let _ = write!(
                        row,
                        " {} | {} |",
                        cell(stats[v].get(q), study.cases[v].seeds.len()),
                        difference(stats[v].get(q), base.get(q))
                    );
                }
                let _ = writeln!(md, "{row}");
            }
            let _ = writeln!(md);
        }
    }
}

fn group_of(case: &Case) -> String {
    case.group
        .clone()
        .unwrap_or_else(|| format!("variants of {}", case.baseline.as_deref().unwrap_or("")))
}

fn baseline_index(study: &Study, variant: usize) -> usize {
    let name = study.cases[variant].baseline.as_deref().unwrap_or_default();
    study
        .cases
        .iter()
        .position(|c| c.name == name)
        .unwrap_or(variant)
}

/// (variant - baseline) / sqrt(SE_v^2 + SE_b^2).
fn difference(v: MeanErr, b: MeanErr) -> String {
    let se = v.stderr.hypot(b.stderr);
    let d = v.mean - b.mean;
    if !d.is_finite() {
        "n/a".into()
    } else if se > 0.0 {
        short(d / se)
    } else if d == 0.0 {
        "0".into()
    } else {
        "n/a (no SE)".into()
    }
}
