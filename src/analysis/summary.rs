//! Every measure of every ensemble of one analysis run: what `facets analyse` writes to
//! summary.json and `facets compare` reads back.

use anyhow::bail;
use serde::{Deserialize, Serialize};

use super::coarse_grain::{CoarseGrainInput, DEFAULT_CUTOFF};
use super::orientation::{self, OrientationInput, OrientationResult};
use super::pressure::{self, PressureInput, PressureProfile};
use super::rdf::{self, RdfInput, RdfResult};
use crate::deposit::{DepositMeta, Ensemble, Source};
use crate::grains::GrainKind;

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

/// Ranges of the parameters: beyond them a measure means nothing, or its grids grow without
/// bound (a width or spacing of zero would take forever, a huge cut-off would fill memory).
const W_OVER_D: (f64, f64) = (0.1, 100.0);
const CUTOFF: (f64, f64) = (1.0, 10.0);
const DH_OVER_D: (f64, f64) = (0.01, 100.0);
const RDF_DR: (f64, f64) = (0.001, 10.0);
/// r_max's lower bound is 1.5 dr, one bin.
const RDF_R_MAX: (f64, f64) = (0.0, 100.0);
const RDF_MARGIN: (f64, f64) = (0.0, 1000.0);
/// Orientation bins from 0.01 degree to a whole period of the squares (pi/2).
const BIN_WIDTH: (f64, f64) = (
    0.01 * std::f64::consts::PI / 180.0,
    std::f64::consts::FRAC_PI_2,
);

impl AnalysisParameters {
    /// Checks every number, naming the parameter (and its `facets analyse` option, if it has
    /// one) and the range expected.
    pub fn validate(&self) -> anyhow::Result<()> {
        if let Some(w) = self.w_over_d {
            in_range(
                "--w-over-d (coarse-graining width w, in grain widths D)",
                w,
                W_OVER_D,
            )?;
        }
        for &w in &self.w_scan_over_d {
            in_range(
                "--w-scan (a coarse-graining width of the scan, in grain widths D)",
                w,
                W_OVER_D,
            )?;
        }
        in_range(
            "--cutoff (kernel cut-off, in multiples of w)",
            self.cutoff,
            CUTOFF,
        )?;
        in_range(
            "dh_over_d (spacing of the pressure profile's points, in D)",
            self.dh_over_d,
            DH_OVER_D,
        )?;
        in_range(
            "orientation.bin_width (bin width of f(theta), rad)",
            self.orientation.bin_width,
            BIN_WIDTH,
        )?;
        in_range("rdf.dr (bin width of g(r), in D)", self.rdf.dr, RDF_DR)?;
        in_range(
            "rdf.r_max (largest r of g(r), in D)",
            self.rdf.r_max,
            RDF_R_MAX,
        )?;
        if self.rdf.r_max < 1.5 * self.rdf.dr {
            bail!(
                "rdf.r_max (largest r of g(r), in D) is {}, expected at least 1.5 bin widths \
                 (rdf.dr = {}) to hold one bin",
                self.rdf.r_max,
                self.rdf.dr
            );
        }
        in_range(
            "rdf.margin (least distance of a reference grain from the area's edges, in D)",
            self.rdf.margin,
            RDF_MARGIN,
        )?;
        Ok(())
    }

    pub fn w_over_d_for(&self, shape: GrainKind) -> f64 {
        self.w_over_d.unwrap_or(match shape {
            GrainKind::Square => 4.0,
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
    pub shape: GrainKind,
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
    parameters.validate()?;
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

/// An error naming `what` unless `value` is a finite number in [lo, hi].
fn in_range(what: &str, value: f64, (lo, hi): (f64, f64)) -> anyhow::Result<()> {
    if !(value.is_finite() && value >= lo && value <= hi) {
        bail!("{what} is {value}, expected a finite number from {lo} to {hi}");
    }
    Ok(())
}
