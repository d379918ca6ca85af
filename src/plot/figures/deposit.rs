use std::path::{Path, PathBuf};

use super::{source_name, tag};
use crate::analysis::summary::EnsembleSummary;
use crate::deposit::{LoadOptions, Source, load_realisation};
use crate::plot::deposit_picture::draw_deposit;

/// The ensemble's example deposit to scale, grains coloured by orientation, force chains:
/// `deposit_SRC_phi0_X.png` (with its tables, see [`draw_deposit`]).
pub fn deposit_figure(out: &Path, source: Source, e: &EnsembleSummary) -> anyhow::Result<PathBuf> {
    let options = LoadOptions {
        fallback_meta: Some(e.example_meta.clone()),
        contacts: e.example_contacts.as_ref().map(PathBuf::from),
    };
    let real = load_realisation(Path::new(&e.example_deposit), &options)?;
    let path = out.join(format!(
        "deposit_{}_{}.png",
        source_name(source),
        tag(e.phi0)
    ));
    draw_deposit(&path, &real, source)?;
    Ok(path)
}
