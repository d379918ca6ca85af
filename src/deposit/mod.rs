//! The deposit model: a table of grains (centre, orientation, outline), whatever made it
//! (a photograph or a simulation). SI units inside; millimetres in files (SPEC §4).

mod grain;
mod table;

pub use grain::{Grain, fold_angle};
pub use table::{Deposit, read_deposit_csv, write_deposit_csv};
