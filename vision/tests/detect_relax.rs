//! The joint relaxation (`DetectParams::relax`) on gap-free configurations where a grain fitted
//! alone can turn or slip into its neighbours: nut lattices flat and diamond, stacks of
//! parallel rods of both sizes, and a block of rods cut by every edge of the frame. What a
//! user needs: every grain found once, its angle within a degree or two, and no two
//! outlines overlapping by more than a pixel.

mod common;

use common::*;
use vision::{DetectParams, Detection, ScaleCheck, detect};

const PX_PER_MM: f64 = 10.0;

/// Nuts face to face in a `columns` x `rows` lattice turned by `angle`, with no gap: every
/// nut's outline meets its neighbours' on all sides.
fn nut_lattice(angle: f64, columns: usize, rows: usize) -> Scene {
    let side = nut().width();
    let (s, c) = angle.sin_cos();
    let size = (columns.max(rows) as f64 + 3.0) * side * 1.5;
    let mut grains = Vec::new();
    for j in 0..rows {
        for i in 0..columns {
            let a = (i as f64 - 0.5 * (columns as f64 - 1.0)) * side;
            let b = (j as f64 - 0.5 * (rows as f64 - 1.0)) * side;
            grains.push((
                0.5 * size + a * c - b * s,
                0.5 * size + a * s + b * c,
                angle,
            ));
        }
    }
    Scene {
        shape: nut(),
        width: size,
        height: size,
        grains,
    }
}

/// Whether the point (metres) lies inside the outline shrunk by `inset` (metres) on every
/// side.
fn inside(d: &Detection, x: f64, y: f64, inset: f64) -> bool {
    let o = &d.outline;
    let (s, c) = o.theta.sin_cos();
    let (dx, dy) = (x - o.x, y - o.y);
    let (u, v) = (dx * c + dy * s, -dx * s + dy * c);
    u.abs() < 0.5 * o.shape.length() - inset && v.abs() < 0.5 * o.shape.width() - inset
}

/// Points (on a grid of a tenth of a pixel) that two detected outlines, each shrunk by a
/// pixel, both hold: none when no two overlap by more than a pixel.
fn overlapping_points(found: &[Detection]) -> usize {
    let pixel = 1e-3 / PX_PER_MM;
    let step = 0.1 * pixel;
    let mut shared = 0;
    for (i, a) in found.iter().enumerate() {
        let reach = 0.5 * a.outline.shape.length().hypot(a.outline.shape.width());
        for b in &found[i + 1..] {
            if (a.outline.x - b.outline.x).hypot(a.outline.y - b.outline.y) > 2.0 * reach {
                continue;
            }
            let n = (2.0 * reach / step) as i64;
            for k in -n..=n {
                for l in -n..=n {
                    let (x, y) = (a.outline.x + k as f64 * step, a.outline.y + l as f64 * step);
                    if inside(a, x, y, pixel) && inside(b, x, y, pixel) {
                        shared += 1;
                    }
                }
            }
        }
    }
    shared
}

fn detect_relaxed(scene: &Scene) -> Vec<Detection> {
    let image = render(scene, PX_PER_MM, &Style::lab());
    // A solid block of rods shows no single rod's thickness: the scale check, another
    // stage's concern, is left out.
    let params = DetectParams {
        scale_check: ScaleCheck::Off,
        relax: true,
        ..DetectParams::new(scene.shape, PX_PER_MM / MM)
    };
    detect(&image, &params).expect("detection")
}

/// Every grain found once, the angles within `angle_rms` (RMS) and `angle_max` degrees, and
/// no overlap beyond a pixel.
fn assert_found(scene: &Scene, found: &[Detection], angle_rms: f64, angle_max: f64) {
    let m = compare(scene, found);
    eprintln!("{m:?}");
    assert_eq!(m.recall(), 1.0, "{m:?}");
    assert_eq!(m.precision(), 1.0, "{m:?}");
    assert!(m.centre_rms_mm < 0.1, "{m:?}");
    assert!(
        m.angle_rms_deg < angle_rms && m.angle_max_deg < angle_max,
        "{m:?}"
    );
    assert_eq!(overlapping_points(found), 0, "outlines overlap");
}

