//! The figures' numbers in the units their axes state: f(theta) per degree against theta in
//! degrees over the folding range.

use std::path::Path;
use std::process::Command;

fn analyse(table: &str, out: &Path) {
    let status = Command::new(env!("CARGO_BIN_EXE_facets"))
        .arg("analyse")
        .arg(
            Path::new(env!("CARGO_MANIFEST_DIR"))
                .join("data-samples/deposits")
                .join(table),
        )
        .arg("--out")
        .arg(out)
        .output()
        .unwrap();
    assert!(
        status.status.success(),
        "{}",
        String::from_utf8_lossy(&status.stderr)
    );
}

#[test]
fn orientation_table_is_per_degree_over_the_folding_range() {
    let dir = tempfile::tempdir().unwrap();
    analyse("photo.csv", dir.path());
    let mut reader = csv::Reader::from_path(dir.path().join("orientation.csv")).unwrap();
    assert_eq!(
        reader.headers().unwrap(),
        vec!["series", "theta_deg", "f_per_deg", "stderr"]
    );
    let (mut integral, mut bins, mut isotropic) = (0.0, 0, Vec::new());
    for row in reader.records() {
        let row = row.unwrap();
        let number = |k: usize| row[k].parse::<f64>().unwrap();
        if row[0].starts_with("isotropic") {
            isotropic.push(number(2));
            continue;
        }
        let theta = number(1);
        assert!(
            (0.0..90.0).contains(&theta),
            "theta {theta} deg outside 0-90"
        );
        integral += number(2);
        bins += 1;
    }
    // 5-degree bins over 90 degrees: f in 1/deg sums to 1 / 5 deg.
    assert_eq!(bins, 18);
    assert!(
        (integral * 5.0 - 1.0).abs() < 1e-9,
        "integral {}",
        integral * 5.0
    );
    assert!(!isotropic.is_empty() && isotropic.iter().all(|f| (f * 90.0 - 1.0).abs() < 1e-9));
}
