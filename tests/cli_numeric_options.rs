//! Every numeric option of `facets analyse`, `render` and `detect` given zero, negative, NaN,
//! infinite or out-of-range values: the command exits with an error that names the option,
//! writes no result, and does not hang (a run still going after the deadline is killed and
//! fails the test).

use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};
use std::time::{Duration, Instant};

/// Far above the time a refused option takes (reading a small sample and checking numbers), so
/// that only a hang or a full analysis reaches it, even on a busy machine.
const DEADLINE: Duration = Duration::from_secs(60);

/// Values no floating-point option takes.
const NONSENSE: [&str; 5] = ["0", "-1", "NaN", "inf", "-inf"];

fn sample(path: &str) -> String {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("data-samples")
        .join(path)
        .display()
        .to_string()
}

/// One command to try: its arguments before the option, the option, the values it must refuse,
/// and the arguments after.
struct Case {
    before: Vec<String>,
    option: &'static str,
    values: Vec<&'static str>,
    after: Vec<String>,
}

fn strings(args: &[&str]) -> Vec<String> {
    args.iter().map(|s| s.to_string()).collect()
}

fn cases(out: &Path) -> Vec<Case> {
    let out = out.display().to_string();
    let stack = sample("deposits/stack.csv");
    let analyse = |option: &'static str, values: Vec<&'static str>, after: &[&str]| Case {
        before: vec![
            "analyse".into(),
            stack.clone(),
            "--out".into(),
            format!("{out}/analyse"),
        ],
        option,
        values,
        after: strings(after),
    };
    let frames = vec!["0,0,0,0", "10,0,0,50", "NaN,100,0,50", "0,inf,0,50"];
    let mut all = vec![
        analyse("--w-over-d", NONSENSE.to_vec(), &[]),
        analyse("--w-scan", NONSENSE.to_vec(), &[]),
        analyse("--w-scan", vec!["1,0,3", "1,NaN"], &[]),
        analyse("--cutoff", NONSENSE.to_vec(), &[]),
        analyse("--cutoff", vec!["1e300"], &[]),
        analyse("--phi0", NONSENSE.to_vec(), &["--silo-width-mm", "165.6"]),
        analyse("--silo-width-mm", NONSENSE.to_vec(), &["--phi0", "0.1"]),
        analyse(
            "--frame-mm",
            frames.clone(),
            &["--phi0", "0.1", "--silo-width-mm", "165.6"],
        ),
        analyse("--frame-mm", vec!["0,100,0,50"], &[]),
    ];

    let render = |option: &'static str, values: Vec<&'static str>, args: &[&str]| Case {
        before: [strings(&["render"]), strings(args)].concat(),
        option,
        values,
        after: vec!["--out".into(), format!("{out}/photo.png")],
    };
    let deposit = sample("deposits/photo.csv");
    all.extend([
        render("--px-per-mm", NONSENSE.to_vec(), &[&deposit]),
        render("--px-per-mm", NONSENSE.to_vec(), &["--generate", "square"]),
        render("--px-per-mm", vec!["1e6"], &[&deposit]),
        render(
            "--frame-mm",
            frames.clone(),
            &[&deposit, "--px-per-mm", "5"],
        ),
        render("--bits", vec!["0", "-1", "NaN", "inf"], &[&deposit]),
        render("--seed", vec!["-1", "NaN", "inf"], &[&deposit]),
    ]);

    let detect = |option: &'static str, values: Vec<&'static str>, args: &[&str]| Case {
        before: [strings(&["detect"]), strings(args)].concat(),
        option,
        values,
        after: vec![
            "--out".into(),
            format!("{out}/detect"),
            sample("photos/rod53-lab-10px.png"),
        ],
    };
    let rods = ["--shape", "rod53"];
    let rods_at_10 = ["--shape", "rod53", "--px-per-mm", "10"];
    let custom_at_10 = ["--shape", "rod", "--px-per-mm", "10"];
    let in_silo = ["--phi0", "0.1", "--silo-width-mm", "160"];
    all.extend([
        detect("--px-per-mm", NONSENSE.to_vec(), &rods),
        detect("--px-per-mm", NONSENSE.to_vec(), &["--shape", "square"]),
        detect("--px-per-mm", vec!["0.1", "1e5"], &rods),
        detect(
            "--length-mm",
            vec!["0", "-1", "NaN", "inf", "2", "1000"],
            &custom_at_10,
        ),
        detect(
            "--width-mm",
            [NONSENSE.to_vec(), vec!["7"]].concat(),
            &[&custom_at_10[..], &["--length-mm", "6"]].concat(),
        ),
        // A size with a named kind: the kind has its own.
        detect("--length-mm", vec!["6"], &rods_at_10),
        detect(
            "--phi0",
            [NONSENSE.to_vec(), vec!["1.5"]].concat(),
            &[&rods_at_10[..], &["--silo-width-mm", "160"]].concat(),
        ),
        detect(
            "--silo-width-mm",
            NONSENSE.to_vec(),
            &[&rods_at_10[..], &["--phi0", "0.1"]].concat(),
        ),
        detect(
            "--frame-mm",
            frames.clone(),
            &[&rods_at_10[..], &in_silo[..]].concat(),
        ),
        // The sample is 60 x 40 mm at 10 px/mm: a frame of another size is not its frame.
        detect(
            "--frame-mm",
            vec!["0,120,0,40", "0,60,0,80"],
            &[&rods_at_10[..], &in_silo[..]].concat(),
        ),
        detect(
            "--min-confidence",
            vec!["-1", "NaN", "inf", "1.5"],
            &rods_at_10,
        ),
        detect(
            "--finalists",
            vec!["0", "-1", "NaN", "inf", "1000000000"],
            &rods_at_10,
        ),
        detect(
            "--settle-sweeps",
            vec!["-1", "NaN", "inf", "1000000000"],
            &rods_at_10,
        ),
    ]);
    all
}

