//! Checkpoint and resume (issue 3): a run stopped and resumed writes the same files, byte for
//! byte, as a run that was never stopped; periodic checkpoints and snapshots survive a resume;
//! a checkpoint is refused for another scene or seed; Ctrl-C leaves a checkpoint to resume.

use std::path::{Path, PathBuf};
use std::process::Command;

use facets::fill::{
    CHECKPOINT_FILE, Checkpoint, FillControl, FillOutcome, StopAt, fill, fill_with, scene_hash,
};
use facets::scene::{Scene, parse_scene};

/// 60 squares, stopped 0.05 s after the last one is in: the filling, its bands and part of the
/// relaxation (the energy window, the load checks) all lie on either side of a checkpoint.
/// A snapshot every 1 000 steps and a checkpoint every 20 ms of simulated time.
const SCENE: &str = r#"
[silo]
width_mm = 96

[grains]
kind = "square"
count = 60

[feed]
phi0 = 0.1

[run]
time_step_s = 4e-6
relaxation_ratio = 1e-3
max_relaxation_time_s = 0.05

[output]
snapshot_every_steps = 1000
checkpoint_every_s = 0.02
"#;

fn scene() -> Scene {
    parse_scene(SCENE, "resume.toml").unwrap()
}

/// The files of a run folder, run.json without its wall time.
fn files(dir: &Path) -> Vec<(String, Vec<u8>)> {
    let mut names: Vec<PathBuf> = ["deposit.csv", "deposit.contacts.csv", "grains.vtu"]
        .iter()
        .map(|n| dir.join(n))
        .collect();
    let mut snapshots: Vec<PathBuf> = std::fs::read_dir(dir.join("snapshots"))
        .unwrap()
        .map(|e| e.unwrap().path())
        .collect();
    snapshots.sort();
    names.extend(snapshots);
    let mut out: Vec<(String, Vec<u8>)> = names
        .iter()
        .map(|p| {
            let name = p.strip_prefix(dir).unwrap().display().to_string();
            (name, std::fs::read(p).unwrap())
        })
        .collect();
    let mut record: serde_json::Value =
        serde_json::from_slice(&std::fs::read(dir.join("run.json")).unwrap()).unwrap();
    record.as_object_mut().unwrap().remove("wall_time_s");
    out.push(("run.json".into(), record.to_string().into_bytes()));
    out
}

fn assert_same_files(a: &Path, b: &Path, what: &str) {
    let (x, y) = (files(a), files(b));
    let names = |f: &[(String, Vec<u8>)]| f.iter().map(|n| n.0.clone()).collect::<Vec<_>>();
    assert_eq!(names(&x), names(&y), "{what}: not the same files");
    for ((name, p), (_, q)) in x.iter().zip(&y) {
        assert!(
            p == q,
            "{what}: {name} differs from the uninterrupted run's"
        );
    }
}

fn stopped_at(outcome: FillOutcome) -> (PathBuf, u64) {
    match outcome {
        FillOutcome::Stopped {
            checkpoint, steps, ..
        } => (checkpoint, steps),
        FillOutcome::Finished(_) => panic!("the run should have stopped"),
    }
}

#[test]
fn stopped_and_resumed_runs_write_the_same_files() {
    let scene = scene();
    let whole = tempfile::tempdir().unwrap();
    let record = fill(&scene, 3, whole.path(), &mut |_| {}).unwrap();
    let fill_steps = (record.fill_time_s / record.time_step_s) as u64;
    // Two stops off the loop's own decision points: one while grains rain in, one while
    // the deposit relaxes.
    let first = record.steps / 3 + 7;
    let second = (fill_steps + record.steps) / 2 + 13;
    assert!(first < fill_steps && second > fill_steps && second < record.steps);

    let parts = tempfile::tempdir().unwrap();
    let stop = |stop, resume| FillControl {
        resume,
        stop,
        interrupt: None,
    };
    let (path, steps) = stopped_at(
        fill_with(
            &scene,
            3,
            parts.path(),
            stop(StopAt::Steps(first), None),
            &mut |_| {},
        )
        .unwrap(),
    );
    assert_eq!(steps, first);
    assert!(!parts.path().join("deposit.csv").exists());
    let resume = Checkpoint::read(&path).unwrap();
    assert_eq!(resume.progress().1, first);
    let (path, steps) = stopped_at(
        fill_with(
            &scene,
            3,
            parts.path(),
            stop(StopAt::Steps(second), Some(resume)),
            &mut |_| {},
        )
        .unwrap(),
    );
    assert_eq!(steps, second);
    let resume = Some(Checkpoint::read(&path).unwrap());
    let end = fill_with(
        &scene,
        3,
        parts.path(),
        stop(StopAt::Never, resume),
        &mut |_| {},
    );
    assert!(matches!(end.unwrap(), FillOutcome::Finished(_)));
    assert_same_files(whole.path(), parts.path(), "stopped twice");

    // The uninterrupted run left its last periodic checkpoint (every 20 ms): resumed into an
    // empty folder, it writes the rest of the snapshots and the same final files.
    let periodic = Checkpoint::read(&whole.path().join(CHECKPOINT_FILE)).unwrap();
    let (time, checkpoint_step) = periodic.progress();
    let last = (record.simulated_time_s / 0.02).floor() * 0.02;
    assert!((time - last).abs() < 2e-3, "checkpoint at {time} s");
    let later = tempfile::tempdir().unwrap();
    let control = stop(StopAt::Never, Some(periodic));
    fill_with(&scene, 3, later.path(), control, &mut |_| {}).unwrap();
    let before_checkpoint = |name: &str| {
        name.strip_prefix("snapshots/step-")
            .and_then(|s| s.strip_suffix(".vtu"))
            .is_some_and(|s| s.parse::<u64>().unwrap() <= checkpoint_step)
    };
    let whole_files: Vec<_> = files(whole.path())
        .into_iter()
        .filter(|(n, _)| !before_checkpoint(n))
        .collect();
    let later_files = files(later.path());
    assert!(
        later_files.iter().any(|(n, _)| n.starts_with("snapshots/")),
        "{time} s, {} steps",
        record.steps
    );
    assert!(whole_files == later_files, "resumed periodic checkpoint");
}

