//! `--photos DIR`: real photographs as the experiment side, listed in `DIR/manifest.csv` or
//! `DIR/manifest.toml`. Each photograph: `file` (relative to DIR), `shape` (square, rod53,
//! rod3), `phi0`, `px_per_mm`; optionally `silo_width_mm` (default 258, the experiment's) and
//! `frame_y_mm` (height of the photograph's bottom edge above the floor, default 290: region
//! E). The photograph spans the silo's full width from its left wall. A `NAME.truth.csv`
//! beside a photograph (a deposit table in frame coordinates) makes the report score the
//! detector on it. Every error names the manifest, its line and the field.
//!
//! ```text
//! file,shape,phi0,px_per_mm
//! run01.png,square,0.1,10
//! ```
//! ```toml
//! [[photo]]
//! file = "run01.png"
//! shape = "square"
//! phi0 = 0.1
//! px_per_mm = 10
//! ```

use std::path::{Path, PathBuf};

use anyhow::{Context, bail};
use serde::Deserialize;

use super::photograph::Photo;
use crate::grains::GrainKind;

const EXPERIMENT_SILO_WIDTH_MM: f64 = 258.0;
const REGION_E_BOTTOM_MM: f64 = 290.0;

#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
struct Entry {
    file: String,
    shape: String,
    phi0: f64,
    px_per_mm: f64,
    #[serde(default)]
    silo_width_mm: Option<f64>,
    #[serde(default)]
    frame_y_mm: Option<f64>,
}

#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
struct TomlManifest {
    photo: Vec<Entry>,
}

/// Reads the manifest of `dir` (manifest.csv or manifest.toml).
pub fn read_manifest(dir: &Path) -> anyhow::Result<Vec<Photo>> {
    let csv = dir.join("manifest.csv");
    let toml = dir.join("manifest.toml");
    let photos = match (csv.exists(), toml.exists()) {
        (true, true) => bail!(
            "{} has both manifest.csv and manifest.toml: keep one",
            dir.display()
        ),
        (true, false) => read_csv(dir, &csv)?,
        (false, true) => read_toml(dir, &toml)?,
        (false, false) => bail!(
            "{}: no manifest.csv or manifest.toml (columns file,shape,phi0,px_per_mm)",
            dir.display()
        ),
    };
    if photos.is_empty() {
        bail!("{}: the manifest lists no photograph", dir.display());
    }
    Ok(photos)
}

fn read_csv(dir: &Path, path: &Path) -> anyhow::Result<Vec<Photo>> {
    let file =
        std::fs::File::open(path).with_context(|| format!("cannot open {}", path.display()))?;
    let mut reader = csv::ReaderBuilder::new()
        .trim(csv::Trim::All)
        .from_reader(file);
    let headers = reader
        .headers()
        .with_context(|| format!("{}:1: cannot read the header", path.display()))?
        .clone();
    let known = [
        "file",
        "shape",
        "phi0",
        "px_per_mm",
        "silo_width_mm",
        "frame_y_mm",
    ];
    for h in &headers {
        if !known.contains(&h) {
            bail!(
                "{}:1: unknown column `{h}`; expected {}",
                path.display(),
                known.join(", ")
            );
        }
    }
    for required in &known[..4] {
        if !headers.iter().any(|h| h == *required) {
            bail!("{}:1: missing column `{required}`", path.display());
        }
    }
    let mut photos = Vec::new();
    for record in reader.records() {
        let record = record.with_context(|| format!("in {}", path.display()))?;
        let line = record.position().map_or(0, |p| p.line());
        let at = |name: &str| {
            headers
                .iter()
                .position(|h| h == name)
                .and_then(|k| record.get(k))
                .filter(|v| !v.is_empty())
        };
        let number = |name: &str| -> anyhow::Result<Option<f64>> {
            at(name)
                .map(|v| {
                    v.parse::<f64>().map_err(|_| {
                        anyhow::anyhow!(
                            "{}:{line}: field `{name}`: `{v}` is not a number",
                            path.display()
                        )
                    })
                })
                .transpose()
        };
        let need = |name: &str| -> anyhow::Result<f64> {
            number(name)?
                .with_context(|| format!("{}:{line}: field `{name}` is empty", path.display()))
        };
        let entry = Entry {
            file: at("file")
                .with_context(|| format!("{}:{line}: field `file` is empty", path.display()))?
                .to_string(),
            shape: at("shape").unwrap_or_default().to_string(),
            phi0: need("phi0")?,
            px_per_mm: need("px_per_mm")?,
            silo_width_mm: number("silo_width_mm")?,
            frame_y_mm: number("frame_y_mm")?,
        };
        photos.push(check(dir, &entry).with_context(|| format!("{}:{line}", path.display()))?);
    }
    Ok(photos)
}

