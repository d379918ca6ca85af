//! Measures the detector on full-width frames made by the tests' image maker:
//! `cargo run --release -p vision --example measure_detect`.
//! Prints recall, precision, centre and orientation RMS and the time per photograph.

#[path = "../tests/common/mod.rs"]
mod common;

use std::time::Instant;

use common::*;
use vision::{DetectParams, detect};

fn main() {
    let scenes = [
        (
            "squares, sheared lattice 37 x 17",
            square_lattice(0.3, 37, 17),
        ),
        (
            "long rods, stacks 1 mm apart 20 x 35",
            rod_stacks(long_rod(), 0.35, 20, 35, 1.0 * MM),
        ),
        (
            "long rods, solid block 10 x 16",
            rod_block(long_rod(), 0.35, 10, 16),
        ),
        (
            "short rods, stacks 1 mm apart 30 x 35",
            rod_stacks(short_rod(), 0.35, 30, 35, 1.0 * MM),
        ),
    ];
    for (name, scene) in &scenes {
        for px_per_mm in [10.0, 6.0] {
            let image = render(scene, px_per_mm, &Style::lab());
            let params = DetectParams::new(scene.shape, px_per_mm / MM);
            let start = Instant::now();
            let found = detect(&image, &params).expect("detection");
            let secs = start.elapsed().as_secs_f64();
            let m = compare(scene, &found);
            println!(
                "{name} @ {px_per_mm} px/mm ({}x{} px): truth {} recall {:.4} precision {:.4} \
                 centre RMS {:.3} mm orientation RMS {:.2} deg  {:.2} s",
                image.width(),
                image.height(),
                m.truth,
                m.recall(),
                m.precision(),
                m.centre_rms_mm,
                m.angle_rms_deg,
                secs
            );
        }
    }
}
