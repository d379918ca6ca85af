//! Frames that are no backlit photograph of grains give no grains and a warning saying why,
//! never invented grains; the scale check warns by default, refuses or is off on request.

mod common;

use std::str::FromStr;

use common::*;
use image::{DynamicImage, GrayImage, Luma, Rgb, RgbImage};
use vision::{DetectError, DetectParams, ScaleCheck, detect_report};

/// A frame of 40 x 30 mm at 10 px/mm.
fn uniform(level: u8) -> DynamicImage {
    DynamicImage::ImageLuma8(GrayImage::from_pixel(400, 300, Luma([level])))
}

/// A deposit photograph exposed `gain` times too long: clipped at full scale.
fn overexposed(gain: f32) -> DynamicImage {
    let image = render(&square_lattice(0.2, 3, 3), 10.0, &Style::lab()).to_luma32f();
    let clipped = GrayImage::from_fn(image.width(), image.height(), |x, y| {
        Luma([(255.0 * (gain * image.get_pixel(x, y)[0]).min(1.0)).round() as u8])
    });
    DynamicImage::ImageLuma8(clipped)
}

/// Noise about a mid grey, and nothing else (a deterministic hash of the pixel).
fn noise_only() -> DynamicImage {
    DynamicImage::ImageLuma8(GrayImage::from_fn(400, 300, |x, y| {
        let h =
            (x.wrapping_mul(73_856_093) ^ y.wrapping_mul(19_349_663)).wrapping_mul(2_654_435_761);
        Luma([80 + (h >> 24) as u8 % 96])
    }))
}

#[test]
fn frames_without_background_or_grains_give_no_grains_and_say_why() {
    let red = DynamicImage::ImageRgb8(RgbImage::from_pixel(400, 300, Rgb([255, 0, 0])));
    let frames = [
        ("black", uniform(0), "no bright background"),
        ("white", uniform(255), "no dark grains"),
        ("uniform grey", uniform(128), "no dark grains"),
        ("saturated", overexposed(20.0), "no dark grains"),
        ("saturated red", red, "no dark grains"),
        ("noise only", noise_only(), "no contrast above its noise"),
    ];
    for shape in [nut(), long_rod(), short_rod()] {
        let params = DetectParams::new(shape, 10.0 / MM);
        for (name, frame, why) in &frames {
            let report = detect_report(frame, &params).unwrap();
            assert!(report.grains.is_empty(), "{name}: {:?}", report.grains);
            assert_eq!(report.warnings.len(), 1, "{name}: {:?}", report.warnings);
            let warning = &report.warnings[0];
            assert!(
                warning.starts_with("no grains: ") && warning.contains(why),
                "{name}: {warning}"
            );
        }
    }
}

#[test]
fn a_photograph_passes_the_levels_and_the_default_scale_check() {
    let scene = square_lattice(0.3, 3, 3);
    let image = render(&scene, 10.0, &Style::lab());
    let params = DetectParams::new(scene.shape, 10.0 / MM);
    assert_eq!(params.scale_check, ScaleCheck::Warn);
    let report = detect_report(&image, &params).unwrap();
    assert!(report.warnings.is_empty(), "{:?}", report.warnings);
    let m = compare(&scene, &report.grains);
    assert_eq!((m.matched, m.detected), (9, 9), "{m:?}");
    // Exposed twice as long (the background clipped, the grains not): still a photograph.
    let report = detect_report(&overexposed(2.0), &params).unwrap();
    assert!(report.warnings.is_empty(), "{:?}", report.warnings);
    assert_eq!(report.grains.len(), 9);
}

#[test]
fn a_wrong_scale_warns_by_default_refuses_on_request_and_passes_when_off() {
    let scene = square_lattice(0.2, 3, 3);
    let image = render(&scene, 10.0, &Style::lab());
    let mut params = DetectParams::new(scene.shape, 7.0 / MM);
    let report = detect_report(&image, &params).unwrap();
    assert_eq!(report.warnings.len(), 1, "{:?}", report.warnings);
    let warning = &report.warnings[0];
    assert!(
        warning.contains("7.00 px/mm") && warning.contains("--scale-check"),
        "{warning}"
    );
    params.scale_check = ScaleCheck::Refuse;
    let e = detect_report(&image, &params).unwrap_err();
    let text = e.to_string();
    match e {
        DetectError::ImplausibleScale {
            given_px_per_mm,
            measured_px_per_mm,
            ..
        } => {
            assert_eq!(given_px_per_mm, 7.0);
            assert!((measured_px_per_mm - 10.0).abs() < 2.0, "{text}");
        }
        other => panic!("expected an implausible scale, got {other}"),
    }
    assert!(
        text.contains("7.00 px/mm") && text.contains("--scale-check warn"),
        "{text}"
    );
    params.scale_check = ScaleCheck::Off;
    let report = detect_report(&image, &params).unwrap();
    assert!(report.warnings.is_empty(), "{:?}", report.warnings);
}

#[test]
fn scale_check_names_are_read_and_others_refused() {
    for check in [ScaleCheck::Warn, ScaleCheck::Refuse, ScaleCheck::Off] {
        assert_eq!(ScaleCheck::from_str(&check.to_string()).unwrap(), check);
    }
    for bad in ["", "no", "Refuse", "0"] {
        let e = ScaleCheck::from_str(bad).unwrap_err().to_string();
        assert!(
            e.contains("--scale-check") && e.contains("warn, refuse, off"),
            "{bad}: {e}"
        );
    }
}
