//! `facets validate` end to end on a tiny study: two cases (a baseline and a variant) of 60
//! squares in a 120 mm silo, two seeds each. The deposits are far too small for the study's
//! quantities to mean anything; the test checks the machinery: the runs, the raw results, a
//! report with every finding's section, the variants beside their baseline, `--report-only`
//! giving the same report, and a second run reusing every seed.

use std::path::{Path, PathBuf};
use std::process::Command;

use facets::validate::findings::Verdict;
use facets::validate::{Options, validate};

/// The time step and relaxation of tests/silo_fill.rs's small scene: statics in seconds.
const SCENE: &str = r#"
[silo]
width_mm = 120

[grains]
kind = "square"
count = 60

[feed]
phi0 = 0.01

[run]
seed = 5
time_step_s = 4e-6
relaxation_ratio = 1e-3
max_relaxation_time_s = 2

[output]
frame = "whole"
"#;

const STUDY: &str = r#"
[analysis]
rdf_margin_over_d = 1.1

[[case]]
name = "slow"
scene = "scenes/tiny.toml"
seeds = 2

[[case]]
name = "slow-rough"
scene = "scenes/tiny.toml"
seeds = [5, 6]
group = "grain friction"
baseline = "slow"
[case.overrides.contact]
friction = 0.8
"#;

fn write_study(dir: &Path) -> PathBuf {
    std::fs::create_dir_all(dir.join("scenes")).unwrap();
    std::fs::write(dir.join("scenes/tiny.toml"), SCENE).unwrap();
    let study = dir.join("study.toml");
    std::fs::write(&study, STUDY).unwrap();
    study
}

