use std::path::{Path, PathBuf};

use anyhow::{Context, bail};

use super::meta::{DepositMeta, Source, contacts_path, meta_path, read_meta_json};
use super::{AnalysedArea, Contact, Deposit, read_contacts_csv, read_deposit_csv};
use crate::grains::GrainKind;

/// One filling: its grains, its contacts when simulated, and its sidecar.
#[derive(Clone, Debug)]
pub struct Realisation {
    pub name: String,
    pub deposit: Deposit,
    pub contacts: Option<Vec<Contact>>,
    pub meta: DepositMeta,
    pub shape: GrainKind,
}

impl Realisation {
    pub fn analysed_area(&self) -> anyhow::Result<AnalysedArea> {
        AnalysedArea::new(self.meta.frame(&self.deposit), self.meta.silo_width())
            .with_context(|| format!("deposit {}", self.name))
    }

    /// Median grain width D (robust to a few badly detected grains).
    pub fn grain_width(&self) -> f64 {
        median(self.deposit.grains.iter().map(|g| g.width).collect())
    }

    /// Mass of each grain from its outline and the areal density.
    pub fn masses(&self) -> Vec<f64> {
        let rho = self.meta.areal_density(self.shape);
        self.deposit
            .grains
            .iter()
            .map(|g| rho * g.length * g.width)
            .collect()
    }
}

fn median(mut v: Vec<f64>) -> f64 {
    v.sort_by(f64::total_cmp);
    v[v.len() / 2]
}

/// How to find a deposit's sidecars; the command line fills what a sidecar does not give.
#[derive(Clone, Debug, Default)]
pub struct LoadOptions {
    /// Used when `NAME.meta.json` is absent.
    pub fallback_meta: Option<DepositMeta>,
    /// An explicit contact table (else `NAME.contacts.csv` when it exists).
    pub contacts: Option<PathBuf>,
}

/// Reads `path` and its sidecars (see the module doc of `deposit::meta`).
pub fn load_realisation(path: &Path, options: &LoadOptions) -> anyhow::Result<Realisation> {
    let deposit = read_deposit_csv(path)?;
    let shape = GrainKind::of_deposit(&deposit)
        .with_context(|| format!("in deposit table {}", path.display()))?;
    let sidecar = meta_path(path);
    let meta = if sidecar.exists() {
        read_meta_json(&sidecar)?
    } else {
        match &options.fallback_meta {
            Some(m) => m.clone(),
            None => bail!(
                "{}: no sidecar {} and no --phi0/--silo-width-mm given: the analysed area and phi0 are unknown",
                path.display(),
                sidecar.display()
            ),
        }
    };
    let contacts_file = options.contacts.clone().or_else(|| {
        let p = contacts_path(path);
        p.exists().then_some(p)
    });
    let contacts = match contacts_file {
        Some(p) => Some(read_contacts_csv(&p, deposit.grains.len())?),
        None => None,
    };
    Ok(Realisation {
        name: path.display().to_string(),
        deposit,
        contacts,
        meta,
        shape,
    })
}

/// Many realisations of one (shape, phi0) from one source.
#[derive(Clone, Debug)]
pub struct Ensemble {
    pub shape: GrainKind,
    pub phi0: f64,
    pub source: Source,
    pub realisations: Vec<Realisation>,
}

impl Ensemble {
    /// Refuses an empty ensemble, mixed shapes, mixed phi0 and mixed sources, naming the
    /// realisation that differs from the first.
    pub fn new(realisations: Vec<Realisation>) -> anyhow::Result<Self> {
        let Some(first) = realisations.first() else {
            bail!("an ensemble needs at least one deposit");
        };
        let (shape, phi0, source) = (first.shape, first.meta.phi0, first.meta.source);
        for r in &realisations {
            if r.shape != shape {
                bail!(
                    "mixed shapes in one ensemble: {} holds {} but {} holds {}",
                    first.name,
                    shape.display_name(),
                    r.name,
                    r.shape.display_name()
                );
            }
            if (r.meta.phi0 - phi0).abs() > 1e-9 {
                bail!(
                    "mixed phi0 in one ensemble: {} has phi0 = {} but {} has {}",
                    first.name,
                    phi0,
                    r.name,
                    r.meta.phi0
                );
            }
            if r.meta.source != source {
                bail!(
                    "experiment and simulation mixed in one ensemble: {} and {}",
                    first.name,
                    r.name
                );
            }
        }
        Ok(Ensemble {
            shape,
            phi0,
            source,
            realisations,
        })
    }

    /// Groups realisations by phi0 (ascending) into ensembles; all must share one shape.
    pub fn group_by_phi0(mut realisations: Vec<Realisation>) -> anyhow::Result<Vec<Ensemble>> {
        realisations.sort_by(|a, b| a.meta.phi0.total_cmp(&b.meta.phi0));
        let mut groups: Vec<Vec<Realisation>> = Vec::new();
        for r in realisations {
            match groups.last_mut() {
                Some(g) if (g[0].meta.phi0 - r.meta.phi0).abs() <= 1e-9 => g.push(r),
                _ => groups.push(vec![r]),
            }
        }
        let ensembles = groups
            .into_iter()
            .map(Ensemble::new)
            .collect::<anyhow::Result<Vec<_>>>()?;
        if let Some(e) = ensembles.iter().find(|e| e.shape != ensembles[0].shape) {
            bail!(
                "mixed shapes: phi0 = {} holds {} but phi0 = {} holds {}",
                ensembles[0].phi0,
                ensembles[0].shape.display_name(),
                e.phi0,
                e.shape.display_name()
            );
        }
        Ok(ensembles)
    }
}
