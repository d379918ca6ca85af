//! Filling a silo (issue 3): a scene becomes a world of walls, a feeder rains grains into it,
//! the deposit relaxes, and the run's folder receives the deposit, its contacts, the sidecar
//! the analysis reads, a VTK file and the run record.
//!
//! Files of a run folder: `deposit.csv`, `deposit.contacts.csv`, `deposit.meta.json` (read by
//! `facets analyse`), `grains.vtu` (VTK for ParaView, meshio), `run.json`, and
//! `snapshots/step-N.vtu` on request; `checkpoint.bin` when the run is stopped (Ctrl-C) or asked
//! for periodic checkpoints.

mod checkpoint;
mod earlier;
mod ensemble;
mod feeder;
mod outline;
mod output;
mod record;
mod run;
mod runs;
mod silo;
mod vtk;
mod walls;

pub use checkpoint::{CHECKPOINT_FILE, Checkpoint, scene_hash};
pub use earlier::{EarlierRun, clear_earlier_run, earlier_run, refuse_earlier_runs};
pub use ensemble::{FillEvent, FillJob, fill_all};
pub use feeder::{Feeder, FeederState, Rain};
pub use outline::Placed;
pub use output::{check_writable, deposit_of, frame_of};
pub use record::{EnergiesRecord, RunRecord};
pub use run::{
    FillControl, FillOutcome, FillProgress, STEPS_BETWEEN_STOP_CHECKS, StopAt, fill, fill_with,
};
pub use runs::{PlannedRun, Runs, default_out, planned_runs};
pub use silo::{FLOOR, LEFT_WALL, RIGHT_WALL, Silo};
pub use vtk::{GRAINS_VTK, write_vtk};
