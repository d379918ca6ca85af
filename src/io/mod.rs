//! File output shared by every command.

mod atomic;

pub use atomic::write_atomic;
