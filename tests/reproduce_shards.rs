//! A plan split over tasks (`--task K --tasks N`, then `--collect`) gives the same deposits,
//! tables and report numbers, bit for bit, as one process; `--collect` names a missing unit;
//! bad shares are refused; `--slurm` writes the job array, its collect job and submit.sh.

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

use serde_json::Value;

fn facets(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_facets"))
        .args(args)
        .output()
        .expect("facets runs")
}

fn ok(args: &[&str]) -> String {
    let out = facets(args);
    assert!(
        out.status.success(),
        "facets {args:?} failed:\n{}\n{}",
        String::from_utf8_lossy(&out.stdout),
        String::from_utf8_lossy(&out.stderr)
    );
    String::from_utf8_lossy(&out.stdout).into_owned()
}

fn refused(args: &[&str]) -> String {
    let out = facets(args);
    assert!(!out.status.success(), "facets {args:?} succeeded");
    String::from_utf8_lossy(&out.stderr).into_owned()
}

/// Squares only, few grains: two simulated fillings and one photographed, seconds each.
fn write_plan(dir: &Path) -> PathBuf {
    let plan = serde_json::json!({
        "name": "shards",
        "silo_width_mm": 120.0,
        "shapes": [{"kind": "square", "grains": 40, "phi0s": [0.25], "w_over_d": 1.0}],
        "simulation_realisations": 2,
        "photo_realisations": 1,
        "frame": "whole",
        "photo_px_per_mm": 8.0,
        "photo_style": "lab",
        "rdf_margin_over_d": 1.1,
        "w_scan_over_d": [1.0, 2.0],
        "max_relaxation_time_s": 0.5
    });
    let path = dir.join("plan.json");
    std::fs::write(&path, serde_json::to_string_pretty(&plan).unwrap()).unwrap();
    path
}

/// The report's numbers: everything but wall times and the counts of fillings run now.
fn numbers(out: &Path) -> Value {
    let text = std::fs::read_to_string(out.join("report.json")).unwrap();
    let mut v: Value = serde_json::from_str(&text).unwrap();
    for key in ["stages", "fillings_run", "fillings_reused"] {
        v.as_object_mut().unwrap().remove(key);
    }
    for shape in v["shapes"].as_array_mut().unwrap() {
        for row in shape["rows"].as_array_mut().unwrap() {
            row["detector"]["seconds_per_photo"] = Value::Null;
        }
    }
    v
}

/// Files under `root` (relative paths) that hold results: tables, summaries, comparisons.
fn tables(root: &Path) -> Vec<PathBuf> {
    let mut out = Vec::new();
    let mut stack = vec![root.to_path_buf()];
    while let Some(dir) = stack.pop() {
        for entry in std::fs::read_dir(&dir).unwrap() {
            let path = entry.unwrap().path();
            let name = path.file_name().unwrap().to_string_lossy().into_owned();
            if path.is_dir() {
                stack.push(path);
            } else if name.ends_with(".csv") || name == "summary.json" || name == "comparison.json"
            {
                out.push(path.strip_prefix(root).unwrap().to_path_buf());
            }
        }
    }
    out.sort();
    out
}

#[test]
fn any_split_gives_the_one_process_results_bit_for_bit() {
    let dir = tempfile::tempdir().unwrap();
    let plan = write_plan(dir.path());
    let plan = plan.to_str().unwrap();
    let one = dir.path().join("one");
    ok(&["reproduce", "--plan", plan, "--out", one.to_str().unwrap()]);

    let split = dir.path().join("split");
    let split_s = split.to_str().unwrap();
    // Two of three tasks done: --collect names the third's unit and its task, and fails.
    for task in ["0", "2"] {
        let said = ok(&[
            "reproduce",
            "--plan",
            plan,
            "--out",
            split_s,
            "--task",
            task,
            "--tasks",
            "3",
        ]);
        assert!(said.contains("1 of 3 units"), "{said}");
    }
    let e = refused(&[
        "reproduce",
        "--plan",
        plan,
        "--out",
        split_s,
        "--collect",
        "--tasks",
        "3",
    ]);
    assert!(
        e.contains("1 of 3 units")
            && e.contains("unit 1 (task 1 of 3)")
            && e.contains("simulation seed 2")
            && e.contains("seed-2"),
        "{e}"
    );
    assert!(
        !split.join("report.json").exists(),
        "no report from a partial plan"
    );
    ok(&[
        "reproduce",
        "--plan",
        plan,
        "--out",
        split_s,
        "--task",
        "1",
        "--tasks",
        "3",
    ]);
    ok(&["reproduce", "--plan", plan, "--out", split_s, "--collect"]);

    assert_eq!(numbers(&one), numbers(&split));
    let files = tables(&one);
    assert_eq!(files, tables(&split));
    // Deposits (3), the detection and truth tables, both summaries, the comparison, charts.
    assert!(files.len() >= 10, "{files:?}");
    // Summaries name an example deposit by its path: the output folders' names aside.
    let text = |root: &Path, f: &Path| {
        std::fs::read_to_string(root.join(f))
            .unwrap()
            .replace(root.to_str().unwrap(), "OUT")
    };
    for f in &files {
        assert!(
            text(&one, f) == text(&split, f),
            "{} differs between one process and three tasks",
            f.display()
        );
    }
    // The overlay of the report's first photograph was drawn by the task that detected it.
    let report: Value =
        serde_json::from_str(&std::fs::read_to_string(split.join("report.json")).unwrap()).unwrap();
    for p in report["shapes"][0]["photographs"].as_array().unwrap() {
        assert!(split.join(p.as_str().unwrap()).exists(), "{p} missing");
    }
}

