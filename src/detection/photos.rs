//! The photographs of a batch: which files, where each one's table goes, and reading them.

use std::collections::HashMap;
use std::path::{Path, PathBuf};

use anyhow::{Context, bail};

use crate::deposit::meta_path;

/// The photographs named: files as given, folders expanded to the PNG/TIFF/JPEG files they
/// hold (sorted, so a batch runs in a reproducible order).
pub fn collect_photos(inputs: &[PathBuf]) -> anyhow::Result<Vec<PathBuf>> {
    let mut photos = Vec::new();
    for input in inputs {
        if input.is_dir() {
            let mut found: Vec<PathBuf> = std::fs::read_dir(input)
                .with_context(|| format!("cannot read folder {}", input.display()))?
                .filter_map(|e| e.ok().map(|e| e.path()))
                .filter(|p| p.is_file() && is_photo(p))
                .collect();
            found.sort();
            photos.extend(found);
        } else {
            photos.push(input.clone());
        }
    }
    Ok(photos)
}

fn is_photo(path: &Path) -> bool {
    let ext = path
        .extension()
        .and_then(|e| e.to_str())
        .unwrap_or("")
        .to_ascii_lowercase();
    matches!(ext.as_str(), "png" | "tif" | "tiff" | "jpg" | "jpeg")
}

/// The stem of a photograph's outputs: its file name without the extension.
pub fn stem(photo: &Path) -> &str {
    photo
        .file_stem()
        .and_then(|s| s.to_str())
        .unwrap_or("photo")
}

/// Where the table of each photograph goes: `out/<stem>.csv`. Refuses, before any detecting,
/// a batch in which two photographs would write the same table (`c1/p.png` and `c2/p.png`, or
/// `p.png` and `p.tif`): the second would overwrite the first.
pub fn table_paths(photos: &[PathBuf], out: &Path) -> anyhow::Result<Vec<PathBuf>> {
    let mut first: HashMap<PathBuf, &Path> = HashMap::new();
    let mut tables = Vec::with_capacity(photos.len());
    for photo in photos {
        let table = out.join(format!("{}.csv", stem(photo)));
        if let Some(earlier) = first.get(&table) {
            bail!(
                "photographs {} and {} would both write {}: detect them into different --out \
                 folders (one run per folder), or rename one",
                earlier.display(),
                photo.display(),
                table.display()
            );
        }
        first.insert(table.clone(), photo);
        tables.push(table);
    }
    Ok(tables)
}

/// Refuses, unless `overwrite`, a batch whose outputs exist already (a table, its sidecar or
/// its overlay): an earlier run into the same folder may have written them from another
/// photograph of the same name (`c1/p.png` then, in a second run, `c2/p.png`), and nothing
/// in a table says which photograph it came from. Checked before any detecting.
pub fn refuse_existing(tables: &[PathBuf], overwrite: bool) -> anyhow::Result<()> {
    if overwrite {
        return Ok(());
    }
    let existing: Vec<PathBuf> = tables
        .iter()
        .flat_map(|t| [t.clone(), meta_path(t), overlay_path(t)])
        .filter(|p| p.exists())
        .collect();
    if let Some(first) = existing.first() {
        let more = match existing.len() {
            1 => String::new(),
            n => format!(" (and {} more outputs of this batch)", n - 1),
        };
        bail!(
            "{} exists already{more}: an earlier run wrote it, perhaps from another photograph \
             of the same name; give --overwrite to replace it, or another --out folder",
            first.display()
        );
    }
    Ok(())
}

/// The overlay beside a table: `<stem>_overlay.png`.
pub fn overlay_path(table: &Path) -> PathBuf {
    table.with_file_name(format!("{}_overlay.png", stem(table)))
}

/// Decodes a photograph, refusing one larger than `max_pixels` before decoding it.
pub fn read_photo(path: &Path, max_pixels: u64) -> anyhow::Result<image::DynamicImage> {
    let open = || {
        image::ImageReader::open(path)
            .and_then(|r| r.with_guessed_format())
            .with_context(|| format!("cannot open photograph {}", path.display()))
    };
    let (w, h) = open()?.into_dimensions().with_context(|| {
        format!(
            "{} is not a readable PNG, TIFF or JPEG image",
            path.display()
        )
    })?;
    if w as u64 * h as u64 > max_pixels {
        bail!(
            "{} is {w} x {h} px; at most {} megapixels are accepted (larger photographs are \
             processed in tiles, but their decoded pixels alone would not fit in memory): split \
             it into overlapping parts",
            path.display(),
            max_pixels / 1_000_000
        );
    }
    open()?.decode().with_context(|| {
        format!(
            "{} is not a readable PNG, TIFF or JPEG image",
            path.display()
        )
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn same_named_photographs_are_refused_naming_both() {
        let out = Path::new("d");
        let photos = [PathBuf::from("c1/p.png"), PathBuf::from("c2/q.png")];
        let tables = table_paths(&photos, out).unwrap();
        assert_eq!(tables, [out.join("p.csv"), out.join("q.csv")]);
        for other in ["c2/p.png", "c1/p.tif"] {
            let photos = [PathBuf::from("c1/p.png"), PathBuf::from(other)];
            let e = table_paths(&photos, out).unwrap_err().to_string();
            assert!(
                e.contains("c1/p.png") && e.contains(other) && e.contains("p.csv"),
                "{e}"
            );
        }
        assert_eq!(
            overlay_path(Path::new("d/p.csv")),
            Path::new("d/p_overlay.png")
        );
    }
}
