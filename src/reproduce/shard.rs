//! Shares of a plan for several processes or machines (`--task K --tasks N`, `--collect`).
//!
//! A plan's independent work is a list of units in a fixed order: every filling of
//! [`simulate::fillings`](super::simulate::fillings) (shape, phi0, side, seed), then every real
//! photograph of the manifest. A photographed filling's unit also holds its photograph and its
//! detection. Task K of N takes the units k with k mod N = K. A unit's outputs depend only on
//! the plan and its seed, so any split writes the same files as one process.

use std::path::PathBuf;

use super::detect;
use super::layout::Layout;
use super::photograph::Photo;
use super::simulate::{self, Filling, Side};

/// Task `task` of `tasks` (counted from 0, as `$SLURM_ARRAY_TASK_ID`).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Shard {
    pub task: usize,
    pub tasks: usize,
}

impl Shard {
    /// Refuses a count of zero and a task outside 0..tasks, naming the options.
    pub fn new(task: usize, tasks: usize) -> anyhow::Result<Shard> {
        anyhow::ensure!(
            tasks >= 1,
            "--tasks {tasks}: expected at least 1 (the number of shares of the plan)"
        );
        anyhow::ensure!(
            task < tasks,
            "--task {task} with --tasks {tasks}: expected a task in 0..={} (tasks count from 0, as $SLURM_ARRAY_TASK_ID)",
            tasks - 1
        );
        Ok(Shard { task, tasks })
    }

    /// Whether unit `k` of the plan's list is this task's.
    pub fn takes(&self, k: usize) -> bool {
        k % self.tasks == self.task
    }
}

/// One independent piece of a plan's work.
#[derive(Clone, Debug)]
pub enum Unit {
    /// A filling; on the photographed side, its photograph and detection too.
    Filling(Box<Filling>),
    /// A real photograph (`--photos`) to detect.
    Photo(Photo),
}

impl Unit {
    /// What the unit is, for messages.
    pub fn describe(&self) -> String {
        match self {
            Unit::Filling(f) => format!(
                "{} phi0 = {} {} seed {}",
                f.kind.name(),
                f.phi0,
                match f.side {
                    Side::Simulation => "simulation",
                    Side::Photographed => "photographed",
                },
                f.seed
            ),
            Unit::Photo(p) => format!("photograph {}", p.path.display()),
        }
    }

    /// The photograph the unit detects, if any (a rendered one need not exist yet).
    pub fn photo_path(&self, layout: &Layout) -> Option<PathBuf> {
        match self {
            Unit::Filling(f) if f.side == Side::Photographed => {
                Some(layout.photo(f.kind, f.phi0, f.seed))
            }
            Unit::Filling(_) => None,
            Unit::Photo(p) => Some(p.path.clone()),
        }
    }

    /// The first of the unit's outputs that is missing, named with its path; None when the
    /// unit is done.
    pub fn missing(&self, layout: &Layout) -> Option<String> {
        let (kind, phi0) = match self {
            Unit::Filling(f) => {
                if simulate::done(f).is_none() {
                    return Some(format!("no finished filling in {}", f.dir.display()));
                }
                if f.side == Side::Simulation {
                    return None;
                }
                (f.kind, f.phi0)
            }
            Unit::Photo(p) => (p.kind, p.phi0),
        };
        let photo = self.photo_path(layout)?;
        if let Unit::Filling(_) = self {
            let truth = crate::photo::truth_path(&photo);
            for path in [&truth, &photo] {
                if !path.exists() {
                    return Some(format!("no {}", path.display()));
                }
            }
        }
        let table = detect::table_path(layout, kind, phi0, &photo);
        (!detect::table_done(&table)).then(|| format!("no detection table {}", table.display()))
    }
}

/// The plan's units in their fixed order: `fillings` (as [`simulate::fillings`] lists them),
/// then the real photographs.
pub fn units(fillings: Vec<Filling>, real: Option<Vec<Photo>>) -> Vec<Unit> {
    fillings
        .into_iter()
        .map(|f| Unit::Filling(Box::new(f)))
        .chain(real.into_iter().flatten().map(Unit::Photo))
        .collect()
}

/// The photographs that get an overlay for the report: the first of each (shape, phi0) in
/// the plan's order, whichever task detects it.
pub fn overlay_photos(units: &[Unit], layout: &Layout) -> Vec<PathBuf> {
    let mut seen = Vec::new();
    let mut out = Vec::new();
    for unit in units {
        let (kind, phi0) = match unit {
            Unit::Filling(f) => (f.kind, f.phi0),
            Unit::Photo(p) => (p.kind, p.phi0),
        };
        if let Some(path) = unit.photo_path(layout) {
            if !seen
                .iter()
                .any(|&(k, p): &(_, f64)| k == kind && (p - phi0).abs() < 1e-9)
            {
                seen.push((kind, phi0));
                out.push(path);
            }
        }
    }
    out
}

/// Every unit not done, with its index and what is missing; for `--collect`'s error.
pub fn missing(units: &[Unit], layout: &Layout) -> Vec<(usize, String)> {
    units
        .iter()
        .enumerate()
        .filter_map(|(k, u)| {
            u.missing(layout)
                .map(|m| (k, format!("{}: {m}", u.describe())))
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_unit_is_in_exactly_one_share() {
        for tasks in 1..6 {
            for k in 0..20 {
                let owners = (0..tasks)
                    .filter(|&t| Shard::new(t, tasks).unwrap().takes(k))
                    .count();
                assert_eq!(owners, 1, "unit {k} of {tasks} shares");
            }
        }
    }

    #[test]
    fn bad_shares_are_refused_by_option() {
        let e = Shard::new(0, 0).unwrap_err().to_string();
        assert!(e.contains("--tasks 0"), "{e}");
        let e = Shard::new(3, 3).unwrap_err().to_string();
        assert!(e.contains("--task 3") && e.contains("0..=2"), "{e}");
    }
}
