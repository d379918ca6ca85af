//! Stage 4: the same analysis on both sides (`analysis::summary::analyse`, as `facets analyse`),
//! per shape, then both on the same axes (as `facets compare`): f(theta), g(r), g(1) and phi_f
//! against phi0, the w scan, pressure profiles and a deposit picture per side and phi0.

use std::path::{Path, PathBuf};

use anyhow::Context;

use super::detect::Detected;
use super::layout::Layout;
use super::plan::{Plan, ShapePlan};
use super::progress::{Event, Progress};
use super::simulate::{Filled, Side};
use crate::analysis::compare::{Comparison, compare, write_comparison};
use crate::analysis::rdf::RdfInput;
use crate::analysis::summary::{AnalysisParameters, Summary};
use crate::analysis::tables::{Tables, analyse_tables, write_summary};
use crate::grains::GrainKind;
use crate::plot::write_figures;

/// Both sides of one shape, measured.
#[derive(Clone, Debug)]
pub struct ShapeAnalysis {
    pub kind: GrainKind,
    pub simulation: Option<Summary>,
    pub experiment: Option<Summary>,
    pub comparison: Option<Comparison>,
    /// PNG figures, both sides overlaid.
    pub figures: Vec<PathBuf>,
}

/// The analysis parameters of a plan for one shape.
pub fn parameters(plan: &Plan, shape: Option<&ShapePlan>) -> AnalysisParameters {
    AnalysisParameters {
        rdf: RdfInput {
            r_max: plan.rdf_margin_over_d,
            margin: plan.rdf_margin_over_d,
            ..RdfInput::default()
        },
        w_over_d: shape.map(|s| s.w_over_d),
        w_scan_over_d: plan.w_scan_over_d.clone(),
        ..AnalysisParameters::default()
    }
}

/// Analyses every shape that has deposits on either side.
pub fn analyse_all(
    plan: &Plan,
    layout: &Layout,
    filled: &[Filled],
    detected: &[Detected],
    progress: &Progress,
) -> anyhow::Result<Vec<ShapeAnalysis>> {
    let mut kinds: Vec<GrainKind> = plan.shapes.iter().map(|s| s.kind).collect();
    for d in detected {
        if !kinds.contains(&d.kind) {
            kinds.push(d.kind);
        }
    }
    progress(Event::Stage {
        stage: "analyse",
        counts: "shapes",
        total: kinds.len(),
    });
    let mut out = Vec::new();
    for kind in kinds {
        progress(Event::Working(kind.name()));
        let shape = plan.shapes.iter().find(|s| s.kind == kind);
        let params = parameters(plan, shape);
        let sim_tables: Vec<PathBuf> = filled
            .iter()
            .filter(|f| f.filling.kind == kind && f.filling.side == Side::Simulation)
            .map(|f| f.filling.deposit())
            .collect();
        let exp_tables: Vec<PathBuf> = detected
            .iter()
            .filter(|d| d.kind == kind)
            .map(|d| d.table.clone())
            .collect();
        let simulation = side(&sim_tables, &params, &layout.analysis_dir(kind, false))?;
        let experiment = side(&exp_tables, &params, &layout.analysis_dir(kind, true))?;
        let figures_dir = layout.figures_dir(kind);
        std::fs::create_dir_all(&figures_dir)
            .with_context(|| format!("cannot create {}", figures_dir.display()))?;
        let comparison = match (&experiment, &simulation) {
            (Some(e), Some(s)) => {
                let c = compare(e, s)?;
                write_comparison(&figures_dir, &c)?;
                Some(c)
            }
            _ => None,
        };
        let summaries: Vec<&Summary> = experiment.iter().chain(simulation.iter()).collect();
        let figures = if summaries.is_empty() {
            Vec::new()
        } else {
            write_figures(&figures_dir, &summaries)?
        };
        out.push(ShapeAnalysis {
            kind,
            simulation,
            experiment,
            comparison,
            figures,
        });
        progress(Event::Done);
    }
    progress(Event::StageEnd);
    Ok(out)
}

/// One side's ensembles analysed, summary.json written; None without deposits.
fn side(
    tables: &[PathBuf],
    params: &AnalysisParameters,
    dir: &Path,
) -> anyhow::Result<Option<Summary>> {
    if tables.is_empty() {
        return Ok(None);
    }
    let input = Tables {
        tables: tables.to_vec(),
        ..Tables::default()
    };
    let summary = analyse_tables(&input, params, &|_| {})?;
    write_summary(dir, &summary)?;
    Ok(Some(summary))
}
