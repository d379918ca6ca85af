use serde::{Deserialize, Serialize};

/// A mean over realisations and its standard error (sample standard deviation / sqrt(n); 0 for
/// a single realisation, where the spread is unknown).
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct MeanErr {
    /// NaN when there is nothing to average (written as null in JSON).
    #[serde(deserialize_with = "nan_from_null")]
    pub mean: f64,
    #[serde(deserialize_with = "nan_from_null")]
    pub stderr: f64,
    pub n: usize,
}

/// serde_json writes NaN as null; read null back as NaN.
fn nan_from_null<'de, D: serde::Deserializer<'de>>(d: D) -> Result<f64, D::Error> {
    Ok(Option::<f64>::deserialize(d)?.unwrap_or(f64::NAN))
}

impl MeanErr {
    pub fn of(values: &[f64]) -> MeanErr {
        let n = values.len();
        if n == 0 {
            return MeanErr {
                mean: f64::NAN,
                stderr: f64::NAN,
                n,
            };
        }
        let mean = values.iter().sum::<f64>() / n as f64;
        let stderr = if n > 1 {
            let var = values.iter().map(|v| (v - mean).powi(2)).sum::<f64>() / (n - 1) as f64;
            (var / n as f64).sqrt()
        } else {
            0.0
        };
        MeanErr { mean, stderr, n }
    }
}

/// Column-wise mean and standard error of equally long series (one per realisation).
pub fn mean_err_columns(series: &[Vec<f64>]) -> (Vec<f64>, Vec<f64>) {
    let len = series.first().map_or(0, Vec::len);
    (0..len)
        .map(|k| {
            let column: Vec<f64> = series.iter().map(|s| s[k]).collect();
            let m = MeanErr::of(&column);
            (m.mean, m.stderr)
        })
        .unzip()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn mean_and_standard_error() {
        let m = MeanErr::of(&[1.0, 2.0, 3.0, 4.0]);
        assert_eq!(m.mean, 2.5);
        // sample sd = sqrt(5/3); stderr = sd / 2
        assert!((m.stderr - (5.0f64 / 3.0).sqrt() / 2.0).abs() < 1e-15);
        let empty = MeanErr::of(&[]);
        let back: MeanErr = serde_json::from_str(&serde_json::to_string(&empty).unwrap()).unwrap();
        assert!(back.mean.is_nan() && back.n == 0);
    }
}
