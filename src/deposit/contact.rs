//! The contact table of a simulated deposit (docs/model.md §4): one row per contact,
//! `i,j,fx_N,fy_N,cx_mm,cy_mm`, the force on grain i from j (or from a wall) applied at (cx, cy).

use std::io::Read;
use std::path::Path;

use anyhow::{Context, bail};
use serde::Deserialize;

use crate::io::write_atomic;

const MM: f64 = 1e-3;

/// What a grain touches: another grain (by row index in the deposit table) or a wall.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Partner {
    Grain(usize),
    Wall(Wall),
}

/// The silo's boundaries, with the negative `j` that names them in a contact table.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Wall {
    /// j = -1
    Left,
    /// j = -2
    Right,
    /// j = -3
    Floor,
}

impl Wall {
    pub fn code(self) -> i64 {
        match self {
            Wall::Left => -1,
            Wall::Right => -2,
            Wall::Floor => -3,
        }
    }

    fn from_code(j: i64) -> Option<Wall> {
        match j {
            -1 => Some(Wall::Left),
            -2 => Some(Wall::Right),
            -3 => Some(Wall::Floor),
            _ => None,
        }
    }
}

/// One contact, SI units: the force on grain `i` from `partner`, applied at `point`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Contact {
    pub i: usize,
    pub partner: Partner,
    /// Force on grain i (N).
    pub force: [f64; 2],
    /// Contact point (m), same frame as the grain centres.
    pub point: [f64; 2],
}

impl Contact {
    pub fn magnitude(&self) -> f64 {
        self.force[0].hypot(self.force[1])
    }
}

#[derive(Debug, Deserialize)]
struct Row {
    i: i64,
    j: i64,
    #[serde(rename = "fx_N")]
    fx: f64,
    #[serde(rename = "fy_N")]
    fy: f64,
    cx_mm: f64,
    cy_mm: f64,
}

const COLUMNS: [&str; 6] = ["i", "j", "fx_N", "fy_N", "cx_mm", "cy_mm"];

/// Reads a contact table for a deposit of `n_grains` grains. Errors name the file, the line and
/// the field: a missing column, a non-finite number, a grain index outside the deposit, an
/// unknown wall code, a grain touching itself, or an empty table.
pub fn read_contacts_csv(path: &Path, n_grains: usize) -> anyhow::Result<Vec<Contact>> {
    let file =
        std::fs::File::open(path).with_context(|| format!("cannot open {}", path.display()))?;
    parse_contacts_csv(file, n_grains)
        .with_context(|| format!("in contact table {}", path.display()))
}

pub(crate) fn parse_contacts_csv<R: Read>(
    input: R,
    n_grains: usize,
) -> anyhow::Result<Vec<Contact>> {
    let mut reader = csv::ReaderBuilder::new()
        .trim(csv::Trim::All)
        .from_reader(input);
    let headers = reader
        .headers()
        .context("cannot read the header line")?
        .clone();
    for needed in COLUMNS {
        if !headers.iter().any(|h| h == needed) {
            bail!(
                "line 1: missing column `{needed}` (the header must contain {}; found {})",
                COLUMNS.join(","),
                headers.iter().collect::<Vec<_>>().join(",")
            );
        }
    }
    let mut contacts = Vec::new();
    for (index, record) in reader.deserialize::<Row>().enumerate() {
        let line = index + 2;
        let row =
            record.map_err(|e| anyhow::anyhow!("line {line}: {}", csv_error_text(&e, &headers)))?;
        for (name, value) in [
            ("fx_N", row.fx),
            ("fy_N", row.fy),
            ("cx_mm", row.cx_mm),
            ("cy_mm", row.cy_mm),
        ] {
            if !value.is_finite() {
                bail!("line {line}: field `{name}` is {value}, expected a finite number");
            }
        }
        let grain_index = |field: &str, k: i64| -> anyhow::Result<usize> {
            if k < 0 || k as usize >= n_grains {
                bail!(
                    "line {line}: field `{field}` is {k}, but the deposit has grains 0..{} only",
                    n_grains.saturating_sub(1)
                );
            }
            Ok(k as usize)
        };
        let i = grain_index("i", row.i)?;
        let partner = if row.j >= 0 {
            let j = grain_index("j", row.j)?;
            if j == i {
                bail!("line {line}: fields `i` and `j` are both {i}: a grain cannot touch itself");
            }
            Partner::Grain(j)
        } else {
            match Wall::from_code(row.j) {
                Some(w) => Partner::Wall(w),
                None => bail!(
                    "line {line}: field `j` is {}, expected a grain index or a wall (-1 left, -2 right, -3 floor)",
                    row.j
                ),
            }
        };
        contacts.push(Contact {
            i,
            partner,
            force: [row.fx, row.fy],
            point: [row.cx_mm * MM, row.cy_mm * MM],
        });
    }
    if contacts.is_empty() {
        bail!("the table has no contacts (a deposit at rest has at least its floor contacts)");
    }
    Ok(contacts)
}