#[test]
fn a_tiny_study_runs_reports_and_resumes() {
    let dir = tempfile::tempdir().unwrap();
    let options = Options {
        study: Some(write_study(dir.path())),
        out: dir.path().join("runs"),
        report: dir.path().join("docs/validation.md"),
        report_only: false,
    };
    let outcome = validate(&options, None, &|_| {}).unwrap();
    assert_eq!((outcome.runs.ran, outcome.runs.reused), (4, 0));
    assert_eq!(outcome.measured, 4);
    for case in ["slow", "slow-rough"] {
        for seed in [5, 6] {
            let run = options.out.join(case).join(format!("seed-{seed}"));
            for file in [
                "deposit.csv",
                "deposit.contacts.csv",
                "deposit.meta.json",
                "grains.vtu",
                "run.json",
                "scene.toml",
            ] {
                assert!(run.join(file).is_file(), "{}/{file}", run.display());
            }
        }
    }
    // The variant's scene is the scene file with its override.
    let scene = std::fs::read_to_string(options.out.join("slow-rough/seed-5/scene.toml")).unwrap();
    let scene = facets::scene::parse_scene(&scene, "variant").unwrap();
    assert_eq!(scene.contact.friction, 0.8);
    assert_eq!(scene.grains.count, 60);

    // One row per case and seed, the quantities in columns; the load shares add up to one.
    let csv = std::fs::read_to_string(options.out.join("results.csv")).unwrap();
    let mut reader = csv::Reader::from_reader(csv.as_bytes());
    let header = reader.headers().unwrap().clone();
    let column = |name: &str| header.iter().position(|h| h == name).unwrap();
    let rows: Vec<csv::StringRecord> = reader.records().map(Result::unwrap).collect();
    assert_eq!(rows.len(), 4);
    assert_eq!(
        rows.iter()
            .map(|r| (r[0].to_string(), r[1].to_string()))
            .collect::<Vec<_>>(),
        [
            ("slow", "5"),
            ("slow", "6"),
            ("slow-rough", "5"),
            ("slow-rough", "6")
        ]
        .map(|(c, s)| (c.to_string(), s.to_string()))
    );
    for r in &rows {
        let get = |name: &str| r[column(name)].parse::<f64>().unwrap();
        let (floor, walls) = (get("floor_share"), get("walls_share"));
        assert!((floor + walls - 1.0).abs() < 1e-9, "{floor} + {walls}");
        assert!((get("support_over_weight") - 1.0).abs() < 0.02);
        assert!((0.0..=1.0).contains(&get("diagonal_share")));
        // Rod quantities do not apply to squares.
        assert!(r[column("preferred_angle_deg")].is_empty());
    }
    let json: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(options.out.join("results.json")).unwrap())
            .unwrap();
    assert_eq!(json["realisations"].as_array().unwrap().len(), 4);

    // Every finding has its section; the cases the tiny study lacks are not measured.
    let report = std::fs::read_to_string(&options.report).unwrap();
    for id in ["F1", "F2", "F3", "F4", "F5"] {
        assert!(report.contains(&format!("\n## {id} ")), "no section {id}");
        assert!(
            report.contains(&format!("**{id} verdict: ")),
            "no verdict {id}"
        );
    }
    assert!(report.contains("long rods 0.04: not measured"));
    // The case table names the grains as every command does.
    assert!(
        report.contains("| 60 square |"),
        "case table names the grains"
    );
    assert!(report.contains("**not measured**"));
    let verdicts = &outcome.verdicts;
    assert_eq!(verdicts.len(), 5);
    assert_eq!(verdicts[2], ("F3", Verdict::NotMeasured));
    assert_eq!(verdicts[3], ("F4", Verdict::NotMeasured));
    assert!(report.contains("## Variants: grain friction"));
    assert!(report.contains("| slow (baseline) | slow-rough | delta/SE |"));
    assert!(report.contains(&format!(
        "--study {}",
        options.study.as_ref().unwrap().display()
    )));
    let figures = dir.path().join("docs/validation-figures");
    for f in [
        "pressure_over_overburden.png",
        "load_shares.png",
        "load_shares.csv",
    ] {
        assert!(figures.join(f).is_file(), "{f}");
    }

    // --report-only measures the same runs and writes the same report, bit for bit.
    let results = std::fs::read(options.out.join("results.csv")).unwrap();
    std::fs::remove_file(&options.report).unwrap();
    let again = validate(
        &Options {
            report_only: true,
            ..options.clone()
        },
        None,
        &|_| {},
    )
    .unwrap();
    assert_eq!((again.runs.ran, again.measured), (0, 4));
    assert_eq!(std::fs::read_to_string(&options.report).unwrap(), report);
    assert_eq!(
        std::fs::read(options.out.join("results.csv")).unwrap(),
        results
    );

    // A second run finds every seed done and runs none again.
    let deposit = options.out.join("slow/seed-5/deposit.csv");
    let before = std::fs::metadata(&deposit).unwrap().modified().unwrap();
    let second = validate(&options, None, &|_| {}).unwrap();
    assert_eq!((second.runs.ran, second.runs.reused), (0, 4));
    assert_eq!(
        std::fs::metadata(&deposit).unwrap().modified().unwrap(),
        before
    );
    assert_eq!(std::fs::read_to_string(&options.report).unwrap(), report);

    // A study edited under existing runs is refused, not measured as the old scene.
    std::fs::write(
        options.study.as_ref().unwrap(),
        STUDY.replace("friction = 0.8", "friction = 0.7"),
    )
    .unwrap();
    let e = validate(&options, None, &|_| {}).unwrap_err().to_string();
    assert!(
        e.contains("slow-rough") && e.contains("another scene"),
        "{e}"
    );
}

#[test]
fn the_command_refuses_bad_studies_naming_the_field() {
    let dir = tempfile::tempdir().unwrap();
    let study = write_study(dir.path());
    let run = |text: &str| {
        std::fs::write(&study, text).unwrap();
        let out = Command::new(env!("CARGO_BIN_EXE_facets"))
            .args(["validate", "--study"])
            .arg(&study)
            .arg("--out")
            .arg(dir.path().join("runs"))
            .arg("--report")
            .arg(dir.path().join("report.md"))
            .output()
            .unwrap();
        assert!(!out.status.success());
        String::from_utf8(out.stderr).unwrap()
    };
    let e = run(&STUDY.replace("seeds = 2", "seeds = -1"));
    assert!(
        e.contains("case `slow`") && e.contains("`seeds` is -1"),
        "{e}"
    );
    let e = run(&STUDY.replace("scenes/tiny.toml", "scenes/none.toml"));
    assert!(
        e.contains("scenes/none.toml") && e.contains("not found"),
        "{e}"
    );
    let e = run(&STUDY.replace("friction = 0.8", "frictoin = 0.8"));
    assert!(e.contains("contact.frictoin"), "{e}");
    let e = run(&STUDY.replace("group =", "grupo ="));
    assert!(e.contains("study.toml:") && e.contains("grupo"), "{e}");
    // Nothing was run.
    assert!(!dir.path().join("runs/slow").exists());
}