#[test]
fn bad_shares_are_refused_naming_the_option() {
    let dir = tempfile::tempdir().unwrap();
    let plan = write_plan(dir.path());
    let out = dir.path().join("out");
    let (plan, out) = (plan.to_str().unwrap(), out.to_str().unwrap());
    let e = refused(&[
        "reproduce",
        "--plan",
        plan,
        "--out",
        out,
        "--task",
        "3",
        "--tasks",
        "3",
    ]);
    assert!(e.contains("--task 3") && e.contains("0..=2"), "{e}");
    let e = refused(&[
        "reproduce",
        "--plan",
        plan,
        "--out",
        out,
        "--task",
        "0",
        "--tasks",
        "0",
    ]);
    assert!(e.contains("--tasks 0"), "{e}");
    let e = refused(&[
        "reproduce",
        "--plan",
        plan,
        "--out",
        out,
        "--task",
        "-1",
        "--tasks",
        "2",
    ]);
    assert!(e.contains("--task"), "{e}");
    let e = refused(&["reproduce", "--plan", plan, "--out", out, "--task", "1"]);
    assert!(e.contains("--tasks"), "{e}");
    let e = refused(&["reproduce", "--plan", plan, "--out", out, "--tasks", "2"]);
    assert!(e.contains("--tasks"), "{e}");
    let slurm = dir.path().join("slurm");
    let slurm = slurm.to_str().unwrap();
    let e = refused(&[
        "reproduce",
        "--plan",
        plan,
        "--out",
        out,
        "--slurm",
        slurm,
        "--throttle",
        "0",
    ]);
    assert!(e.contains("--throttle 0"), "{e}");
    let e = refused(&[
        "reproduce",
        "--plan",
        plan,
        "--out",
        out,
        "--slurm",
        slurm,
        "--sbatch-line",
        "qos=long",
    ]);
    assert!(e.contains("--sbatch-line") && e.contains("qos=long"), "{e}");
    assert!(!dir.path().join("out").join("report.json").exists());
}

#[test]
fn slurm_scripts_run_the_shares_then_collect() {
    let dir = tempfile::tempdir().unwrap();
    let plan = write_plan(dir.path());
    let out = dir.path().join("out");
    let slurm = dir.path().join("slurm");
    ok(&[
        "reproduce",
        "--plan",
        plan.to_str().unwrap(),
        "--out",
        out.to_str().unwrap(),
        "--slurm",
        slurm.to_str().unwrap(),
        "--tasks",
        "2",
        "--throttle",
        "5",
        "--partition",
        "short",
        "--account",
        "granular",
        "--sbatch-line=--qos=long",
        "--sbatch-line",
        "#SBATCH --constraint=avx2",
        "--grain-steps-per-second",
        "1e5",
    ]);
    let read = |name: &str| std::fs::read_to_string(slurm.join(name)).unwrap();
    let (array, collect, submit) = (
        read("array.sbatch"),
        read("collect.sbatch"),
        read("submit.sh"),
    );
    let has = |text: &str, line: &str| text.lines().any(|l| l.trim() == line);
    // Three units over two tasks, at most five at once.
    assert!(has(&array, "#SBATCH --array=0-1%5"), "{array}");
    for text in [&array, &collect] {
        for line in [
            "#SBATCH --partition=short",
            "#SBATCH --account=granular",
            "#SBATCH --qos=long",
            "#SBATCH --constraint=avx2",
        ] {
            assert!(has(text, line), "{line} missing:\n{text}");
        }
        // Every #SBATCH line comes before the first command, or sbatch ignores it.
        let first_command = text
            .lines()
            .position(|l| !l.starts_with('#') && !l.trim().is_empty())
            .unwrap();
        assert!(
            text.lines()
                .skip(first_command)
                .all(|l| !l.starts_with("#SBATCH")),
            "{text}"
        );
    }
    let out_abs = std::path::absolute(&out).unwrap();
    assert!(
        array.contains("--task \"$SLURM_ARRAY_TASK_ID\" --tasks 2")
            && array.contains(&format!("--out '{}'", out_abs.display())),
        "{array}"
    );
    assert!(collect.contains("--collect --tasks 2"), "{collect}");
    // The estimates and the numbers behind them.
    assert!(
        array.contains("1.000e5 grain-steps per second (given)"),
        "{array}"
    );
    for option in ["--cpus-per-task=", "--mem=", "--time="] {
        assert!(array.contains(&format!("#SBATCH {option}")), "{option}");
    }
    assert!(array.contains("Largest task: 2 units"), "{array}");
    // The collect job waits for every task's success; submit.sh prints both ids.
    assert!(
        submit.contains("--dependency=afterok:\"$array\""),
        "{submit}"
    );
    assert!(submit.contains("echo \"array job: $array\"") && submit.contains("collect job"));
    // The tasks read the plan copied beside the scripts.
    let copied = std::fs::read_to_string(slurm.join("plan.json")).unwrap();
    assert!(copied.contains("\"shards\""));
    assert!(
        slurm.join("logs").is_dir(),
        "Slurm does not create the log folder"
    );
    #[cfg(unix)]
    {
        use std::os::unix::fs::PermissionsExt;
        let mode = std::fs::metadata(slurm.join("submit.sh"))
            .unwrap()
            .permissions()
            .mode();
        assert!(mode & 0o100 != 0, "submit.sh is not executable");
    }
}
