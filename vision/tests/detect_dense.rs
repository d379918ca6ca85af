//! The detector on dense touching configurations with known truth.

mod common;

use common::*;
use vision::{DetectParams, detect};

fn run(scene: &Scene, px_per_mm: f64, style: &Style) -> Metrics {
    let image = render(scene, px_per_mm, style);
    let found = detect(&image, &DetectParams::new(scene.shape, px_per_mm / MM)).unwrap();
    let m = compare(scene, &found);
    eprintln!("{m:?}");
    m
}

#[test]
fn rods_face_to_face() {
    let scene = rod_block(long_rod(), 0.35, 3, 6);
    let m = run(&scene, 10.0, &Style::lab());
    assert_eq!(m.recall(), 1.0, "{m:?}");
    assert_eq!(m.precision(), 1.0, "{m:?}");
    assert!(m.centre_max_mm < 0.1, "{m:?}");
    assert!(m.angle_max_deg < 1.0, "{m:?}");
}

#[test]
fn square_lattice_tilted() {
    let scene = square_lattice(0.3, 5, 4);
    let m = run(&scene, 10.0, &Style::lab());
    assert_eq!(m.recall(), 1.0, "{m:?}");
    assert_eq!(m.precision(), 1.0, "{m:?}");
    assert!(m.centre_max_mm < 0.1, "{m:?}");
    assert!(m.angle_max_deg < 1.0, "{m:?}");
}

#[test]
#[ignore]
fn debug_dump() {
    let scene = rod_block(long_rod(), 0.35, 3, 6);
    let image = render(&scene, 10.0, &Style::lab());
    image.save("/tmp/rods.png").unwrap();
    let found = detect(&image, &DetectParams::new(scene.shape, 10.0 / MM)).unwrap();
    for d in &found {
        eprintln!(
            "found {:.2} {:.2} {:.1} {:.2}",
            d.outline.x / MM,
            d.outline.y / MM,
            d.outline.theta.to_degrees(),
            d.confidence
        );
    }
    for g in &scene.grains {
        eprintln!(
            "truth {:.2} {:.2} {:.1}",
            g.0 / MM,
            g.1 / MM,
            g.2.to_degrees()
        );
    }
}
