//! What an earlier run left in a run folder: a fresh run there refuses to overwrite it unless
//! told to start over.

use std::path::{Path, PathBuf};

use anyhow::Context;

use super::checkpoint::CHECKPOINT_FILE;

/// The run record, written last by a finished run.
const RUN_RECORD: &str = "run.json";

/// An earlier run found in a run folder.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum EarlierRun {
    /// It finished: its record (`run.json`).
    Finished(PathBuf),
    /// It stopped and left this checkpoint (`checkpoint.bin`).
    Stopped(PathBuf),
}

/// The earlier run in `dir`, if any: a finished one (`run.json`; a checkpoint beside it was
/// left on the way), else a stopped one (`checkpoint.bin`).
pub fn earlier_run(dir: &Path) -> Option<EarlierRun> {
    let record = dir.join(RUN_RECORD);
    let checkpoint = dir.join(CHECKPOINT_FILE);
    if record.exists() {
        Some(EarlierRun::Finished(record))
    } else if checkpoint.exists() {
        Some(EarlierRun::Stopped(checkpoint))
    } else {
        None
    }
}

/// Refuses, naming every file and what to pass instead, to start runs in folders that hold
/// earlier ones.
pub fn refuse_earlier_runs(dirs: &[PathBuf]) -> anyhow::Result<()> {
    let found: Vec<EarlierRun> = dirs.iter().filter_map(|d| earlier_run(d)).collect();
    if found.is_empty() {
        return Ok(());
    }
    let lines: Vec<String> = found
        .iter()
        .map(|e| match e {
            EarlierRun::Finished(p) => format!("  {}: a finished run", p.display()),
            EarlierRun::Stopped(p) => format!("  {}: a stopped run's checkpoint", p.display()),
        })
        .collect();
    let stopped: Vec<String> = found
        .iter()
        .filter_map(|e| match e {
            EarlierRun::Stopped(p) => Some(p.display().to_string()),
            EarlierRun::Finished(_) => None,
        })
        .collect();
    let resume = if stopped.is_empty() {
        String::new()
    } else {
        format!(
            "pass --resume {} to continue the stopped runs, or ",
            stopped.join(" ")
        )
    };
    anyhow::bail!(
        "the output folders hold earlier runs:\n{}\n{resume}pass --restart to start over \
         (their files are replaced)",
        lines.join("\n")
    )
}

/// Removes what marks an earlier run in `dir` (its record and checkpoint), so that a run
/// started over and stopped is never taken for the earlier one.
pub fn clear_earlier_run(dir: &Path) -> anyhow::Result<()> {
    for name in [RUN_RECORD, CHECKPOINT_FILE] {
        let path = dir.join(name);
        if path.exists() {
            std::fs::remove_file(&path)
                .with_context(|| format!("cannot remove the earlier {}", path.display()))?;
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn earlier_runs_are_named_with_what_to_pass() {
        let dir = tempfile::tempdir().unwrap();
        let [fresh, stopped, finished] = ["seed-1", "seed-2", "seed-3"].map(|s| dir.path().join(s));
        for d in [&fresh, &stopped, &finished] {
            std::fs::create_dir_all(d).unwrap();
        }
        std::fs::write(stopped.join(CHECKPOINT_FILE), "").unwrap();
        std::fs::write(finished.join(CHECKPOINT_FILE), "").unwrap();
        std::fs::write(finished.join(RUN_RECORD), "{}").unwrap();
        refuse_earlier_runs(std::slice::from_ref(&fresh)).unwrap();
        let e = refuse_earlier_runs(&[fresh, stopped.clone(), finished.clone()])
            .unwrap_err()
            .to_string();
        let checkpoint = stopped.join(CHECKPOINT_FILE).display().to_string();
        assert!(
            e.contains(&format!("--resume {checkpoint}"))
                && e.contains(&finished.join(RUN_RECORD).display().to_string())
                && e.contains("--restart"),
            "{e}"
        );
        clear_earlier_run(&finished).unwrap();
        assert_eq!(earlier_run(&finished), None);
    }
}
