//! The detector's behaviour on edge cases: cut grains, empty photographs, wrong scales,
//! 16-bit input, squares at angles beyond 45 degrees.

mod common;

use common::*;
use image::{DynamicImage, GrayImage, Luma};
use vision::{DetectError, DetectParams, ScaleCheck, detect};

#[test]
fn square_angle_recovered_modulo_quarter_turn() {
    // 110 degrees is 20 degrees for a square.
    let scene = square_lattice(110f64.to_radians(), 3, 3);
    let image = render(&scene, 10.0, &Style::lab());
    let found = detect(&image, &DetectParams::new(scene.shape, 10.0 / MM)).unwrap();
    let m = compare(&scene, &found);
    assert_eq!(m.matched, 9, "{m:?}");
    for d in &found {
        assert!(d.outline.theta >= 0.0 && d.outline.theta < std::f64::consts::FRAC_PI_2);
        assert!((d.outline.theta.to_degrees() - 20.0).abs() < 3.0, "{d:?}");
    }
}

#[test]
fn grains_cut_by_the_frame_are_flagged() {
    // A 3 x 3 lattice with the frame moved so the left grains are cut (the sheared middle
    // row's is not): centres stay inside the frame, outlines cross its edge.
    let mut scene = square_lattice(0.0, 3, 3);
    let side = scene.shape.width();
    let left = scene
        .grains
        .iter()
        .map(|g| g.0)
        .fold(f64::INFINITY, f64::min);
    let shift = left - 0.2 * side;
    for g in &mut scene.grains {
        g.0 -= shift;
    }
    scene.width -= shift;
    let image = render(&scene, 10.0, &Style::lab());
    let found = detect(&image, &DetectParams::new(scene.shape, 10.0 / MM)).unwrap();
    let m = compare(&scene, &found);
    assert_eq!(m.matched, 9, "{m:?}");
    for d in &found {
        let at_edge = d.outline.x < 0.5 * side;
        assert_eq!(d.cut, at_edge, "{d:?}");
    }
    let truly_cut = scene.grains.iter().filter(|g| g.0 < 0.5 * side).count();
    assert!(truly_cut >= 2);
    assert_eq!(found.iter().filter(|d| d.cut).count(), truly_cut);
}

#[test]
fn empty_photograph_gives_no_grains() {
    let blank = Scene {
        shape: nut(),
        width: 40.0 * MM,
        height: 30.0 * MM,
        grains: vec![],
    };
    let image = render(&blank, 10.0, &Style::lab());
    let found = detect(&image, &DetectParams::new(nut(), 10.0 / MM)).unwrap();
    assert!(found.is_empty());
    let white = DynamicImage::ImageLuma8(GrayImage::from_pixel(50, 40, Luma([255])));
    assert!(
        detect(&white, &DetectParams::new(long_rod(), 10.0 / MM))
            .unwrap()
            .is_empty()
    );
}

#[test]
fn wrong_scale_is_refused_on_request_with_the_measured_one() {
    for (shape, scene) in [
        (nut(), square_lattice(0.2, 3, 3)),
        (long_rod(), rod_block(long_rod(), 0.4, 2, 4)),
    ] {
        let image = render(&scene, 10.0, &Style::lab());
        let mut params = DetectParams::new(shape, 4.0 / MM);
        params.scale_check = ScaleCheck::Refuse;
        let err = detect(&image, &params).unwrap_err();
        match err {
            DetectError::ImplausibleScale {
                measured_px_per_mm, ..
            } => {
                assert!((measured_px_per_mm - 10.0).abs() < 2.5, "{err}");
                assert!(err.to_string().contains("px/mm"));
            }
            other => panic!("expected an implausible scale, got {other}"),
        }
    }
}

#[test]
fn sixteen_bit_photographs_work() {
    let scene = square_lattice(0.5, 3, 2);
    let mut style = Style::lab();
    style.sixteen_bit = true;
    let image = render(&scene, 10.0, &style);
    assert!(matches!(image, DynamicImage::ImageLuma16(_)));
    let found = detect(&image, &DetectParams::new(scene.shape, 10.0 / MM)).unwrap();
    let m = compare(&scene, &found);
    assert_eq!((m.matched, m.detected), (6, 6), "{m:?}");
    assert!(m.centre_max_mm < 0.1, "{m:?}");
}

#[test]
fn oversized_photograph_is_refused_with_the_limit() {
    let image = DynamicImage::ImageLuma8(GrayImage::from_pixel(200, 100, Luma([255])));
    let mut params = DetectParams::new(nut(), 10.0 / MM);
    params.max_pixels = 10_000;
    let err = detect(&image, &params).unwrap_err();
    assert!(matches!(err, DetectError::TooLarge { .. }), "{err}");
}
