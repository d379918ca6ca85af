use std::io::Read;
use std::path::Path;

use anyhow::{Context, bail};
use serde::Deserialize;

use super::Grain;
use crate::io::write_atomic;

const MM: f64 = 1e-3;

/// A deposit: the grains of one photograph or one simulated filling.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Deposit {
    pub grains: Vec<Grain>,
}

/// One row of a deposit CSV. Extra columns written by the detector are optional.
#[derive(Debug, Deserialize)]
struct Row {
    x_mm: f64,
    y_mm: f64,
    theta_rad: f64,
    length_mm: f64,
    width_mm: f64,
    #[serde(default)]
    confidence: Option<f64>,
    #[serde(default)]
    cut: Option<u8>,
}

/// Reads a deposit table (docs/model.md §4). Errors name the file, the line and the field.
pub fn read_deposit_csv(path: &Path) -> anyhow::Result<Deposit> {
    let file =
        std::fs::File::open(path).with_context(|| format!("cannot open {}", path.display()))?;
    parse_deposit_csv(file).with_context(|| format!("in deposit table {}", path.display()))
}

/// Reads a deposit table held in memory; errors name it `name`, the line and the field.
pub fn parse_deposit_text(text: &str, name: &str) -> anyhow::Result<Deposit> {
    parse_deposit_csv(text.as_bytes()).with_context(|| format!("in deposit table {name}"))
}

fn parse_deposit_csv<R: Read>(input: R) -> anyhow::Result<Deposit> {
    let mut reader = csv::ReaderBuilder::new()
        .trim(csv::Trim::All)
        .from_reader(input);
    let headers = reader
        .headers()
        .context("cannot read the header line")?
        .clone();
    for needed in ["x_mm", "y_mm", "theta_rad", "length_mm", "width_mm"] {
        if !headers.iter().any(|h| h == needed) {
            bail!(
                "line 1: missing column `{needed}` (the header must contain x_mm,y_mm,theta_rad,length_mm,width_mm; found {})",
                headers.iter().collect::<Vec<_>>().join(",")
            );
        }
    }
    let mut grains = Vec::new();
    for (index, record) in reader.deserialize::<Row>().enumerate() {
        let line = index + 2;
        let row = record.map_err(|e| anyhow::anyhow!("line {line}: {}", csv_error_text(&e)))?;
        let fields = [
            ("x_mm", row.x_mm),
            ("y_mm", row.y_mm),
            ("theta_rad", row.theta_rad),
            ("length_mm", row.length_mm),
            ("width_mm", row.width_mm),
        ];
        for (name, value) in fields {
            if !value.is_finite() {
                bail!("line {line}: field `{name}` is {value}, expected a finite number");
            }
        }
        if row.width_mm <= 0.0 {
            bail!(
                "line {line}: field `width_mm` is {}, expected a positive width",
                row.width_mm
            );
        }
        if row.length_mm < row.width_mm * 0.98 {
            bail!(
                "line {line}: field `length_mm` is {} but width_mm is {}: the length is the long side",
                row.length_mm,
                row.width_mm
            );
        }
        if let Some(c) = row.confidence {
            if !(0.0..=1.0).contains(&c) {
                bail!("line {line}: field `confidence` is {c}, expected a value in [0, 1]");
            }
        }
        let grain = Grain {
            x: row.x_mm * MM,
            y: row.y_mm * MM,
            theta: row.theta_rad,
            length: row.length_mm * MM,
            width: row.width_mm * MM,
            confidence: row.confidence,
            cut: row.cut.unwrap_or(0) != 0,
        };
        grains.push(grain.folded());
    }
    if grains.is_empty() {
        bail!("the table has no grains (a header line and no rows)");
    }
    Ok(Deposit { grains })
}

fn csv_error_text(e: &csv::Error) -> String {
    match e.kind() {
        csv::ErrorKind::Deserialize { err, .. } => match err.field() {
            Some(field) => format!("field {} : {}", field + 1, err.kind()),
            None => err.kind().to_string(),
        },
        _ => e.to_string(),
    }
}

/// Writes a deposit table atomically. Detector columns (`confidence`, `cut`) are written when
/// any grain carries a confidence.
pub fn write_deposit_csv(path: &Path, deposit: &Deposit) -> anyhow::Result<()> {
    let detected = deposit.grains.iter().any(|g| g.confidence.is_some());
    write_table(path, deposit, detected)
}

/// Writes a detector's table atomically, with its columns (`confidence`, `cut`) even when it
/// found no grain: an empty photograph's table has the same header as any other.
pub fn write_detected_csv(path: &Path, deposit: &Deposit) -> anyhow::Result<()> {
    write_table(path, deposit, true)
}

fn write_table(path: &Path, deposit: &Deposit, detected: bool) -> anyhow::Result<()> {
    write_atomic(path, |out| {
        let mut w = csv::Writer::from_writer(out);
        let mut header = vec!["x_mm", "y_mm", "theta_rad", "length_mm", "width_mm"];
        if detected {
            header.extend(["confidence", "cut"]);
        }
        w.write_record(&header)?;
        for g in &deposit.grains {
            let mut rec = vec![
                format!("{:.4}", g.x / MM),
                format!("{:.4}", g.y / MM),
                format!("{:.6}", g.theta),
                format!("{:.4}", g.length / MM),
                format!("{:.4}", g.width / MM),
            ];
            if detected {
                rec.push(format!("{:.4}", g.confidence.unwrap_or(1.0)));
                rec.push(u8::from(g.cut).to_string());
            }
            w.write_record(&rec)?;
        }
        w.flush()?;
        Ok(())
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn round_trip() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("d.csv");
        let deposit = Deposit {
            grains: vec![Grain {
                x: 0.1,
                y: 0.2,
                theta: 0.5,
                length: 8.9e-3,
                width: 3e-3,
                confidence: Some(0.9),
                cut: true,
            }],
        };
        write_deposit_csv(&path, &deposit).unwrap();
        let back = read_deposit_csv(&path).unwrap();
        assert_eq!(back.grains.len(), 1);
        let g = back.grains[0];
        assert!((g.x - 0.1).abs() < 1e-9 && (g.theta - 0.5).abs() < 1e-6 && g.cut);
    }

    #[test]
    fn errors_name_line_and_field() {
        let text = "x_mm,y_mm,theta_rad,length_mm,width_mm\n1,2,0,5,3\n1,NaN,0,5,3\n";
        let err = parse_deposit_csv(text.as_bytes()).unwrap_err().to_string();
        assert!(err.contains("line 3") && err.contains("y_mm"), "{err}");
        let text = "x_mm,y_mm,theta_rad,length_mm\n1,2,0,5\n";
        let err = parse_deposit_csv(text.as_bytes()).unwrap_err().to_string();
        assert!(err.contains("width_mm"), "{err}");
        let text = "x_mm,y_mm,theta_rad,length_mm,width_mm\n1,2,0,abc,3\n";
        let err = format!("{:#}", parse_deposit_csv(text.as_bytes()).unwrap_err());
        assert!(err.contains("line 2"), "{err}");
        let text = "x_mm,y_mm,theta_rad,length_mm,width_mm\n";
        let err = format!("{:#}", parse_deposit_csv(text.as_bytes()).unwrap_err());
        assert!(err.contains("no grains"), "{err}");
    }
}
