//! The deposit model: a table of grains (centre, orientation, outline), whatever made it
//! (a photograph or a simulation), its contacts when simulated, and its sidecar. SI units
//! inside; millimetres in files (docs/model.md §4).
//!
//! Files of one deposit `NAME`:
//! - `NAME.csv` — grains (`x_mm,y_mm,theta_rad,length_mm,width_mm[,confidence,cut]`);
//! - `NAME.contacts.csv` — contacts (`i,j,fx_N,fy_N,cx_mm,cy_mm`; `i`, `j` are 0-based rows of
//!   `NAME.csv`; j = -1 left wall, -2 right wall, -3 floor), simulated deposits only;
//! - `NAME.meta.json` — silo width, phi0, frame, source (see [`DepositMeta`]).
//!
//! x = 0 is the silo's left wall, y = 0 the floor (for a photograph: y of its frame in the
//! silo, given by `frame_mm`). The analysed area is the frame less 40 mm at each side wall.

mod area;
mod built;
mod contact;
mod ensemble;
mod folders;
mod grain;
mod meta;
mod shape;
mod synthetic;
mod table;

pub use area::{AnalysedArea, WALL_MARGIN};
pub use built::SquareStack;
pub use contact::{Contact, Partner, Wall, read_contacts_csv, write_contacts_csv};
pub use ensemble::{Ensemble, LoadOptions, Realisation, load_realisation};
pub use folders::deposit_tables;
pub use grain::{Grain, fold_angle};
pub use meta::{
    DepositMeta, FrameMm, Source, contacts_path, meta_path, read_meta_json, write_meta_json,
};
pub use synthetic::jittered_lattice;
pub use table::{
    Deposit, parse_deposit_text, read_deposit_csv, write_deposit_csv, write_detected_csv,
};
