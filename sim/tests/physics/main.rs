//! Physics tests of the engine: each compares with an exact or analytic answer.

mod apart_pairs;
mod checkpoint;
mod collisions;
mod common;
mod contact_table;
mod determinism;
mod drag;
mod energy;
mod impacts;
mod inputs;
mod plates;
mod resting;
mod sleeping;
mod slope;
mod work;
