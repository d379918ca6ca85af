//! The raw measures of every realisation (OUT/results.csv, OUT/results.json) and their mean
//! and standard error per case.

use std::path::Path;

use serde_json::{Map, Value, json};

use super::measures::{Measures, PROFILE_POINTS, PROFILE_STEP_OVER_W, Q};
use super::study::Study;
use crate::analysis::stats::MeanErr;
use crate::grains::GrainKind;
use crate::io::write_atomic;

/// One measured realisation.
#[derive(Clone, Debug)]
pub struct Measured {
    pub case: usize,
    pub seed: u64,
    pub shape: GrainKind,
    pub phi0: f64,
    pub relaxed: bool,
    pub grains: usize,
    pub measures: Measures,
}

/// One case over its measured seeds.
#[derive(Clone, Debug)]
pub struct CaseStats {
    pub case: usize,
    /// The scene's shape; None when no seed is measured.
    pub shape: Option<GrainKind>,
    pub seeds_measured: usize,
    pub unrelaxed: usize,
    /// Per [`Q`], over the seeds where it is finite.
    pub values: Vec<MeanErr>,
    /// P / overburden at h = k PROFILE_STEP W, k = 1..
    pub profile: Vec<MeanErr>,
}

impl CaseStats {
    pub fn get(&self, q: Q) -> MeanErr {
        self.values[q.index()]
    }
}

fn finite_mean(values: impl Iterator<Item = f64>) -> MeanErr {
    let v: Vec<f64> = values.filter(|x| x.is_finite()).collect();
    MeanErr::of(&v)
}

/// The statistics of each case of the study, in its order.
pub fn case_stats(study: &Study, measured: &[Measured]) -> Vec<CaseStats> {
    (0..study.cases.len())
        .map(|k| {
            let mine: Vec<&Measured> = measured.iter().filter(|m| m.case == k).collect();
            CaseStats {
                case: k,
                shape: mine.first().map(|m| m.shape),
                seeds_measured: mine.len(),
                unrelaxed: mine.iter().filter(|m| !m.relaxed).count(),
                values: Q::ALL
                    .iter()
                    .map(|&q| finite_mean(mine.iter().map(|m| m.measures.get(q))))
                    .collect(),
                profile: (0..PROFILE_POINTS)
                    .map(|p| finite_mean(mine.iter().map(|m| m.measures.profile[p])))
                    .collect(),
            }
        })
        .collect()
}

fn number(x: f64) -> String {
    if x.is_finite() {
        format!("{x}")
    } else {
        String::new()
    }
}

/// results.csv: one row per case and seed, a column per quantity (empty where it does not
/// apply or could not be measured).
pub fn write_results_csv(path: &Path, study: &Study, measured: &[Measured]) -> anyhow::Result<()> {
    write_atomic(path, |out| {
        let mut w = csv::Writer::from_writer(out);
        let mut header = vec!["case", "seed", "shape", "phi0", "relaxed", "grains"];
        header.extend(Q::ALL.iter().map(|q| q.name()));
        w.write_record(&header)?;
        for m in measured {
            let mut row = vec![
                study.cases[m.case].name.clone(),
                m.seed.to_string(),
                m.shape.display_name().to_string(),
                number(m.phi0),
                m.relaxed.to_string(),
                m.grains.to_string(),
            ];
            row.extend(Q::ALL.iter().map(|&q| number(m.measures.get(q))));
            w.write_record(&row)?;
        }
        w.flush()?;
        Ok(())
    })
}

/// results.json: the same rows, with each realisation's pressure profile.
pub fn write_results_json(path: &Path, study: &Study, measured: &[Measured]) -> anyhow::Result<()> {
    let value = |x: f64| if x.is_finite() { json!(x) } else { Value::Null };
    let rows: Vec<Value> = measured
        .iter()
        .map(|m| {
            let mut quantities = Map::new();
            for q in Q::ALL {
                quantities.insert(q.name().to_string(), value(m.measures.get(q)));
            }
            json!({
                "case": study.cases[m.case].name,
                "seed": m.seed,
                "shape": m.shape,
                "phi0": m.phi0,
                "relaxed": m.relaxed,
                "grains": m.grains,
                "quantities": quantities,
                "p_over_overburden_profile": m.measures.profile.iter().map(|&x| value(x)).collect::<Vec<_>>(),
            })
        })
        .collect();
    let doc = json!({
        "study": study.file,
        "profile_h_over_w_step": PROFILE_STEP_OVER_W,
        "realisations": rows,
    });
    write_atomic(path, |w| {
        serde_json::to_writer_pretty(&mut *w, &doc)?;
        Ok(())
    })
}
