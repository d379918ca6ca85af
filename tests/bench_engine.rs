//! `facets bench engine`: the table it promises, the same deposit on every thread count, and
//! a settled deposit saved by one run and read back by the next.

use std::path::Path;
use std::process::{Command, Output};

fn bench(cache: &Path, csv: &Path) -> Output {
    let out = Command::new(env!("CARGO_BIN_EXE_facets"))
        .args(["bench", "engine", "--cases", "square:60", "--steps", "50"])
        .args(["--threads", "1,2", "--settled-cache"])
        .arg(cache)
        .arg("--csv")
        .arg(csv)
        .output()
        .unwrap();
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    out
}

/// (threads, grain-steps per second, sub-contacts) of each row.
fn rows(csv: &Path) -> Vec<(usize, f64, usize)> {
    let mut reader = csv::Reader::from_path(csv).unwrap();
    let headers = reader.headers().unwrap().clone();
    let col = |name: &str| headers.iter().position(|h| h == name).unwrap();
    let (threads, rate, contacts) = (
        col("threads"),
        col("grain_steps_per_s"),
        col("sub_contacts"),
    );
    reader
        .records()
        .map(|r| {
            let r = r.unwrap();
            (
                r[threads].parse().unwrap(),
                r[rate].parse().unwrap(),
                r[contacts].parse().unwrap(),
            )
        })
        .collect()
}

#[test]
fn a_settled_deposit_is_saved_and_read_back_unchanged() {
    let dir = tempfile::tempdir().unwrap();
    let cache = dir.path().join("settled");
    let (first, second) = (dir.path().join("first.csv"), dir.path().join("second.csv"));

    let out = bench(&cache, &first);
    assert!(String::from_utf8_lossy(&out.stderr).contains("settled to kinetic / elastic"));
    let saved: Vec<_> = std::fs::read_dir(&cache).unwrap().collect();
    assert_eq!(saved.len(), 1, "one settled deposit saved");
    let rows_first = rows(&first);
    assert_eq!(rows_first.len(), 2, "one row per thread count");
    for &(threads, rate, contacts) in &rows_first {
        assert!(rate.is_finite() && rate > 0.0, "{threads} threads: {rate}");
        // 60 squares at rest in 23 columns: every grain rests on something.
        assert!(contacts >= 60, "{threads} threads: {contacts} sub-contacts");
    }
    // The same steps on one thread and two end in the same deposit.
    assert_eq!(rows_first[0].2, rows_first[1].2);

    let out = bench(&cache, &second);
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(stderr.contains("read from"), "{stderr}");
    assert!(!stderr.contains("settled to kinetic"), "{stderr}");
    let rows_second = rows(&second);
    let contacts = |r: &[(usize, f64, usize)]| r.iter().map(|x| x.2).collect::<Vec<_>>();
    assert_eq!(contacts(&rows_first), contacts(&rows_second));
}

#[test]
fn a_damaged_saved_deposit_is_refused_naming_the_file() {
    let dir = tempfile::tempdir().unwrap();
    let cache = dir.path().join("settled");
    bench(&cache, &dir.path().join("a.csv"));
    let file = std::fs::read_dir(&cache)
        .unwrap()
        .next()
        .unwrap()
        .unwrap()
        .path();
    std::fs::write(&file, b"not a world").unwrap();
    let out = Command::new(env!("CARGO_BIN_EXE_facets"))
        .args(["bench", "engine", "--cases", "square:60", "--steps", "5"])
        .arg("--settled-cache")
        .arg(&cache)
        .output()
        .unwrap();
    assert!(!out.status.success());
    let stderr = String::from_utf8_lossy(&out.stderr);
    let name = file.file_name().unwrap().to_string_lossy();
    assert!(stderr.contains(&*name), "{stderr}");
}

#[test]
fn bare_scaling_is_accepted_and_a_bad_case_is_named() {
    // Bare `--scaling` means both layouts; clap must accept its default before the cases are
    // read, which fail here without settling anything.
    let out = Command::new(env!("CARGO_BIN_EXE_facets"))
        .args(["bench", "engine", "--scaling", "--cases", "pebble:10"])
        .output()
        .unwrap();
    assert!(!out.status.success());
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(stderr.contains("case `pebble:10`"), "{stderr}");
}