/// A flat lattice: the nuts' holes give the centres exactly, and only the neighbours' centres
/// pin each nut's angle.
#[test]
fn a_flat_gap_free_nut_lattice_is_found_unturned() {
    let scene = nut_lattice(0.02, 6, 5);
    let found = detect_relaxed(&scene);
    assert_found(&scene, &found, 1.0, 2.0);
}

/// The same lattice turned by 45 degrees: a nut turned by half its symmetry period in place
/// is the greedy fit's mistake here.
#[test]
fn a_diamond_gap_free_nut_lattice_is_found_unturned() {
    let scene = nut_lattice(std::f64::consts::FRAC_PI_4 + 0.02, 6, 5);
    let found = detect_relaxed(&scene);
    assert_found(&scene, &found, 1.0, 2.0);
}

/// Stacks of parallel rods face to face, the stacks' ends touching (staggered rows): the
/// seams between rods show only as their highlights.
#[test]
#[ignore = "fails: one rod of 28 missed, one 5.7 degrees off (the greedy fit alone: 27 degrees \
            RMS); docs/results/detector-bench.md, \"Joint relaxation\""]
fn stacks_of_parallel_short_rods_are_found_unslipped() {
    let scene = rod_block(short_rod(), 0.1, 4, 7);
    let found = detect_relaxed(&scene);
    assert_found(&scene, &found, 1.5, 3.0);
}

#[test]
fn stacks_of_parallel_long_rods_are_found_unslipped() {
    let scene = rod_block(long_rod(), 0.1, 3, 7);
    let found = detect_relaxed(&scene);
    assert_found(&scene, &found, 1.5, 3.0);
}

/// A block of rods larger than the frame, cut by all four edges: every rod whose centre
/// lies a width or more inside the frame found, at its angle; none overlapping another.
#[test]
#[ignore = "fails: 24 of 28 rods inside found, some turned, with or without the relaxation; \
            docs/results/detector-bench.md, \"Joint relaxation\""]
fn rods_cut_by_every_edge_are_found() {
    let block = rod_block(short_rod(), 0.3, 6, 12);
    // The frame: the middle of the block, a rod length in from its extent on every side.
    let (xs, ys): (Vec<f64>, Vec<f64>) = block.grains.iter().map(|g| (g.0, g.1)).unzip();
    let lo = |v: &[f64]| v.iter().copied().fold(f64::INFINITY, f64::min);
    let hi = |v: &[f64]| v.iter().copied().fold(f64::NEG_INFINITY, f64::max);
    let l = short_rod().length();
    let (x0, y0) = (lo(&xs) + l, lo(&ys) + l);
    let (w, h) = (hi(&xs) - lo(&xs) - 2.0 * l, hi(&ys) - lo(&ys) - 2.0 * l);
    let scene = Scene {
        shape: block.shape,
        width: w,
        height: h,
        grains: block
            .grains
            .iter()
            .map(|&(x, y, t)| (x - x0, y - y0, t))
            .collect(),
    };
    let found = detect_relaxed(&scene);
    let d = short_rod().width();
    let well_inside = Scene {
        grains: scene
            .grains
            .iter()
            .copied()
            .filter(|&(x, y, _)| x > d && y > d && x < w - d && y < h - d)
            .collect(),
        ..scene
    };
    let m = compare(&well_inside, &found);
    eprintln!("{m:?}");
    eprintln!("all: {:?}", compare(&scene, &found));
    assert_eq!(m.recall(), 1.0, "{m:?}");
    assert!(m.angle_rms_deg < 1.5 && m.angle_max_deg < 3.0, "{m:?}");
    assert_eq!(overlapping_points(&found), 0, "outlines overlap");
    // Every detection is a rod of the scene (cut ones included): none invented over the edge.
    let all = compare(&scene, &found);
    eprintln!("all: {all:?}");
    assert_eq!(all.precision(), 1.0, "{all:?}");
}
