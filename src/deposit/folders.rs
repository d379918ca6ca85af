//! Deposit tables named by the user: files as given, folders opened, ensembles as `facets sim`
//! writes them (`DIR/seed-N/deposit.csv`) included.

use std::path::{Path, PathBuf};

use anyhow::Context;

/// Deposit tables under `paths`: files as given; a folder gives its `*.csv` tables (files
/// named `*.contacts.csv` and `*.grains.csv` are sidecars, not deposits) and those of its
/// `seed-N/` subfolders (an ensemble as `facets sim --realisations` writes it), in the order
/// of N. A folder with neither is refused by name.
pub fn deposit_tables(paths: &[PathBuf]) -> anyhow::Result<Vec<PathBuf>> {
    let mut out = Vec::new();
    for p in paths {
        if !p.is_dir() {
            out.push(p.clone());
            continue;
        }
        let mut found = tables_in(p)?;
        for (_, seed_dir) in seed_folders(p)? {
            found.extend(tables_in(&seed_dir)?);
        }
        if found.is_empty() {
            anyhow::bail!(
                "{}: no deposit tables (*.csv) in this folder or in seed-N/ folders inside it",
                p.display()
            );
        }
        out.extend(found);
    }
    Ok(out)
}

fn entries(dir: &Path) -> anyhow::Result<Vec<PathBuf>> {
    Ok(std::fs::read_dir(dir)
        .with_context(|| format!("cannot list {}", dir.display()))?
        .filter_map(|e| e.ok().map(|e| e.path()))
        .collect())
}

/// The deposit tables directly in `dir`, sorted.
fn tables_in(dir: &Path) -> anyhow::Result<Vec<PathBuf>> {
    let mut found: Vec<PathBuf> = entries(dir)?
        .into_iter()
        .filter(|f| {
            let name = f.file_name().map(|n| n.to_string_lossy().into_owned());
            f.is_file()
                && name.is_some_and(|n| {
                    n.ends_with(".csv")
                        && !n.ends_with(".contacts.csv")
                        && !n.ends_with(".grains.csv")
                })
        })
        .collect();
    found.sort();
    Ok(found)
}

/// The `seed-N/` folders in `dir`, by N.
fn seed_folders(dir: &Path) -> anyhow::Result<Vec<(u64, PathBuf)>> {
    let mut seeds: Vec<(u64, PathBuf)> = entries(dir)?
        .into_iter()
        .filter(|p| p.is_dir())
        .filter_map(|p| {
            let name = p.file_name()?.to_str()?;
            let seed = name.strip_prefix("seed-")?.parse().ok()?;
            Some((seed, p))
        })
        .collect();
    seeds.sort();
    Ok(seeds)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn an_ensemble_folder_gives_its_seeds_tables_in_order() {
        let dir = tempfile::tempdir().unwrap();
        for seed in [2, 10, 1] {
            let d = dir.path().join(format!("seed-{seed}"));
            std::fs::create_dir_all(&d).unwrap();
            for name in ["deposit.csv", "deposit.contacts.csv", "deposit.meta.json"] {
                std::fs::write(d.join(name), "").unwrap();
            }
        }
        std::fs::create_dir_all(dir.path().join("seed-x")).unwrap();
        std::fs::write(dir.path().join("seed-x/deposit.csv"), "").unwrap();
        let found = deposit_tables(&[dir.path().to_path_buf()]).unwrap();
        let seeds: Vec<&Path> = found
            .iter()
            .map(|p| p.strip_prefix(dir.path()).unwrap())
            .collect();
        assert_eq!(
            seeds,
            [
                "seed-1/deposit.csv",
                "seed-2/deposit.csv",
                "seed-10/deposit.csv"
            ]
            .map(Path::new)
        );
        let empty = tempfile::tempdir().unwrap();
        let e = deposit_tables(&[empty.path().to_path_buf()])
            .unwrap_err()
            .to_string();
        assert!(
            e.contains("seed-N") && e.contains(&empty.path().display().to_string()),
            "{e}"
        );
    }
}
