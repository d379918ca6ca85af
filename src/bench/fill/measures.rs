//! The observables of one ensemble that the bench compares: phi_f, f(theta), g(r) for r < 4 D
//! and the pressure profile, each as mean and standard error over realisations.

use serde::{Deserialize, Serialize};

use crate::analysis::coarse_grain::{CoarseGrainInput, DEFAULT_CUTOFF};
use crate::analysis::orientation::{self, OrientationInput};
use crate::analysis::pressure::{self, PressureInput};
use crate::analysis::rdf::{self, RdfInput};
use crate::analysis::stats::MeanErr;
use crate::deposit::Ensemble;
use crate::grains::GrainKind;

/// g(r) is compared for r < this many grain widths D (issue 3).
pub const RDF_R_MAX: f64 = 4.0;

/// How the observables are measured (the analysis's defaults but for the g(r) margin).
#[derive(Clone, Copy, Debug, Serialize, Deserialize)]
pub struct MeasureInput {
    /// Centres of g(r) must lie this many D inside the analysed area. The bench's deposits are
    /// a few layers deep (150 grains by default), so the analysis's 4 D from the top and the
    /// floor would leave few centres or none; a smaller margin biases g(r) at large r by the
    /// area's edges, the same bias for every setting, so differences between settings still
    /// measure them.
    pub rdf_margin_d: f64,
    /// Coarse-graining width of the pressure in D (docs/model.md §3: 4 for squares, 3 for rods).
    pub w_over_d: Option<f64>,
    /// Spacing of the pressure profile's points in D.
    pub dh_over_d: f64,
}

impl Default for MeasureInput {
    fn default() -> Self {
        MeasureInput {
            rdf_margin_d: 0.0,
            w_over_d: None,
            dh_over_d: 0.5,
        }
    }
}

/// The pressure -sigma_yy on the centre line against depth below the free surface.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct PressureMeasure {
    /// Depth h / W.
    pub depth_over_w: Vec<f64>,
    /// -sigma_yy (N/m).
    pub p: Vec<f64>,
    pub p_err: Vec<f64>,
}

#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Measures {
    pub n_realisations: usize,
    pub phi_f: MeanErr,
    /// f(theta) per bin (integral 1 over a period).
    pub f: Vec<f64>,
    pub f_err: Vec<f64>,
    /// Bin centres of g (D), all below [`RDF_R_MAX`]; empty when no centre was deep enough.
    pub r: Vec<f64>,
    pub g: Vec<f64>,
    pub g_err: Vec<f64>,
    /// None when the deposits have no contact tables.
    pub pressure: Option<PressureMeasure>,
}

impl Measures {
    pub fn of(ensemble: &Ensemble, input: &MeasureInput) -> anyhow::Result<Measures> {
        let d = ensemble.realisations[0].grain_width();
        let o = orientation::compute(&OrientationInput::default(), ensemble)?;
        let rdf_input = RdfInput {
            r_max: RDF_R_MAX,
            margin: input.rdf_margin_d,
            ..RdfInput::default()
        };
        let g = rdf::compute(&rdf_input, ensemble)?;
        let keep =
            g.r.iter()
                .take_while(|&&r| r < RDF_R_MAX)
                .count()
                .min(g.g.len());
        let w_over_d = input.w_over_d.unwrap_or(match ensemble.shape {
            GrainKind::Square => 4.0,
            _ => 3.0,
        });
        let p = pressure::compute(
            &PressureInput {
                coarse_grain: CoarseGrainInput {
                    w: w_over_d * d,
                    cutoff: DEFAULT_CUTOFF,
                },
                dh: input.dh_over_d * d,
            },
            ensemble,
        )?;
        Ok(Measures {
            n_realisations: ensemble.realisations.len(),
            phi_f: g.packing_fraction,
            f: o.f,
            f_err: o.f_err,
            r: g.r[..keep].to_vec(),
            g: g.g[..keep].to_vec(),
            g_err: g.g_err[..keep].to_vec(),
            pressure: p.map(|p| PressureMeasure {
                depth_over_w: p.h_over_w,
                p: p.sigma_yy.iter().map(|s| -s).collect(),
                p_err: p.sigma_yy_err,
            }),
        })
    }
}
