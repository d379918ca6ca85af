//! Every measure of every ensemble of one analysis run: what `facets analyse` writes to
//! summary.json and `facets compare` reads back.

use serde::{Deserialize, Serialize};

use super::coarse_grain::{CoarseGrainInput, DEFAULT_CUTOFF};
use super::orientation::{self, OrientationInput, OrientationResult};
use super::pressure::{self, PressureInput, PressureProfile};
use super::rdf::{self, RdfInput, RdfResult};
use crate::deposit::{DepositMeta, Ensemble, Shape, Source};

#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct AnalysisParameters {
    pub orientation: OrientationInput,
    pub rdf: RdfInput,
    /// Coarse-graining width in grain widths D; None = docs/model.md's 4 D for squares, 3 D for rods.
    pub w_over_d: Option<f64>,
    /// The widths of the scan over w, in D.
    pub w_scan_over_d: Vec<f64>,
    /// Kernel cut-off in multiples of w.
    pub cutoff: f64,
    /// Spacing of the pressure profile's points, in D.
    pub dh_over_d: f64,
}

impl Default for AnalysisParameters {
    fn default() -> Self {
        AnalysisParameters {
            orientation: OrientationInput::default(),
            rdf: RdfInput::default(),
            w_over_d: None,
            w_scan_over_d: vec![1.0, 2.0, 3.0, 4.0, 6.0],
            cutoff: DEFAULT_CUTOFF,
            dh_over_d: 0.5,
        }
    }
}

impl AnalysisParameters {
    pub fn w_over_d_for(&self, shape: Shape) -> f64 {
        self.w_over_d.unwrap_or(match shape {
            Shape::Square => 4.0,
            _ => 3.0,
        })
    }
}

#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct EnsembleSummary {
    pub phi0: f64,
    pub n_realisations: usize,
    /// Median grain width D (m) of the first realisation.
    pub grain_width: f64,
    pub orientation: OrientationResult,
    pub rdf: RdfResult,
    /// At the main w; None without contacts.
    pub pressure: Option<PressureProfile>,
    pub w_scan: Vec<PressureProfile>,
    /// The realisation drawn in the deposit picture, and what is needed to read it again.
    pub example_deposit: String,
    pub example_contacts: Option<String>,
    pub example_meta: DepositMeta,
}

#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct Summary {
    pub shape: Shape,
    pub source: Source,
    pub parameters: AnalysisParameters,
    pub ensembles: Vec<EnsembleSummary>,
}

/// Runs every measure on each ensemble; `done` is called after each ensemble (progress).
/// `example` gives, per ensemble, the deposit file and contact file of its first realisation.
pub fn analyse(
    ensembles: &[Ensemble],
    examples: &[(String, Option<String>)],
    parameters: &AnalysisParameters,
    done: &dyn Fn(usize),
) -> anyhow::Result<Summary> {
    let Some(first) = ensembles.first() else {
        anyhow::bail!("nothing to analyse: no deposits");
    };
    if examples.len() != ensembles.len() {
        anyhow::bail!(
            "{} example files for {} ensembles: give one per ensemble",
            examples.len(),
            ensembles.len()
        );
    }
    let mut out = Vec::new();
    for (k, ensemble) in ensembles.iter().enumerate() {
        let d = ensemble.realisations[0].grain_width();
        let cg = |w_over_d: f64| CoarseGrainInput {
            w: w_over_d * d,
            cutoff: parameters.cutoff,
        };
        let base = PressureInput {
            coarse_grain: cg(parameters.w_over_d_for(ensemble.shape)),
            dh: parameters.dh_over_d * d,
        };
        let ws: Vec<f64> = parameters.w_scan_over_d.iter().map(|x| x * d).collect();
        let (example_deposit, example_contacts) = examples[k].clone();
        out.push(EnsembleSummary {
            phi0: ensemble.phi0,
            n_realisations: ensemble.realisations.len(),
            grain_width: d,
            orientation: orientation::compute(&parameters.orientation, ensemble)?,
            rdf: rdf::compute(&parameters.rdf, ensemble)?,
            pressure: pressure::compute(&base, ensemble)?,
            w_scan: pressure::w_scan(&ws, &base, ensemble)?,
            example_deposit,
            example_contacts,
            example_meta: ensemble.realisations[0].meta.clone(),
        });
        done(k + 1);
    }
    Ok(Summary {
        shape: first.shape,
        source: first.source,
        parameters: parameters.clone(),
        ensembles: out,
    })
}
