//! Rendered photographs: dark grains, bright field and holes, full 16-bit range, no light
//! between faces that touch, determinism across thread counts.

use vision::render::{Style, render};
use vision::{Frame, GrainOutline, GrainShape};

fn frame() -> Frame {
    Frame {
        width: 0.03,
        height: 0.02,
        scale: 1e4,
    }
}

fn nut(x: f64, y: f64) -> GrainOutline {
    GrainOutline {
        x,
        y,
        theta: 0.0,
        shape: GrainShape::nut(6.9e-3),
    }
}

/// Level at a frame point (metres).
fn level(photo: &vision::render::Photograph, frame: &Frame, x: f64, y: f64) -> f32 {
    let (c, r) = frame.to_pixel(x, y);
    photo.levels[r as usize * photo.columns as usize + c as usize]
}

#[test]
fn grains_dark_field_and_hole_bright() {
    let f = frame();
    let g = nut(0.012, 0.01);
    for style in [Style::clean(), Style::lab(), Style::hard()] {
        let photo = render(&[g], &f, &style, 5);
        let field = level(&photo, &f, 0.025, 0.01);
        let body = level(&photo, &f, 0.012 + 2.6e-3, 0.01);
        let hole = level(&photo, &f, 0.012, 0.01);
        // Even the hard style keeps grains well below the field (contrast >= 0.3 of it).
        assert!(body < 0.7 * field, "{style:?}: body {body} field {field}");
        assert!(hole > 0.8 * field, "{style:?}: hole {hole} field {field}");
    }
}

#[test]
fn faces_touching_show_no_light_but_corners_do() {
    let f = frame();
    let clean = Style {
        full_well: 0.0,
        read_noise: 0.0,
        dust_per_cm2: 0.0,
        scratches_per_100cm2: 0.0,
        blur_px: 0.0,
        ..Style::clean()
    };
    // Two nuts face to face along x; the shared face at x = 15.05 mm splits pixel column 150
    // in halves, one dark half from each nut: the pixel must be as dark as a grain (light
    // passing each half separately would leave it a quarter bright).
    let seam_x = 0.01505;
    let photo = render(
        &[nut(seam_x - 3.45e-3, 0.01), nut(seam_x + 3.45e-3, 0.01)],
        &f,
        &clean,
        1,
    );
    let field = level(&photo, &f, 0.015, 0.0185);
    let seam = level(&photo, &f, seam_x, 0.01 + 2.5e-3);
    assert!(seam < 0.1 * field, "seam {seam} field {field}");
    // Where the rounded corners meet (r = 0.345 mm) light comes through.
    let corner = level(&photo, &f, seam_x, 0.01 + 3.45e-3 - 0.05e-3);
    assert!(corner > seam + 0.2 * field, "corner {corner} seam {seam}");
}

#[test]
fn sixteen_bit_output_spans_the_range() {
    let f = frame();
    let photo = render(&[nut(0.012, 0.01)], &f, &Style::clean(), 2).to_luma16();
    let min = *photo.as_raw().iter().min().unwrap();
    let max = *photo.as_raw().iter().max().unwrap();
    assert!(min < 6553 && max > 52428, "{min}..{max}");
    // Not just 8-bit values shifted up: the low byte varies.
    assert!(photo.as_raw().iter().any(|v| v % 257 != 0));
}

#[test]
fn same_seed_same_photograph_whatever_the_threads() {
    let f = frame();
    let grains = [nut(0.008, 0.01), nut(0.0149, 0.01), nut(0.022, 0.012)];
    let on = |threads| {
        rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .unwrap()
            .install(|| render(&grains, &f, &Style::lab(), 9))
    };
    let one = on(1);
    assert_eq!(one, on(3));
    assert_ne!(one, render(&grains, &f, &Style::lab(), 10));
}

#[test]
fn the_bore_narrows_with_its_scale_and_its_chamfer_glints() {
    let f = frame();
    let quiet = Style {
        full_well: 0.0,
        read_noise: 0.0,
        dust_per_cm2: 0.0,
        scratches_per_100cm2: 0.0,
        blur_px: 0.0,
        ..Style::clean()
    };
    let g = nut(0.012, 0.01);
    // The nominal bore is 3.3 mm: 1.5 mm from the centre is open, unless the bore is 80 %.
    let at_1p5 = |style: &Style| level(&render(&[g], &f, style, 1), &f, 0.012 + 1.5e-3, 0.01);
    let field = level(&render(&[g], &f, &quiet, 1), &f, 0.025, 0.01);
    assert!(at_1p5(&quiet) > 0.8 * field);
    let narrow = Style {
        bore_scale: 0.8,
        ..quiet.clone()
    };
    assert!(at_1p5(&narrow) < 0.1 * field);
    // A 0.5 mm chamfer glinting at half the field: grey between 1.65 and 2.15 mm.
    let glint = Style {
        chamfer_mm: 0.5,
        chamfer_glint: 0.5,
        ..quiet.clone()
    };
    let ring = |style: &Style| level(&render(&[g], &f, style, 1), &f, 0.012 + 1.9e-3, 0.01);
    let (plain, grey) = (ring(&quiet), ring(&glint));
    assert!(plain < 0.1 * field, "{plain} {field}");
    assert!((grey - 0.5 * field).abs() < 0.1 * field, "{grey} {field}");
}
