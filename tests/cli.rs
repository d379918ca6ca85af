//! `facets analyse` and `facets compare` on the sample tables: the files they promise exist,
//! PNGs decode, CSVs hold finite numbers; bad input gives an error naming file, line and field.

use std::path::{Path, PathBuf};
use std::process::Command;

fn facets() -> Command {
    Command::new(env!("CARGO_BIN_EXE_facets"))
}

fn samples() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("data-samples/deposits")
}

fn run_ok(cmd: &mut Command) {
    let out = cmd.output().unwrap();
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
}

fn check_png(path: &Path) {
    let img = image::open(path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    assert!(
        img.width() >= 300 && img.height() >= 200,
        "{}",
        path.display()
    );
    // Not a blank canvas: some pixels are dark (text, lines).
    let rgb = img.to_rgb8();
    let dark = rgb
        .pixels()
        .filter(|p| p.0.iter().all(|&c| c < 100))
        .count();
    assert!(dark > 100, "{} looks empty", path.display());
}

fn check_csv(path: &Path) {
    let mut reader = csv::Reader::from_path(path).unwrap();
    let headers = reader.headers().unwrap().clone();
    let mut rows = 0;
    for rec in reader.records() {
        let rec = rec.unwrap();
        for (h, field) in headers.iter().zip(rec.iter()) {
            if h == "series" {
                continue;
            }
            let v: f64 = field
                .parse()
                .unwrap_or_else(|_| panic!("{}: `{h}` = {field}", path.display()));
            assert!(v.is_finite(), "{}: `{h}` = {v}", path.display());
        }
        rows += 1;
    }
    assert!(rows > 0, "{} has no rows", path.display());
}

#[test]
fn analyse_and_compare_write_every_figure_with_its_numbers() {
    let tmp = tempfile::tempdir().unwrap();
    let (sim, exp, cmp) = (
        tmp.path().join("sim"),
        tmp.path().join("exp"),
        tmp.path().join("cmp"),
    );
    run_ok(
        facets()
            .arg("analyse")
            .arg(samples().join("stack.csv"))
            .arg("--out")
            .arg(&sim),
    );
    run_ok(
        facets()
            .arg("analyse")
            .arg(samples().join("photo.csv"))
            .arg("--out")
            .arg(&exp),
    );
    run_ok(
        facets()
            .args(["compare", "--experiment"])
            .arg(&exp)
            .arg("--simulation")
            .arg(&sim)
            .arg("--out")
            .arg(&cmp),
    );
    let figures = [
        "orientation",
        "rdf",
        "g1_vs_phi0",
        "packing_fraction_vs_phi0",
        "pressure_phi0_0.100",
        "pressure_w_scan_phi0_0.100",
        "deposit_sim_phi0_0.100",
    ];
    for name in figures {
        for dir in [&sim, &cmp] {
            check_png(&dir.join(format!("{name}.png")));
            check_csv(&dir.join(format!("{name}.csv")));
        }
    }
    check_png(&cmp.join("deposit_exp_phi0_0.100.png"));
    check_csv(&cmp.join("deposit_exp_phi0_0.100.grains.csv"));
    // The overlay holds both sources.
    let text = std::fs::read_to_string(cmp.join("rdf.csv")).unwrap();
    assert!(text.contains("exp phi0") && text.contains("sim phi0"));
    let summary: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(sim.join("summary.json")).unwrap()).unwrap();
    let janssen = &summary["ensembles"][0]["pressure"]["janssen"];
    assert!(janssen["lambda_over_w"].as_f64().unwrap() > 0.0);
    assert!(cmp.join("comparison.json").exists());
}

