use std::path::Path;

use anyhow::{Context, bail};

use super::Scene;
use super::validate::{Invalid, validate};

/// Reads, parses and checks a scene file. Errors read `FILE:LINE:COLUMN: field `section.key`:
/// what is wrong`.
pub fn load_scene(path: &Path) -> anyhow::Result<Scene> {
    let text = std::fs::read_to_string(path)
        .with_context(|| format!("cannot read scene file {}", path.display()))?;
    parse_scene(&text, &path.display().to_string())
}

/// Parses and checks scene text; `file` names it in errors.
pub fn parse_scene(text: &str, file: &str) -> anyhow::Result<Scene> {
    let scene: Scene = match toml::from_str(text) {
        Ok(s) => s,
        Err(e) => {
            let offset = e.span().map_or(0, |s| s.start);
            let (line, column) = line_column(text, offset);
            let field = field_at(text, line);
            bail!("{file}:{line}:{column}: {field}{}", e.message().trim_end());
        }
    };
    if let Err(Invalid {
        section,
        key,
        message,
    }) = validate(&scene)
    {
        let place = match locate(text, section, key) {
            Some(line) => format!("{file}:{line}"),
            None => format!("{file} (default value)"),
        };
        bail!("{place}: field `{section}.{key}`: {message}");
    }
    Ok(scene)
}

/// 1-based line and column of a byte offset.
fn line_column(text: &str, offset: usize) -> (usize, usize) {
    let before = &text[..offset.min(text.len())];
    let line = before.matches('\n').count() + 1;
    let column = before.len() - before.rfind('\n').map_or(0, |p| p + 1) + 1;
    (line, column)
}

/// "field `section.key`: " for the key written on `line` (the error's span points at a key or
/// its value), or "" when the line holds no key (a missing field: the message names it).
fn field_at(text: &str, line: usize) -> String {
    let Some(this) = text.lines().nth(line - 1) else {
        return String::new();
    };
    let section = section_before(text, line);
    let key = this
        .split_once('=')
        .map(|(k, _)| k.trim().trim_matches('"').to_string());
    match key {
        Some(k) if !k.is_empty() && !k.starts_with('[') => {
            format!("field `{}{k}`: ", prefix(&section))
        }
        _ if !section.is_empty() => format!("in section `[{section}]`: "),
        _ => String::new(),
    }
}

fn prefix(section: &str) -> String {
    if section.is_empty() {
        String::new()
    } else {
        format!("{section}.")
    }
}

/// The `[section]` header in force at `line` (1-based), "" before any.
fn section_before(text: &str, line: usize) -> String {
    text.lines()
        .take(line)
        .filter_map(header)
        .last()
        .unwrap_or_default()
}

fn header(l: &str) -> Option<String> {
    let t = l.trim();
    (t.starts_with('[') && t.ends_with(']'))
        .then(|| t.trim_matches(|c| c == '[' || c == ']').trim().to_string())
}

/// The line where `key` is set inside `[section]`, if the file sets it.
fn locate(text: &str, section: &str, key: &str) -> Option<usize> {
    let mut current = String::new();
    for (k, l) in text.lines().enumerate() {
        if let Some(h) = header(l) {
            current = h;
            continue;
        }
        if current == section {
            if let Some((name, _)) = l.split_once('=') {
                if name.trim().trim_matches('"') == key {
                    return Some(k + 1);
                }
            }
        }
    }
    None
}

#[cfg(test)]
mod tests {
    use super::*;

    const GOOD: &str = "[grains]\nkind = \"square\"\ncount = 100\n\n[feed]\nphi0 = 0.05\n";

    #[test]
    fn defaults_are_the_papers() {
        let s = parse_scene(GOOD, "good.toml").unwrap();
        assert_eq!(s.silo.width_mm, 256.0);
        assert_eq!(s.feed.speed_m_s, 3.5);
        assert_eq!(s.contact.law(), sim::ContactLaw::default());
        assert_eq!(s.run.relaxation_ratio, 1e-4);
    }

    #[test]
    fn errors_name_file_line_and_field() {
        let e = parse_scene(&GOOD.replace("0.05", "\"a lot\""), "s.toml")
            .unwrap_err()
            .to_string();
        assert!(
            e.starts_with("s.toml:6:") && e.contains("`feed.phi0`"),
            "{e}"
        );
        let e = parse_scene(&format!("{GOOD}colour = 3\n"), "s.toml")
            .unwrap_err()
            .to_string();
        assert!(e.starts_with("s.toml:7:") && e.contains("colour"), "{e}");
        let e = parse_scene(&GOOD.replace("0.05", "1.5"), "s.toml")
            .unwrap_err()
            .to_string();
        assert!(
            e.starts_with("s.toml:6:") && e.contains("`feed.phi0`"),
            "{e}"
        );
        let e = parse_scene(&GOOD.replace("count = 100", "count = 0"), "s.toml")
            .unwrap_err()
            .to_string();
        assert!(
            e.starts_with("s.toml:3:") && e.contains("`grains.count`"),
            "{e}"
        );
        let e = parse_scene("[grains]\nkind = \"square\"\ncount = 10\n", "s.toml")
            .unwrap_err()
            .to_string();
        assert!(e.contains("feed"), "{e}");
        let e = parse_scene(&GOOD.replace("square", "hexagon"), "s.toml")
            .unwrap_err()
            .to_string();
        assert!(
            e.starts_with("s.toml:2:") && e.contains("`grains.kind`"),
            "{e}"
        );
    }
}