#[test]
fn a_checkpoint_of_another_scene_or_seed_is_refused() {
    let mut scene = scene();
    scene.grains.count = 20;
    scene.output.snapshot_every_steps = None;
    let dir = tempfile::tempdir().unwrap();
    let control = FillControl {
        stop: StopAt::Time(0.01),
        ..FillControl::default()
    };
    let (path, steps) = stopped_at(fill_with(&scene, 3, dir.path(), control, &mut |_| {}).unwrap());
    assert_eq!(steps, 2500, "0.01 s of 4 us steps");

    let mut other = scene.clone();
    other.feed.phi0 = 0.05;
    let refused = |scene: &Scene, seed| {
        let out = tempfile::tempdir().unwrap();
        let control = FillControl {
            resume: Some(Checkpoint::read(&path).unwrap()),
            ..FillControl::default()
        };
        let e = fill_with(scene, seed, out.path(), control, &mut |_| {}).unwrap_err();
        // Refused before anything is simulated or written.
        assert!(!out.path().join("deposit.csv").exists());
        format!("{e:#}")
    };
    let e = refused(&other, 3);
    let (mine, theirs) = (scene_hash(&scene, 3), scene_hash(&other, 3));
    assert_ne!(mine, theirs);
    assert!(
        e.contains(&format!("{mine:016x}"))
            && e.contains(&format!("{theirs:016x}"))
            && e.contains("[feed]")
            && !e.contains("[grains]"),
        "{e}"
    );
    let e = refused(&scene, 4);
    assert!(
        e.contains("seed 3") && e.contains("seed 4") && e.contains("differ in the seed"),
        "{e}"
    );

    // Not a checkpoint, and a checkpoint cut short.
    let bytes = std::fs::read(&path).unwrap();
    let bad = dir.path().join("bad.bin");
    std::fs::write(&bad, b"[grains]\n").unwrap();
    let e = format!("{:#}", Checkpoint::read(&bad).unwrap_err());
    assert!(
        e.contains("bad.bin") && e.contains("not a facets checkpoint"),
        "{e}"
    );
    std::fs::write(&bad, &bytes[..bytes.len() / 2]).unwrap();
    let e = format!("{:#}", Checkpoint::read(&bad).unwrap_err());
    assert!(e.contains("truncated or corrupt"), "{e}");
}

#[cfg(unix)]
#[test]
fn ctrl_c_writes_a_checkpoint_that_resumes_to_the_same_files() {
    let dir = tempfile::tempdir().unwrap();
    // A longer relaxation, so that the run is still going when the signal comes; sleeping
    // grains on, so that their state goes through the checkpoint too.
    let text = SCENE
        .replace(
            "max_relaxation_time_s = 0.05",
            "max_relaxation_time_s = 0.3\n\n[model]\nsleep = true",
        )
        .replace("snapshot_every_steps = 1000\n", "");
    let scene = dir.path().join("scene.toml");
    std::fs::write(&scene, text).unwrap();
    let facets = || {
        let mut c = Command::new(env!("CARGO_BIN_EXE_facets"));
        c.arg("sim").arg(&scene);
        c
    };
    let (whole, stopped) = (dir.path().join("whole"), dir.path().join("stopped"));
    let o = facets().arg("--out").arg(&whole).output().unwrap();
    assert!(whole.join("seed-1/deposit.csv").exists(), "{o:?}");

    let child = facets()
        .arg("--out")
        .arg(&stopped)
        .stderr(std::process::Stdio::piped())
        .spawn()
        .unwrap();
    // Interrupt once the first periodic checkpoint shows the run is under way.
    let periodic = stopped.join("seed-1").join(CHECKPOINT_FILE);
    let start = std::time::Instant::now();
    while !periodic.exists() {
        assert!(start.elapsed().as_secs() < 120, "no checkpoint appeared");
        std::thread::sleep(std::time::Duration::from_millis(2));
    }
    // SAFETY: kill(2) on the pid of a child this test spawned and has not yet waited for.
    assert_eq!(unsafe { libc::kill(child.id() as i32, libc::SIGINT) }, 0);
    let o = child.wait_with_output().unwrap();
    let e = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(130), "{e}");
    assert!(e.contains("resume with") && e.contains("--resume"), "{e}");
    assert!(!stopped.join("seed-1/deposit.csv").exists(), "{e}");

    facets().arg("--resume").arg(&periodic).output().unwrap();
    for name in ["deposit.csv", "deposit.contacts.csv", "grains.vtu"] {
        let a = std::fs::read(whole.join("seed-1").join(name)).unwrap();
        let b = std::fs::read(stopped.join("seed-1").join(name)).unwrap();
        assert!(a == b, "{name}: the resumed run differs");
    }
}
