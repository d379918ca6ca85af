//! One command line (issue 56): grain kinds and frames written the same in every command; the
//! output of one command read by the next without options; nothing overwritten unasked.

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

use facets::deposit::{read_deposit_csv, read_meta_json};

fn facets() -> Command {
    Command::new(env!("CARGO_BIN_EXE_facets"))
}

fn sample(path: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("data-samples")
        .join(path)
}

fn stderr(o: &Output) -> String {
    String::from_utf8_lossy(&o.stderr).into_owned()
}

fn succeeded(o: Output) -> Output {
    assert!(o.status.success(), "{}", stderr(&o));
    o
}

/// The files under `dir` (folders left empty do not count).
fn files_under(dir: &Path) -> Vec<PathBuf> {
    let mut files = Vec::new();
    for entry in std::fs::read_dir(dir).unwrap() {
        let path = entry.unwrap().path();
        if path.is_dir() {
            files.extend(files_under(&path));
        } else {
            files.push(path);
        }
    }
    files
}

#[test]
fn every_command_names_grains_and_frames_alike() {
    let help = |command: &str, flag: &str| {
        let o = succeeded(facets().args([command, flag]).output().unwrap());
        String::from_utf8_lossy(&o.stdout).into_owned()
    };
    for command in ["render", "detect", "analyse"] {
        let text = help(command, "--help");
        assert!(
            text.contains("--frame-mm <X_MIN,X_MAX,Y_MIN,Y_MAX>"),
            "{command} --help:\n{text}"
        );
    }
    for (command, option) in [("render", "--generate"), ("detect", "--shape")] {
        // The short help lists an option's values on one line.
        let text = help(command, "-h");
        let line = text
            .find(&format!("{option} <"))
            .and_then(|k| text[k..].lines().find(|l| l.contains("possible values")))
            .unwrap_or_else(|| panic!("{command} {option}: no values listed:\n{text}"));
        for kind in ["square", "rod53", "rod3"] {
            assert!(line.contains(kind), "{command} {option}: {line}");
        }
    }
}

#[test]
fn rods_without_a_size_are_refused_not_guessed() {
    let dir = tempfile::tempdir().unwrap();
    let o = facets()
        .args(["detect", "--shape", "rod", "--px-per-mm", "10", "--out"])
        .arg(dir.path())
        .arg(sample("photos/rod53-lab-10px.png"))
        .output()
        .unwrap();
    let e = stderr(&o);
    assert!(!o.status.success(), "{e}");
    assert!(
        e.contains("--length-mm") && e.contains("rod53") && e.contains("rod3"),
        "{e}"
    );
    assert!(files_under(dir.path()).is_empty());
}

#[test]
fn same_named_photographs_are_refused_before_any_detecting() {
    let dir = tempfile::tempdir().unwrap();
    let (c1, c2, out) = (
        dir.path().join("c1"),
        dir.path().join("c2"),
        dir.path().join("d"),
    );
    for c in [&c1, &c2] {
        std::fs::create_dir_all(c).unwrap();
        std::fs::copy(sample("photos/square-lab-10px.png"), c.join("p.png")).unwrap();
    }
    let o = facets()
        .args(["detect", "--shape", "square", "--px-per-mm", "10", "--out"])
        .arg(&out)
        .arg(c1.join("p.png"))
        .arg(c2.join("p.png"))
        .output()
        .unwrap();
    let e = stderr(&o);
    assert!(!o.status.success(), "{e}");
    let named = |p: PathBuf| e.contains(&p.display().to_string());
    assert!(
        named(c1.join("p.png")) && named(c2.join("p.png")) && named(out.join("p.csv")),
        "{e}"
    );
    assert!(!out.join("p.csv").exists());
}

/// Two runs into one --out, of photographs of the same name in different folders: the second
/// is refused before detecting, the first's table untouched, unless told to overwrite.
#[test]
fn a_later_run_never_overwrites_a_same_named_photographs_table() {
    let dir = tempfile::tempdir().unwrap();
    let (c1, c2, out) = (
        dir.path().join("c1"),
        dir.path().join("c2"),
        dir.path().join("d"),
    );
    std::fs::create_dir_all(&c1).unwrap();
    std::fs::create_dir_all(&c2).unwrap();
    std::fs::copy(sample("photos/square-lab-10px.png"), c1.join("p.png")).unwrap();
    image::GrayImage::from_pixel(300, 200, image::Luma([230]))
        .save(c2.join("p.png"))
        .unwrap();
    let detect = |photo: PathBuf, extra: &[&str]| {
        facets()
            .args(["detect", "--shape", "square", "--px-per-mm", "10", "--out"])
            .arg(&out)
            .args(extra)
            .arg(photo)
            .output()
            .unwrap()
    };
    succeeded(detect(c1.join("p.png"), &[]));
    let table = out.join("p.csv");
    let first = std::fs::read_to_string(&table).unwrap();
    assert!(first.lines().count() > 10, "{first}");
    for extra in [&[][..], &["--overlay"]] {
        let o = detect(c2.join("p.png"), extra);
        let e = stderr(&o);
        assert!(!o.status.success(), "{e}");
        assert!(
            e.contains(&table.display().to_string()) && e.contains("--overwrite"),
            "{e}"
        );
        assert_eq!(std::fs::read_to_string(&table).unwrap(), first);
        assert!(!out.join("p_overlay.png").exists());
    }
    succeeded(detect(c2.join("p.png"), &["--overwrite"]));
    assert_eq!(std::fs::read_to_string(&table).unwrap().lines().count(), 1);
}