#[test]
fn bad_tables_are_refused_naming_file_line_and_field() {
    let tmp = tempfile::tempdir().unwrap();
    let deposit = tmp.path().join("bad.csv");
    std::fs::write(
        &deposit,
        "x_mm,y_mm,theta_rad,length_mm,width_mm\n100,50,0,6.9,6.9\n110,50,0,6.9,6.9\n",
    )
    .unwrap();
    std::fs::write(
        tmp.path().join("bad.contacts.csv"),
        "i,j,fx_N,fy_N,cx_mm,cy_mm\n0,1,0.1,0,105,50\n1,2,0.1,0,115,50\n",
    )
    .unwrap();
    let out = facets()
        .arg("analyse")
        .arg(&deposit)
        .args(["--phi0", "0.1", "--silo-width-mm", "258", "--out"])
        .arg(tmp.path().join("o"))
        .output()
        .unwrap();
    assert!(!out.status.success());
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(
        err.contains("bad.contacts.csv") && err.contains("line 3") && err.contains("`j`"),
        "{err}"
    );
    assert!(!err.contains("panicked"), "{err}");
    // Without a sidecar and without --phi0 the error says what is missing.
    let out = facets()
        .arg("analyse")
        .arg(&deposit)
        .arg("--out")
        .arg(tmp.path().join("o"))
        .output()
        .unwrap();
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(
        err.contains("bad.meta.json") && err.contains("--phi0"),
        "{err}"
    );
}

#[test]
fn mixed_shapes_are_refused() {
    let tmp = tempfile::tempdir().unwrap();
    let rods = tmp.path().join("rods.csv");
    std::fs::write(
        &rods,
        "x_mm,y_mm,theta_rad,length_mm,width_mm\n100,50,0,8.9,3\n",
    )
    .unwrap();
    let out = facets()
        .arg("analyse")
        .arg(&rods)
        .arg(samples().join("photo.csv"))
        .args(["--phi0", "0.1", "--silo-width-mm", "258", "--out"])
        .arg(tmp.path().join("o"))
        .output()
        .unwrap();
    assert!(!out.status.success());
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(
        err.contains("mixed shapes") && err.contains("long rods"),
        "{err}"
    );
    // One table mixing shapes names the line.
    std::fs::write(
        &rods,
        "x_mm,y_mm,theta_rad,length_mm,width_mm\n100,50,0,8.9,3\n120,50,0,6.9,6.9\n",
    )
    .unwrap();
    let out = facets()
        .arg("analyse")
        .arg(&rods)
        .args(["--phi0", "0.1", "--silo-width-mm", "258", "--out"])
        .arg(tmp.path().join("o"))
        .output()
        .unwrap();
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(err.contains("rods.csv") && err.contains("line 3"), "{err}");
}

/// A deposit whose analysed area leaves no grain 4 D inside it (a 96 mm silo: 16 mm once 40 mm
/// is cut at each wall) has no g(r): analyse says so on stderr and prints g(1) as n/a, never NaN.
#[test]
fn analyse_warns_when_no_grain_can_centre_g_of_r() {
    let dir = tempfile::tempdir().unwrap();
    let table = dir.path().join("narrow.csv");
    let mut rows = String::from("x_mm,y_mm,theta_rad,length_mm,width_mm\n");
    for layer in 0..3 {
        for k in 0..13 {
            let x = 3.5 + 7.0 * k as f64;
            let y = 3.5 + 7.0 * layer as f64;
            rows.push_str(&format!("{x:.2},{y:.2},0,6.9,6.9\n"));
        }
    }
    std::fs::write(&table, rows).unwrap();
    let out = facets()
        .arg("analyse")
        .arg(&table)
        .args(["--phi0", "0.1", "--silo-width-mm", "96", "--out"])
        .arg(dir.path().join("out"))
        .output()
        .unwrap();
    let stdout = String::from_utf8_lossy(&out.stdout);
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(out.status.success(), "{stderr}");
    assert!(
        stderr.contains("warning: phi0 = 0.100")
            && stderr.contains("g(r) and g(1) cannot be measured"),
        "no warning on stderr: {stderr}"
    );
    assert!(stdout.contains("g(1) = n/a"), "{stdout}");
    assert!(!stdout.contains("NaN"), "{stdout}");
}
