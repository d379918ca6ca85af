//! Filling a silo (issue 3): a scene becomes a world of walls, a feeder rains grains into it,
//! the deposit relaxes, and the run's folder receives the deposit, its contacts, the sidecar
//! the analysis reads, a VTK file and the run record.
//!
//! Files of a run folder: `deposit.csv`, `deposit.contacts.csv`, `deposit.meta.json` (read by
//! `facets analyse`), `grains.vtk` (ParaView), `run.json`, and `snapshots/step-N.vtk` on request.

mod feeder;
mod outline;
mod output;
mod record;
mod run;
mod silo;
mod vtk;

pub use feeder::{Feeder, Rain};
pub use outline::Placed;
pub use output::{check_writable, deposit_of, frame_of};
pub use record::{EnergiesRecord, RunRecord};
pub use run::{FillProgress, fill};
pub use silo::{FLOOR, LEFT_WALL, RIGHT_WALL, Silo};
pub use vtk::write_vtk;
