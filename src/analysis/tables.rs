//! Deposit tables to a summary, as `facets analyse` and `facets reproduce` both do it: load
//! each table with its sidecars, group the deposits into ensembles by phi0, analyse each
//! ensemble ([`analyse`]), and write `summary.json`.

use std::path::{Path, PathBuf};

use anyhow::Context;

use super::summary::{AnalysisParameters, Summary, analyse};
use crate::deposit::{DepositMeta, Ensemble, LoadOptions, Source, contacts_path, load_realisation};
use crate::io::write_atomic;

/// The tables to analyse and what stands in for what they lack.
#[derive(Clone, Debug, Default)]
pub struct Tables {
    pub tables: Vec<PathBuf>,
    /// Contact tables, none or one per table in the same order (default: `NAME.contacts.csv`
    /// when it exists).
    pub contacts: Vec<PathBuf>,
    /// The sidecar of tables without `NAME.meta.json`.
    pub fallback_meta: Option<DepositMeta>,
}

/// How far the work is, for a progress display.
#[derive(Clone, Copy, Debug)]
pub enum Step {
    /// `done` of `total` tables read.
    Loaded { done: usize, total: usize },
    /// `done` of `total` ensembles analysed.
    Analysed { done: usize, total: usize },
}

/// Analyses the tables: one ensemble per phi0, each named in the summary by its first
/// deposit (absolute paths of the table and its contacts).
pub fn analyse_tables(
    input: &Tables,
    parameters: &AnalysisParameters,
    progress: &dyn Fn(Step),
) -> anyhow::Result<Summary> {
    let total = input.tables.len();
    if !input.contacts.is_empty() && input.contacts.len() != total {
        anyhow::bail!(
            "--contacts gives {} tables for {total} deposits: give one per deposit, in the same \
             order",
            input.contacts.len(),
        );
    }
    parameters.validate()?;
    let mut realisations = Vec::with_capacity(total);
    let mut examples = std::collections::HashMap::new();
    for (k, table) in input.tables.iter().enumerate() {
        let contacts = input.contacts.get(k).cloned();
        let options = LoadOptions {
            fallback_meta: input.fallback_meta.clone(),
            contacts: contacts.clone(),
        };
        let real = load_realisation(table, &options)?;
        let contacts = contacts.or_else(|| {
            let p = contacts_path(table);
            p.exists().then_some(p)
        });
        examples.insert(
            real.name.clone(),
            (absolute(table), contacts.map(|c| absolute(&c))),
        );
        realisations.push(real);
        progress(Step::Loaded { done: k + 1, total });
    }
    let ensembles = Ensemble::group_by_phi0(realisations)?;
    let examples: Vec<(String, Option<String>)> = ensembles
        .iter()
        .map(|e| examples[&e.realisations[0].name].clone())
        .collect();
    let count = ensembles.len();
    analyse(&ensembles, &examples, parameters, &|done| {
        progress(Step::Analysed { done, total: count })
    })
}

/// Reads `dir/summary.json` as `facets analyse` wrote it, drawn as `source` whatever its
/// deposits' sidecars said (the side of a comparison decides the style).
pub fn read_summary(dir: &Path, source: Source) -> anyhow::Result<Summary> {
    let path = dir.join("summary.json");
    let text = std::fs::read_to_string(&path).with_context(|| {
        format!(
            "cannot open {} (give the output folder of `facets analyse`)",
            path.display()
        )
    })?;
    let mut summary: Summary =
        serde_json::from_str(&text).with_context(|| format!("in {}", path.display()))?;
    summary.source = source;
    Ok(summary)
}

/// Writes `dir/summary.json` (the folder created if missing).
pub fn write_summary(dir: &Path, summary: &Summary) -> anyhow::Result<PathBuf> {
    std::fs::create_dir_all(dir).with_context(|| format!("cannot create {}", dir.display()))?;
    let path = dir.join("summary.json");
    write_atomic(&path, |w| {
        serde_json::to_writer_pretty(&mut *w, summary)?;
        Ok(())
    })?;
    Ok(path)
}

fn absolute(p: &Path) -> String {
    std::fs::canonicalize(p)
        .unwrap_or_else(|_| p.to_path_buf())
        .display()
        .to_string()
}
