use serde::{Deserialize, Serialize};

use crate::deposit::FrameMm;
use crate::scene::{Insertion, Scene};

/// `run.json`: what was run and what came out.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct RunRecord {
    pub facets_version: String,
    pub scene: Scene,
    pub seed: u64,
    /// How the insertion band was placed ("surface": following the free surface at a gap).
    pub insertion: Insertion,
    /// Poured grains (the deposit).
    pub grains: usize,
    /// Fixed grains the floor and side walls are built of (0 for flat walls).
    #[serde(default)]
    pub wall_grains: usize,
    pub time_step_s: f64,
    pub steps: u64,
    /// Grains in the silo summed over the steps (the engine benchmark's unit of work); 0 in
    /// records written before it was counted.
    #[serde(default)]
    pub grain_steps: u64,
    pub simulated_time_s: f64,
    /// Simulated time of the last insertion (s).
    pub fill_time_s: f64,
    /// True when kinetic < relaxation_ratio x elastic was reached; false when the relaxation
    /// time ran out first.
    pub relaxed: bool,
    /// Wall time of the run (s), summed over the sessions of a run stopped and resumed.
    pub wall_time_s: f64,
    pub energies: EnergiesRecord,
    /// v phi0 W / A (grains per second).
    pub feed_rate_target_per_s: f64,
    /// Slope of the cumulative count of inserted grains against time (grains per second);
    /// NaN (null in JSON) with fewer than two insertion bands.
    #[serde(deserialize_with = "nan_if_null")]
    pub feed_rate_measured_per_s: f64,
    pub band_height_mm: f64,
    pub insertion_events: usize,
    /// Packing fraction of the analysed area (frame less 40 mm at each side wall; NaN when
    /// the silo is too narrow for one; null in JSON).
    #[serde(deserialize_with = "nan_if_null")]
    pub packing_fraction: f64,
    /// The frame written to the sidecar.
    pub frame_mm: Option<FrameMm>,
    /// Top of the highest grain (mm).
    pub deposit_height_mm: f64,
    /// True when the deposit reaches above the silo's height.
    pub overflow: bool,
    /// Total weight of the grains (N).
    pub weight_n: f64,
    /// Force the grains exert on the floor, the left and the right wall, [x, y] (N).
    pub floor_load_n: [f64; 2],
    pub left_wall_load_n: [f64; 2],
    pub right_wall_load_n: [f64; 2],
    /// Force the grains exert on the plates of a quasi-2D cell, [x, y] (N); zero without
    /// `[plates]` friction.
    #[serde(default)]
    pub plate_load_n: [f64; 2],
    /// Deepest overlap of any grain-grain or grain-wall sub-contact at the end (mm).
    pub deepest_overlap_mm: f64,
}

/// Final energies (J).
#[derive(Clone, Copy, Debug, Serialize, Deserialize)]
pub struct EnergiesRecord {
    pub kinetic_j: f64,
    pub elastic_j: f64,
    pub potential_j: f64,
    pub switching_j: f64,
}

/// JSON has no NaN: serde_json writes it as null; read null back as NaN.
fn nan_if_null<'de, D: serde::Deserializer<'de>>(d: D) -> Result<f64, D::Error> {
    Ok(Option::<f64>::deserialize(d)?.unwrap_or(f64::NAN))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_record_with_nan_fields_reads_back() {
        #[derive(Serialize, Deserialize)]
        struct Probe {
            #[serde(deserialize_with = "nan_if_null")]
            value: f64,
        }
        let text = serde_json::to_string(&Probe { value: f64::NAN }).unwrap();
        assert_eq!(text, r#"{"value":null}"#);
        let back: Probe = serde_json::from_str(&text).unwrap();
        assert!(back.value.is_nan());
        let back: Probe = serde_json::from_str(r#"{"value":0.5}"#).unwrap();
        assert_eq!(back.value, 0.5);
    }
}