/// Rods are named as everywhere (rod53, rod3) or given by their size; a rod of the
/// experiment's size is that grain, another size is written as given, and no size is
/// refused.
#[test]
fn a_custom_rod_is_the_size_given() {
    let dir = tempfile::tempdir().unwrap();
    let photo = sample("photos/rod53-lab-10px.png");
    let detect = |out: &str, shape: &[&str]| {
        let o = facets()
            .args(["detect", "--px-per-mm", "10", "--shape"])
            .args(shape)
            .arg("--out")
            .arg(dir.path().join(out))
            .arg(&photo)
            .output()
            .unwrap();
        let table = dir.path().join(out).join("rod53-lab-10px.csv");
        (o, std::fs::read_to_string(table).ok())
    };
    let (_, named) = detect("named", &["rod53"]);
    let (_, sized) = detect("sized", &["rod", "--length-mm", "4.9", "--width-mm", "3"]);
    assert!(named.is_some() && named == sized);
    let (o, custom) = detect("custom", &["rod", "--length-mm", "6", "--width-mm", "2.5"]);
    let custom = custom.unwrap_or_else(|| panic!("{}", stderr(&o)));
    let rows: Vec<&str> = custom.lines().skip(1).collect();
    assert!(!rows.is_empty());
    for row in rows {
        let fields: Vec<&str> = row.split(',').collect();
        assert_eq!(fields[3..5], ["6.0000", "2.5000"], "{row}");
    }
    for (shape, expected) in [
        (&["rod", "--width-mm", "3"][..], "--length-mm"),
        (
            &["rod3", "--length-mm", "6"][..],
            "--shape rod3 has its own",
        ),
        (
            &["square", "--width-mm", "6"][..],
            "--shape square has its own",
        ),
    ] {
        let (o, table) = detect("refused", shape);
        let e = stderr(&o);
        assert!(!o.status.success() && table.is_none(), "{shape:?}: {e}");
        assert!(e.contains(expected), "{shape:?}: {e}");
    }
}

/// A photograph of part of a deposit, detected with its place in the silo, is analysed with
/// no options: the table is in the silo's coordinates and its sidecar holds the frame given.
#[test]
fn a_detected_photograph_is_analysed_without_options() {
    let dir = tempfile::tempdir().unwrap();
    let deposit = sample("deposits/photo.csv");
    let frame = "0,120,290,350";
    let photo = dir.path().join("part.png");
    succeeded(
        facets()
            .arg("render")
            .arg(&deposit)
            .args([
                "--px-per-mm",
                "6",
                "--frame-mm",
                frame,
                "--bits",
                "8",
                "--out",
            ])
            .arg(&photo)
            .output()
            .unwrap(),
    );
    let detected = dir.path().join("detected");
    succeeded(
        facets()
            .args(["detect", "--shape", "square", "--px-per-mm", "6"])
            .args([
                "--phi0",
                "0.1",
                "--silo-width-mm",
                "258",
                "--frame-mm",
                frame,
            ])
            .arg("--out")
            .arg(&detected)
            .arg(&photo)
            .output()
            .unwrap(),
    );
    let meta = read_meta_json(&detected.join("part.meta.json")).unwrap();
    let f = meta.frame_mm.unwrap();
    assert_eq!((meta.phi0, meta.silo_width_mm), (0.1, 258.0), "{meta:?}");
    assert_eq!(
        [f.x_min, f.x_max, f.y_min, f.y_max],
        [0.0, 120.0, 290.0, 350.0]
    );

    // Every grain found lies where the deposit has one, in the silo's coordinates (the truth
    // in the frame's coordinates would be 290 mm lower).
    let found = read_deposit_csv(&detected.join("part.csv")).unwrap();
    let truth = read_deposit_csv(&deposit).unwrap();
    let uncut: Vec<_> = found.grains.iter().filter(|g| !g.cut).collect();
    assert!(uncut.len() > 50, "{} grains found", uncut.len());
    for g in &uncut {
        let nearest = truth
            .grains
            .iter()
            .map(|t| (t.x - g.x).hypot(t.y - g.y))
            .fold(f64::INFINITY, f64::min);
        assert!(
            nearest < 1e-3,
            "{g:?} is {:.1} mm from a grain",
            nearest * 1e3
        );
    }

    let analysis = dir.path().join("analysis");
    let o = succeeded(
        facets()
            .arg("analyse")
            .arg(&detected)
            .arg("--out")
            .arg(&analysis)
            .output()
            .unwrap(),
    );
    let stdout = String::from_utf8_lossy(&o.stdout);
    assert!(stdout.contains("phi0 = 0.100"), "{stdout}");
    assert!(analysis.join("summary.json").exists());
}

