//! Experiment against simulation, ensemble against ensemble (docs/model.md §5): for each phi0 both have,
//! the difference of each scalar observable in units of the combined standard error.

use std::path::{Path, PathBuf};

use serde::{Deserialize, Serialize};

use super::stats::MeanErr;
use super::summary::Summary;

#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct Difference {
    pub observable: String,
    pub experiment: MeanErr,
    pub simulation: MeanErr,
    /// (sim - exp) / sqrt(err_exp^2 + err_sim^2); None when both errors are 0.
    pub z: Option<f64>,
}

#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct PhiComparison {
    pub phi0: f64,
    pub differences: Vec<Difference>,
}

#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct Comparison {
    pub per_phi0: Vec<PhiComparison>,
}

fn difference(name: &str, e: MeanErr, s: MeanErr) -> Difference {
    let err = e.stderr.hypot(s.stderr);
    Difference {
        observable: name.to_string(),
        experiment: e,
        simulation: s,
        z: (err > 0.0 && err.is_finite()).then(|| (s.mean - e.mean) / err),
    }
}

/// Refuses summaries of different shapes.
pub fn compare(experiment: &Summary, simulation: &Summary) -> anyhow::Result<Comparison> {
    if experiment.shape != simulation.shape {
        anyhow::bail!(
            "the experiment holds {} but the simulation holds {}",
            experiment.shape.display_name(),
            simulation.shape.display_name()
        );
    }
    let mut per_phi0 = Vec::new();
    for e in &experiment.ensembles {
        let Some(s) = simulation
            .ensembles
            .iter()
            .find(|s| (s.phi0 - e.phi0).abs() < 1e-9)
        else {
            continue;
        };
        let mut differences = vec![
            difference("phi_f", e.rdf.packing_fraction, s.rdf.packing_fraction),
            difference("g_at_1", e.rdf.g_at_1, s.rdf.g_at_1),
            difference("S4", e.orientation.s4, s.orientation.s4),
        ];
        if let (Some(a), Some(b)) = (e.orientation.s2, s.orientation.s2) {
            differences.push(difference("S2", a, b));
        }
        per_phi0.push(PhiComparison {
            phi0: e.phi0,
            differences,
        });
    }
    Ok(Comparison { per_phi0 })
}

/// Writes `dir/comparison.json`.
pub fn write_comparison(dir: &Path, comparison: &Comparison) -> anyhow::Result<PathBuf> {
    let path = dir.join("comparison.json");
    crate::io::write_atomic(&path, |w| {
        serde_json::to_writer_pretty(&mut *w, comparison)?;
        Ok(())
    })?;
    Ok(path)
}
