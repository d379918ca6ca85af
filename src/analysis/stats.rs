use serde::{Deserialize, Serialize};

/// A mean over realisations and its standard error (sample standard deviation / sqrt(n); 0 for
/// a single realisation, where the spread is unknown).
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct MeanErr {
    pub mean: f64,
    pub stderr: f64,
    pub n: usize,
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
