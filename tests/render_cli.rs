//! `facets render` end to end: the photograph and its truth table agree, and the truth table
//! renders back to the same grains.

use std::process::Command;

use facets::deposit::read_deposit_csv;

fn facets(args: &[&str]) -> std::process::Output {
    Command::new(env!("CARGO_BIN_EXE_facets"))
        .args(args)
        .output()
        .expect("runs")
}

#[test]
fn truth_table_round_trips_through_a_second_render() {
    let dir = tempfile::tempdir().unwrap();
    let photo = dir.path().join("photo.png");
    let out = facets(&[
        "render",
        "--generate",
        "rod53",
        "--packing",
        "ordered",
        "--px-per-mm",
        "6",
        "--frame-mm",
        "0,40,0,30",
        "--bits",
        "8",
        "--out",
        photo.to_str().unwrap(),
    ]);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let image = image::open(&photo).unwrap();
    assert_eq!((image.width(), image.height()), (240, 180));
    assert!(matches!(image, image::DynamicImage::ImageLuma8(_)));

    let truth = read_deposit_csv(&dir.path().join("photo.truth.csv")).unwrap();
    assert!(truth.grains.len() > 50);
    // Cut grains straddle an edge; uncut ones lie wholly inside (centre at least W/2 in).
    for g in &truth.grains {
        let inside = g.x > 0.0015 && g.x < 0.0385 && g.y > 0.0015 && g.y < 0.0285;
        assert!(g.cut || inside, "{g:?}");
    }
    assert!(truth.grains.iter().any(|g| g.cut));

    // Rendering the truth table over the same frame gives back the same grains and flags.
    let again = dir.path().join("again.png");
    let out = facets(&[
        "render",
        dir.path().join("photo.truth.csv").to_str().unwrap(),
        "--px-per-mm",
        "6",
        "--frame-mm",
        "0,40,0,30",
        "--out",
        again.to_str().unwrap(),
    ]);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let back = read_deposit_csv(&dir.path().join("again.truth.csv")).unwrap();
    assert_eq!(back.grains.len(), truth.grains.len());
    for (a, b) in truth.grains.iter().zip(&back.grains) {
        assert!((a.x - b.x).abs() < 1e-7 && (a.y - b.y).abs() < 1e-7);
        assert!((a.theta - b.theta).abs() < 1e-5 && a.cut == b.cut);
    }
}

#[test]
fn bad_input_is_named() {
    let dir = tempfile::tempdir().unwrap();
    let table = dir.path().join("bad.csv");
    std::fs::write(
        &table,
        "x_mm,y_mm,theta_rad,length_mm,width_mm\n1,2,0,5,oops\n",
    )
    .unwrap();
    let out = facets(&[
        "render",
        table.to_str().unwrap(),
        "--px-per-mm",
        "5",
        "--out",
        dir.path().join("p.png").to_str().unwrap(),
    ]);
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(!out.status.success());
    assert!(err.contains("bad.csv") && err.contains("line 2"), "{err}");
    assert!(!dir.path().join("p.png").exists());
}