fn csv_error_text(e: &csv::Error, headers: &csv::StringRecord) -> String {
    match e.kind() {
        csv::ErrorKind::Deserialize { err, .. } => match err.field() {
            Some(field) => format!(
                "field `{}`: {}",
                headers.get(field as usize).unwrap_or("?"),
                err.kind()
            ),
            None => err.kind().to_string(),
        },
        _ => e.to_string(),
    }
}

/// Writes a contact table atomically (docs/model.md §4 columns).
pub fn write_contacts_csv(path: &Path, contacts: &[Contact]) -> anyhow::Result<()> {
    write_atomic(path, |out| {
        let mut w = csv::Writer::from_writer(out);
        w.write_record(COLUMNS)?;
        for c in contacts {
            let j = match c.partner {
                Partner::Grain(j) => j as i64,
                Partner::Wall(wall) => wall.code(),
            };
            w.write_record([
                c.i.to_string(),
                j.to_string(),
                format!("{:e}", c.force[0]),
                format!("{:e}", c.force[1]),
                format!("{:.6}", c.point[0] / MM),
                format!("{:.6}", c.point[1] / MM),
            ])?;
        }
        w.flush()?;
        Ok(())
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn round_trip_keeps_walls_and_forces() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("c.csv");
        let contacts = vec![
            Contact {
                i: 0,
                partner: Partner::Grain(1),
                force: [0.25, -1.5e-3],
                point: [0.01, 0.02],
            },
            Contact {
                i: 1,
                partner: Partner::Wall(Wall::Floor),
                force: [0.0, 0.3],
                point: [0.011, 0.0],
            },
        ];
        write_contacts_csv(&path, &contacts).unwrap();
        let back = read_contacts_csv(&path, 2).unwrap();
        assert_eq!(back.len(), 2);
        assert_eq!(back[1].partner, Partner::Wall(Wall::Floor));
        assert_eq!(back[0].force, contacts[0].force);
        assert!((back[0].point[1] - 0.02).abs() < 1e-12);
    }

    #[test]
    fn errors_name_line_and_field() {
        let head = "i,j,fx_N,fy_N,cx_mm,cy_mm\n";
        let err = |body: &str, n: usize| {
            format!(
                "{:#}",
                parse_contacts_csv(format!("{head}{body}").as_bytes(), n).unwrap_err()
            )
        };
        let e = err("0,1,1,1,0,0\n0,5,1,1,0,0\n", 2);
        assert!(
            e.contains("line 3") && e.contains("`j`") && e.contains("5"),
            "{e}"
        );
        let e = err("0,1,1,NaN,0,0\n", 2);
        assert!(e.contains("line 2") && e.contains("fy_N"), "{e}");
        let e = err("0,-7,1,1,0,0\n", 2);
        assert!(e.contains("line 2") && e.contains("wall"), "{e}");
        let e = err("", 2);
        assert!(e.contains("no contacts"), "{e}");
        let e = err("0,1,x,1,0,0\n", 2);
        assert!(e.contains("line 2") && e.contains("fx_N"), "{e}");
        let e = format!(
            "{:#}",
            parse_contacts_csv("i,j,fx_N,fy_N,cx_mm\n".as_bytes(), 2).unwrap_err()
        );
        assert!(e.contains("cy_mm"), "{e}");
    }
}