/// An ensemble folder as `facets sim --realisations` writes it is analysed as it is.
#[test]
fn analyse_reads_an_ensemble_folder_through_its_seeds() {
    let dir = tempfile::tempdir().unwrap();
    let ensemble = dir.path().join("runs");
    for seed in [1, 2, 3] {
        let run = ensemble.join(format!("seed-{seed}"));
        std::fs::create_dir_all(&run).unwrap();
        for (from, to) in [
            ("stack.csv", "deposit.csv"),
            ("stack.contacts.csv", "deposit.contacts.csv"),
            ("stack.meta.json", "deposit.meta.json"),
        ] {
            std::fs::copy(sample("deposits").join(from), run.join(to)).unwrap();
        }
        std::fs::write(run.join("run.json"), "{}").unwrap();
    }
    let out = dir.path().join("analysis");
    let o = succeeded(
        facets()
            .arg("analyse")
            .arg(&ensemble)
            .arg("--out")
            .arg(&out)
            .output()
            .unwrap(),
    );
    let stdout = String::from_utf8_lossy(&o.stdout);
    assert!(
        stdout.contains("3 deposits") && stdout.contains("1 ensembles"),
        "{stdout}"
    );

    let empty = dir.path().join("empty");
    std::fs::create_dir_all(empty.join("seed-1")).unwrap();
    let o = facets()
        .arg("analyse")
        .arg(&empty)
        .arg("--out")
        .arg(dir.path().join("none"))
        .output()
        .unwrap();
    let e = stderr(&o);
    assert!(!o.status.success() && e.contains("seed-N"), "{e}");
}

/// 20 squares: a run of a second or two.
const TINY: &str = r#"
[silo]
width_mm = 96

[grains]
kind = "square"
count = 20

[feed]
phi0 = 0.1

[run]
time_step_s = 4e-6
relaxation_ratio = 1e-3
max_relaxation_time_s = 0.05
"#;

#[test]
fn sim_refuses_to_start_over_an_earlier_run_unless_told() {
    let dir = tempfile::tempdir().unwrap();
    let scene = dir.path().join("tiny.toml");
    std::fs::write(&scene, TINY).unwrap();
    let out = dir.path().join("runs");
    let run = out.join("seed-1");
    std::fs::create_dir_all(&run).unwrap();
    let sim = |extra: &[&str]| {
        facets()
            .arg("sim")
            .arg(&scene)
            .arg("--out")
            .arg(&out)
            .args(extra)
            .output()
            .unwrap()
    };

    // A stopped run: its checkpoint is named with --resume and --restart.
    let checkpoint = run.join("checkpoint.bin");
    std::fs::write(&checkpoint, b"an earlier run's checkpoint").unwrap();
    let o = sim(&[]);
    let e = stderr(&o);
    assert!(!o.status.success(), "{e}");
    assert!(
        e.contains(&format!("--resume {}", checkpoint.display())) && e.contains("--restart"),
        "{e}"
    );
    assert!(!run.join("deposit.csv").exists(), "{e}");

    // A finished run: its record is named with --restart.
    let record = run.join("run.json");
    std::fs::write(&record, "{}").unwrap();
    let o = sim(&[]);
    let e = stderr(&o);
    assert!(!o.status.success(), "{e}");
    assert!(
        e.contains(&record.display().to_string()) && e.contains("--restart"),
        "{e}"
    );
    assert!(!run.join("deposit.csv").exists(), "{e}");

    // Told to start over, it runs, and the stale checkpoint is gone.
    let o = sim(&["--restart"]);
    assert!(
        o.status.success() || stderr(&o).contains("did not relax"),
        "{}",
        stderr(&o)
    );
    assert!(run.join("deposit.csv").exists());
    assert!(!checkpoint.exists());
    let written = std::fs::read_to_string(&record).unwrap();
    assert!(written.contains("\"seed\": 1"), "{written}");
}