/// Runs the command to its end or the deadline: (exit status success, stderr).
fn run(args: &[String]) -> (bool, String) {
    let mut child = Command::new(env!("CARGO_BIN_EXE_facets"))
        .args(args)
        .stdout(Stdio::null())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    let start = Instant::now();
    let status = loop {
        if let Some(status) = child.try_wait().unwrap() {
            break status;
        }
        if start.elapsed() > DEADLINE {
            child.kill().unwrap();
            child.wait().unwrap();
            panic!("facets {} still ran after {DEADLINE:?}", args.join(" "));
        }
        std::thread::sleep(Duration::from_millis(20));
    };
    let mut stderr = String::new();
    std::io::Read::read_to_string(&mut child.stderr.take().unwrap(), &mut stderr).unwrap();
    (status.success(), stderr)
}

#[test]
fn every_numeric_option_refuses_nonsense_values_by_name() {
    let dir = tempfile::tempdir().unwrap();
    for case in cases(dir.path()) {
        for value in &case.values {
            // `--option=value`: a value starting with '-' is not taken for an option.
            let args = [
                case.before.clone(),
                vec![format!("{}={value}", case.option)],
                case.after.clone(),
            ]
            .concat();
            let (success, stderr) = run(&args);
            let line = format!("facets {}", args.join(" "));
            assert!(!success, "{line}: exit 0\n{stderr}");
            assert!(
                stderr.contains(case.option),
                "{line}: the error does not name {}:\n{stderr}",
                case.option
            );
            assert!(
                !stderr.contains("panicked"),
                "{line}: a panic, not an error:\n{stderr}"
            );
        }
    }
    // Nothing was written: no summary, photograph or table.
    let written: Vec<PathBuf> = walk(dir.path());
    assert!(written.is_empty(), "files written: {written:?}");
}

/// The files under `dir` (folders left empty do not count).
fn walk(dir: &Path) -> Vec<PathBuf> {
    let mut files = Vec::new();
    for entry in std::fs::read_dir(dir).unwrap() {
        let path = entry.unwrap().path();
        if path.is_dir() {
            files.extend(walk(&path));
        } else {
            files.push(path);
        }
    }
    files
}

#[test]
fn the_defaults_and_sensible_values_are_accepted() {
    // The checks must not refuse what the commands are for: the sample analysed with the
    // edges of the ranges the errors state.
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("analyse");
    let args = strings(&[
        "analyse",
        &sample("deposits/stack.csv"),
        "--w-over-d",
        "0.5",
        "--w-scan",
        "1,6",
        "--cutoff",
        "3",
        "--out",
        &out.display().to_string(),
    ]);
    let (success, stderr) = run(&args);
    assert!(success, "{stderr}");
    assert!(out.join("summary.json").exists());
}

mod random_values {
    use super::*;
    use proptest::prelude::*;

    /// Zero, negative, NaN or infinite: no width, cut-off, scale or fraction takes these.
    fn nonsense() -> impl Strategy<Value = f64> {
        prop_oneof![
            Just(0.0),
            Just(f64::NAN),
            Just(f64::INFINITY),
            Just(f64::NEG_INFINITY),
            -1e300..0.0f64,
        ]
    }

    proptest! {
        #![proptest_config(ProptestConfig::with_cases(24))]

        #[test]
        fn commands_refuse_nonsense_by_name(
            value in nonsense(),
            pick in 0usize..6,
        ) {
            let dir = tempfile::tempdir().unwrap();
            let out = dir.path().display().to_string();
            let (command, option, rest): (Vec<String>, &str, Vec<&str>) = match pick {
                0 => (strings(&["analyse", &sample("deposits/stack.csv")]), "--w-over-d", vec![]),
                1 => (strings(&["analyse", &sample("deposits/stack.csv")]), "--w-scan", vec![]),
                2 => (strings(&["analyse", &sample("deposits/stack.csv")]), "--cutoff", vec![]),
                3 => (
                    strings(&["analyse", &sample("deposits/stack.csv")]),
                    "--phi0",
                    vec!["--silo-width-mm", "165.6"],
                ),
                4 => (strings(&["render", &sample("deposits/photo.csv")]), "--px-per-mm", vec![]),
                _ => (
                    strings(&["detect", "--shape", "square", &sample("photos/square-lab-10px.png")]),
                    "--px-per-mm",
                    vec![],
                ),
            };
            let args = [
                command,
                vec![format!("{option}={value}")],
                strings(&rest),
                vec!["--out".into(), format!("{out}/result.png")],
            ]
            .concat();
            let (success, stderr) = run(&args);
            prop_assert!(!success, "{args:?}: exit 0\n{stderr}");
            prop_assert!(stderr.contains(option), "{args:?}:\n{stderr}");
            prop_assert!(walk(dir.path()).is_empty(), "{args:?}: wrote a file");
        }
    }
}
