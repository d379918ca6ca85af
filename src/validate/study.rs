//! A study file: the cases to run and measure (TOML). Each `[[case]]` names a scene file
//! (relative to the study file), its seeds and optional overrides merged into the scene; a
//! case with `baseline` is a variant of one model element, reported beside that case.

use std::path::{Path, PathBuf};

use anyhow::{Context, bail};
use serde::Deserialize;

use crate::scene::{Scene, parse_scene};

/// The study the command runs when none is given: the paper-scale cases of issue 53.
pub const DEFAULT_STUDY: &str = include_str!("../../data-samples/studies/paper.toml");
/// Where the default study stands, for its scene paths.
pub const DEFAULT_STUDY_PATH: &str = concat!(
    env!("CARGO_MANIFEST_DIR"),
    "/data-samples/studies/paper.toml"
);

/// The most seeds one case may ask for.
const MAX_SEEDS: i64 = 10_000;

/// A study, its scenes read and checked.
#[derive(Clone, Debug)]
pub struct Study {
    /// The study file as given (or the default's path).
    pub file: String,
    pub analysis: AnalysisSection,
    pub cases: Vec<Case>,
}

/// One case: a scene (with its overrides) and its seeds.
#[derive(Clone, Debug)]
pub struct Case {
    pub name: String,
    /// The scene file as written in the study, and where it was found.
    pub scene_file: String,
    pub scene_path: PathBuf,
    pub scene: Scene,
    /// The scene with the overrides merged in, as the TOML a run folder keeps
    /// (`facets sim scene.toml --seed N` runs it again).
    pub scene_toml: String,
    pub seeds: Vec<u64>,
    /// The study overrides fields of the scene file.
    pub overridden: bool,
    pub group: Option<String>,
    pub baseline: Option<String>,
}

impl Case {
    /// A variant of another case.
    pub fn is_variant(&self) -> bool {
        self.baseline.is_some()
    }
}

/// `[analysis]`: how the deposits are measured, where the study may differ from the defaults.
#[derive(Clone, Copy, Debug, PartialEq, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct AnalysisSection {
    /// Bin width of g(r), in grain widths D. Default 0.05: the study's peaks at 1.18-1.21,
    /// 1.31 and 1.4 fall in bins of their own.
    pub rdf_bin_over_d: f64,
    /// g(r) counts around centres at least this far inside the analysed area (D). Default 4,
    /// as `facets analyse`.
    pub rdf_margin_over_d: f64,
}

