//! A silo-filling scene (issue 3): the silo, the grains, the feeder, the contact law, the run
//! and its outputs, read from a TOML file. Every field carries its unit in its name or its doc;
//! unknown fields are an error (docs/model.md §4). Errors name the file, the line and the field.

mod load;
mod time_step;
mod types;
mod validate;

pub use load::{load_scene, parse_scene};
pub use types::{
    ContactSection, FeedSection, FrameChoice, GrainSection, Insertion, ModelSection, OutputSection,
    PlateLaw, PlatesSection, RunSection, Scene, SiloSection, WallKind,
};
