//! `facets detect` on a batch with a corrupt file: the error names the file, the rest of the
//! batch is processed, and the exit code reports the failure.

use std::process::Command;

#[test]
fn corrupt_photograph_is_named_and_the_batch_goes_on() {
    let dir = tempfile::tempdir().unwrap();
    let corrupt = dir.path().join("corrupt.png");
    std::fs::write(&corrupt, b"\x89PNG\r\n\x1a\nthis is not an image").unwrap();
    let blank = dir.path().join("blank.png");
    image::GrayImage::from_pixel(120, 80, image::Luma([250]))
        .save(&blank)
        .unwrap();
    let out = dir.path().join("out");
    let run = Command::new(env!("CARGO_BIN_EXE_facets"))
        .args([
            "detect",
            "--shape",
            "rod",
            "--aspect",
            "5/3",
            "--px-per-mm",
            "10",
            "--out",
        ])
        .arg(&out)
        .arg(&corrupt)
        .arg(&blank)
        .output()
        .unwrap();
    let stderr = String::from_utf8_lossy(&run.stderr);
    assert!(!run.status.success());
    assert!(stderr.contains("corrupt.png"), "{stderr}");
    assert!(
        stderr.contains("no grains found in") && stderr.contains("blank.png"),
        "{stderr}"
    );
    let table = std::fs::read_to_string(out.join("blank.csv")).unwrap();
    assert_eq!(table.lines().count(), 1, "header only: {table}");
}