impl Default for AnalysisSection {
    fn default() -> Self {
        Self {
            rdf_bin_over_d: 0.05,
            rdf_margin_over_d: 4.0,
        }
    }
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct StudyFile {
    #[serde(default)]
    analysis: AnalysisSection,
    #[serde(rename = "case", default)]
    cases: Vec<CaseEntry>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct CaseEntry {
    name: String,
    scene: String,
    seeds: toml::Value,
    #[serde(default)]
    group: Option<String>,
    #[serde(default)]
    baseline: Option<String>,
    #[serde(default)]
    overrides: Option<toml::Table>,
}

/// Reads a study file and every scene it names.
pub fn load_study(path: &Path) -> anyhow::Result<Study> {
    let text = std::fs::read_to_string(path)
        .with_context(|| format!("cannot read study file {}", path.display()))?;
    parse_study(&text, &path.display().to_string(), path.parent())
}

/// The built-in study ([`DEFAULT_STUDY`]), its scenes found beside the source tree.
pub fn default_study() -> anyhow::Result<Study> {
    parse_study(
        DEFAULT_STUDY,
        DEFAULT_STUDY_PATH,
        Path::new(DEFAULT_STUDY_PATH).parent(),
    )
}

/// Parses study text; `file` names it in errors, scene paths are relative to `dir`.
pub fn parse_study(text: &str, file: &str, dir: Option<&Path>) -> anyhow::Result<Study> {
    let raw: StudyFile = toml::from_str(text).map_err(|e| {
        let offset = e.span().map_or(0, |s| s.start);
        let (line, column) = line_column(text, offset);
        anyhow::anyhow!("{file}:{line}:{column}: {}", e.message().trim_end())
    })?;
    let a = raw.analysis;
    for (key, value) in [
        ("rdf_bin_over_d", a.rdf_bin_over_d),
        ("rdf_margin_over_d", a.rdf_margin_over_d),
    ] {
        if !(value.is_finite() && value > 0.0) {
            bail!("{file}: field `analysis.{key}` is {value}, expected a positive number");
        }
    }
    if raw.cases.is_empty() {
        bail!("{file}: no `[[case]]`: a study needs at least one case");
    }
    let dir = dir.unwrap_or(Path::new(""));
    let mut cases: Vec<Case> = Vec::new();
    for entry in raw.cases {
        let case = read_case(entry, file, dir)?;
        if cases.iter().any(|c| c.name == case.name) {
            bail!("{file}: two cases are named `{}`", case.name);
        }
        cases.push(case);
    }
    for case in &cases {
        if let Some(b) = &case.baseline {
            match cases.iter().find(|c| &c.name == b) {
                None => bail!(
                    "{file}: case `{}`: field `baseline` names `{b}`, which is not a case of the study",
                    case.name
                ),
                Some(c) if c.is_variant() => bail!(
                    "{file}: case `{}`: field `baseline` names `{b}`, itself a variant of `{}`: a baseline is a case without `baseline`",
                    case.name,
                    c.baseline.as_deref().unwrap_or_default()
                ),
                Some(c) if c.name == case.name => {
                    bail!("{file}: case `{b}` is its own baseline")
                }
                Some(_) => {}
            }
        }
    }
    Ok(Study {
        file: file.to_string(),
        analysis: a,
        cases,
    })
}

fn read_case(entry: CaseEntry, file: &str, dir: &Path) -> anyhow::Result<Case> {
    let name = entry.name;
    let folder_safe = !name.is_empty()
        && name != "."
        && name != ".."
        && name
            .chars()
            .all(|c| c.is_ascii_alphanumeric() || "._-".contains(c));
    if !folder_safe {
        bail!(
            "{file}: case name `{name}`: expected letters, digits, '.', '_' or '-' (it names the case's folder)"
        );
    }
    let scene_path = dir.join(&entry.scene);
    if !scene_path.is_file() {
        bail!(
            "{file}: case `{name}`: scene file {} not found (field `scene` = \"{}\", relative to the study file)",
            scene_path.display(),
            entry.scene
        );
    }
    let scene_text = std::fs::read_to_string(&scene_path).with_context(|| {
        format!(
            "{file}: case `{name}`: cannot read {}",
            scene_path.display()
        )
    })?;
    let (scene, scene_toml) = match &entry.overrides {
        None => {
            let scene = parse_scene(&scene_text, &scene_path.display().to_string())
                .with_context(|| format!("{file}: case `{name}`"))?;
            (scene, scene_text)
        }
        Some(overrides) => {
            let mut table: toml::Table = toml::from_str(&scene_text).map_err(|e| {
                anyhow::anyhow!("{}: {}", scene_path.display(), e.message().trim_end())
            })?;
            merge(&mut table, overrides);
            let merged = toml::to_string(&table)
                .with_context(|| format!("{file}: case `{name}`: cannot write the merged scene"))?;
            let label = format!(
                "{} with the overrides of case `{name}`",
                scene_path.display()
            );
            let scene = parse_scene(&merged, &label).with_context(|| {
                format!("{file}: case `{name}`: field `overrides` gives a bad scene")
            })?;
            let text = format!(
                "# {} with the overrides of case `{name}` of study {file}\n{merged}",
                entry.scene
            );
            (scene, text)
        }
    };
    let seeds = seeds_of(&entry.seeds, scene.run.seed)
        .map_err(|e| anyhow::anyhow!("{file}: case `{name}`: field `seeds` {e}"))?;
    Ok(Case {
        name,
        scene_file: entry.scene,
        scene_path,
        scene,
        scene_toml,
        seeds,
        overridden: entry.overrides.is_some(),
        group: entry.group,
        baseline: entry.baseline,
    })
}

/// A count (seeds `first`, `first` + 1, ...) or a list of distinct seeds.
fn seeds_of(value: &toml::Value, first: u64) -> Result<Vec<u64>, String> {
    match value {
        toml::Value::Integer(n) if (1..=MAX_SEEDS).contains(n) => {
            Ok((0..*n as u64).map(|k| first + k).collect())
        }
        toml::Value::Integer(n) => Err(format!(
            "is {n}, expected a count of realisations from 1 to {MAX_SEEDS} (or a list of seeds)"
        )),
        toml::Value::Array(list) if !list.is_empty() => {
            let mut seeds = Vec::new();
            for v in list {
                match v.as_integer() {
                    Some(s) if s >= 0 && !seeds.contains(&(s as u64)) => seeds.push(s as u64),
                    Some(s) if s >= 0 => return Err(format!("lists seed {s} twice")),
                    _ => return Err(format!("holds {v}, expected seeds (integers >= 0)")),
                }
            }
            Ok(seeds)
        }
        other => Err(format!(
            "is {other}, expected a count of realisations (1 to {MAX_SEEDS}) or a non-empty list of seeds"
        )),
    }
}

/// Merges `overrides` into `base`: tables key by key, recursively; anything else replaced.
pub fn merge(base: &mut toml::Table, overrides: &toml::Table) {
    for (key, value) in overrides {
        match (base.get_mut(key), value) {
            (Some(toml::Value::Table(b)), toml::Value::Table(o)) => merge(b, o),
            _ => {
                base.insert(key.clone(), value.clone());
            }
        }
    }
}

/// 1-based line and column of a byte offset.
fn line_column(text: &str, offset: usize) -> (usize, usize) {
    let before = &text[..offset.min(text.len())];
    let line = before.matches('\n').count() + 1;
    let column = before.len() - before.rfind('\n').map_or(0, |p| p + 1) + 1;
    (line, column)
}

#[cfg(test)]
mod tests {
    use super::*;

    const SCENE: &str = "[silo]\nwidth_mm = 96\n\n[grains]\nkind = \"square\"\ncount = 50\n\n[feed]\nphi0 = 0.05\n\n[run]\nseed = 3\n";

    fn study_dir() -> tempfile::TempDir {
        let dir = tempfile::tempdir().unwrap();
        std::fs::create_dir(dir.path().join("scenes")).unwrap();
        std::fs::write(dir.path().join("scenes/s.toml"), SCENE).unwrap();
        dir
    }

    fn parse(text: &str, dir: &Path) -> anyhow::Result<Study> {
        parse_study(text, "study.toml", Some(dir))
    }

    #[test]
    fn overrides_merge_into_the_scene_and_seeds_count_from_its_seed() {
        let dir = study_dir();
        let text = r#"
[[case]]
name = "base"
scene = "scenes/s.toml"
seeds = 2

[[case]]
name = "wide-rough"
scene = "scenes/s.toml"
seeds = [7, 9]
group = "walls"
baseline = "base"
[case.overrides.silo]
width_mm = 128
[case.overrides.contact]
friction = 0.6
"#;
        let s = parse(text, dir.path()).unwrap();
        let (base, wide) = (&s.cases[0], &s.cases[1]);
        assert_eq!(base.seeds, vec![3, 4]);
        assert_eq!(wide.seeds, vec![7, 9]);
        assert_eq!(base.scene.silo.width_mm, 96.0);
        // The override replaces one field and keeps its section's others.
        assert_eq!(wide.scene.silo.width_mm, 128.0);
        assert_eq!(wide.scene.silo.height_mm, base.scene.silo.height_mm);
        assert_eq!(wide.scene.grains.count, 50);
        assert_eq!(wide.scene.contact.friction, 0.6);
        assert_eq!(
            base.scene.contact.friction,
            sim::ContactLaw::default().friction
        );
        assert!(wide.is_variant() && !base.is_variant());
        assert_eq!(wide.group.as_deref(), Some("walls"));
        // The merged scene written beside a run reads back as the same scene.
        let again = parse_scene(&wide.scene_toml, "again").unwrap();
        assert_eq!(again, wide.scene);
        assert_eq!(s.analysis, AnalysisSection::default());
    }

    #[test]
    fn the_default_study_reads_with_its_shipped_scenes() {
        let s = default_study().unwrap();
        assert_eq!(s.cases.len(), 7);
        for c in &s.cases {
            let squares = c.scene.grains.kind == crate::grains::GrainKind::Square;
            assert!(c.seeds.len() >= if squares { 6 } else { 3 }, "{}", c.name);
            assert!(!c.is_variant());
        }
    }

    #[test]
    fn errors_name_the_file_and_the_field() {
        let dir = study_dir();
        let case = "[[case]]\nname = \"a\"\nscene = \"scenes/s.toml\"\nseeds = 2\n";
        let err = |text: &str| parse(text, dir.path()).unwrap_err();
        let e = format!("{:#}", err(&format!("{case}colour = 3\n")));
        assert!(
            e.starts_with("study.toml:5:") && e.contains("colour"),
            "{e}"
        );
        let e = format!("{:#}", err(&format!("title = 1\n{case}")));
        assert!(e.starts_with("study.toml:1:") && e.contains("title"), "{e}");
        let e = format!("{:#}", err(&case.replace("seeds = 2", "seeds = 0")));
        assert!(e.contains("`a`") && e.contains("`seeds` is 0"), "{e}");
        let e = format!("{:#}", err(&case.replace("seeds = 2", "seeds = [1, 1]")));
        assert!(e.contains("twice"), "{e}");
        let e = format!("{:#}", err(&case.replace("seeds = 2", "seeds = \"many\"")));
        assert!(e.contains("`seeds`"), "{e}");
        let e = format!("{:#}", err(&case.replace("s.toml", "missing.toml")));
        assert!(e.contains("missing.toml") && e.contains("not found"), "{e}");
        let e = format!(
            "{:#}",
            err(&format!("{case}[case.overrides.silo]\nwidht_mm = 100\n"))
        );
        assert!(
            e.contains("overrides") && e.contains("silo.widht_mm"),
            "{e}"
        );
        let e = format!(
            "{:#}",
            err(&format!("{case}[case.overrides.feed]\nphi0 = 2.0\n"))
        );
        assert!(e.contains("feed.phi0"), "{e}");
        let e = format!("{:#}", err(&format!("{case}baseline = \"zzz\"\n")));
        assert!(e.contains("`baseline`") && e.contains("zzz"), "{e}");
        let e = format!("{:#}", err(&format!("{case}{case}")));
        assert!(e.contains("two cases"), "{e}");
        let e = format!("{:#}", err(&case.replace("\"a\"", "\"a/b\"")));
        assert!(e.contains("case name"), "{e}");
        let e = format!("{:#}", err("[analysis]\nrdf_bin_over_d = 0\n"));
        assert!(e.contains("analysis.rdf_bin_over_d"), "{e}");
        let e = format!("{:#}", err(""));
        assert!(e.contains("no `[[case]]`"), "{e}");
    }
}