fn read_toml(dir: &Path, path: &Path) -> anyhow::Result<Vec<Photo>> {
    let text =
        std::fs::read_to_string(path).with_context(|| format!("cannot open {}", path.display()))?;
    let manifest: TomlManifest = match toml::from_str(&text) {
        Ok(m) => m,
        Err(e) => {
            let offset = e.span().map_or(0, |s| s.start);
            let line = text[..offset.min(text.len())].matches('\n').count() + 1;
            bail!("{}:{line}: {}", path.display(), e.message().trim_end());
        }
    };
    // Line of the k-th [[photo]] table, to name it in errors found after parsing.
    let headers: Vec<usize> = text
        .lines()
        .enumerate()
        .filter(|(_, l)| l.trim() == "[[photo]]")
        .map(|(k, _)| k + 1)
        .collect();
    manifest
        .photo
        .iter()
        .enumerate()
        .map(|(k, entry)| {
            check(dir, entry).with_context(|| match headers.get(k) {
                Some(line) => format!("{}:{line}", path.display()),
                None => format!("{} (photo {})", path.display(), k + 1),
            })
        })
        .collect()
}

/// Checks one entry's fields, naming the one that is wrong.
fn check(dir: &Path, e: &Entry) -> anyhow::Result<Photo> {
    let kind = e.shape.parse::<GrainKind>().ok().with_context(|| {
        format!(
            "field `shape`: `{}` is not a grain shape; expected square, rod53 or rod3",
            e.shape
        )
    })?;
    if !(e.phi0.is_finite() && e.phi0 > 0.0 && e.phi0 < 1.0) {
        bail!(
            "field `phi0`: {} is not a volume fraction in (0, 1)",
            e.phi0
        );
    }
    if !(e.px_per_mm.is_finite() && e.px_per_mm > 0.0) {
        bail!("field `px_per_mm`: {} is not a positive scale", e.px_per_mm);
    }
    let silo_width_mm = e.silo_width_mm.unwrap_or(EXPERIMENT_SILO_WIDTH_MM);
    if !(silo_width_mm.is_finite() && silo_width_mm > 80.0) {
        bail!(
            "field `silo_width_mm`: {silo_width_mm} mm, expected more than 80 mm (40 mm are cut at each wall)"
        );
    }
    let y0 = e.frame_y_mm.unwrap_or(REGION_E_BOTTOM_MM);
    if !(y0.is_finite() && y0 >= 0.0) {
        bail!("field `frame_y_mm`: {y0}, expected a height above the floor (mm)");
    }
    let path = dir.join(&e.file);
    if !path.is_file() {
        bail!("field `file`: {} does not exist", path.display());
    }
    let truth = crate::photo::truth_path(&path);
    Ok(Photo {
        kind,
        phi0: e.phi0,
        truth: truth.exists().then_some(truth),
        path: PathBuf::from(&path),
        px_per_mm: e.px_per_mm,
        silo_width_mm,
        origin_mm: [0.0, y0],
        seed: 0,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn dir_with(name: &str, text: &str) -> tempfile::TempDir {
        let dir = tempfile::tempdir().unwrap();
        std::fs::write(dir.path().join(name), text).unwrap();
        std::fs::write(dir.path().join("a.png"), b"not read here").unwrap();
        dir
    }

    #[test]
    fn csv_and_toml_manifests_read_the_same_photograph() {
        let csv = dir_with(
            "manifest.csv",
            "file,shape,phi0,px_per_mm\na.png,rod53,0.25,8\n",
        );
        let toml = dir_with(
            "manifest.toml",
            "[[photo]]\nfile = \"a.png\"\nshape = \"rod53\"\nphi0 = 0.25\npx_per_mm = 8\n",
        );
        for dir in [&csv, &toml] {
            let photos = read_manifest(dir.path()).unwrap();
            assert_eq!(photos.len(), 1);
            let p = &photos[0];
            assert_eq!(p.kind, GrainKind::ShortRod);
            assert_eq!((p.phi0, p.px_per_mm), (0.25, 8.0));
            assert_eq!(p.origin_mm, [0.0, 290.0]);
            assert_eq!(p.silo_width_mm, 258.0);
            assert!(p.truth.is_none());
        }
    }

    #[test]
    fn errors_name_the_file_line_and_field() {
        let cases = [
            (
                "manifest.csv",
                "file,shape,phi0,px_per_mm\na.png,square,0.1,10\na.png,square,0.1,ten\n",
                ":3",
                "px_per_mm",
            ),
            (
                "manifest.csv",
                "file,shape,phi0,px_per_mm\na.png,hexagon,0.1,10\n",
                ":2",
                "shape",
            ),
            (
                "manifest.csv",
                "file,shape,phi0,px_per_mm\nb.png,square,0.1,10\n",
                ":2",
                "file",
            ),
            (
                "manifest.toml",
                "[[photo]]\nfile = \"a.png\"\nshape = \"square\"\nphi0 = 0.1\npx_per_mm = 10\n\n[[photo]]\nfile = \"a.png\"\nshape = \"square\"\nphi0 = 2\npx_per_mm = 10\n",
                ":7",
                "phi0",
            ),
            (
                "manifest.toml",
                "[[photo]]\nfile = \"a.png\"\nshape = \"square\"\nphi = 0.1\npx_per_mm = 10\n",
                ":4",
                "phi",
            ),
        ];
        for (name, text, line, field) in cases {
            let dir = dir_with(name, text);
            let e = format!("{:#}", read_manifest(dir.path()).unwrap_err());
            assert!(
                e.contains(&format!("{name}{line}")) && e.contains(field),
                "{name}: {e}"
            );
        }
    }
}
