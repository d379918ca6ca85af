//! Photographs above the tile size are processed in overlapping tiles: the result must be
//! the one the whole photograph gives, every grain once.

mod common;

use common::*;
use vision::{DetectParams, Detection, WELL_EXPLAINED, detect_report};

/// The detection of `b` nearest to `a`'s centre, and its distance (mm).
fn nearest<'a>(a: &Detection, b: &'a [Detection]) -> (&'a Detection, f64) {
    b.iter()
        .map(|d| {
            let dist = (d.outline.x - a.outline.x).hypot(d.outline.y - a.outline.y) / MM;
            (d, dist)
        })
        .min_by(|p, q| p.1.total_cmp(&q.1))
        .expect("detections")
}

#[test]
fn tiled_and_whole_detection_agree() {
    // 8 x 6 touching nuts at 6 px/mm: about 400 x 300 px; tiles of 300 x 300 px (cores of
    // 160 px, margins of 1.5 grain lengths) put grains across every tile border.
    let scene = square_lattice(0.3, 8, 6);
    let image = render(&scene, 6.0, &Style::lab());
    let whole_params = DetectParams::new(scene.shape, 6.0 / MM);
    let whole = detect_report(&image, &whole_params).unwrap();
    let mut tiled_params = whole_params;
    tiled_params.tile_pixels = 90_000;
    let tiled = detect_report(&image, &tiled_params).unwrap();
    // Each pixel's darkness is counted once, in the core of its tile; each tile normalises
    // its own backlight, so the fractions may differ by a little.
    let (we, te) = (whole.explained.unwrap(), tiled.explained.unwrap());
    assert!(we > WELL_EXPLAINED && (te - we).abs() < 0.01, "{we} {te}");
    let (whole, tiled) = (whole.grains, tiled.grains);

    let mw = compare(&scene, &whole);
    assert_eq!(mw.recall(), 1.0, "whole photograph: {mw:?}");
    let m = compare(&scene, &tiled);
    assert_eq!(m.recall(), 1.0, "tiles: {m:?}");
    assert_eq!(m.precision(), 1.0, "tiles report a grain twice: {m:?}");
    // Nuts with all four faces against neighbours show their angle only at corner slivers,
    // at 6 px/mm a few degrees for single grains: the tiles must do as well as the whole.
    assert!(m.centre_rms_mm < 0.1, "tiles: {m:?}");
    assert!(
        m.angle_rms_deg < mw.angle_rms_deg + 0.5,
        "tiles: {m:?}, whole: {mw:?}"
    );
    assert_eq!(tiled.len(), whole.len());
    for t in &tiled {
        let (w, dist) = nearest(t, &whole);
        // Each tile normalises its own backlight and accepts grains in its own order: a
        // grain's centre may differ by a few times the detector's 0.1 mm RMS target (a nut
        // boxed in by neighbours shows its pose only at corner slivers; one moved by 0.1 mm
        // and 2.5 degrees since the finalists are compared at full resolution), never by a
        // grain; the RMS against the truth is held to 0.1 mm above.
        assert!(dist < 0.2, "{t:?} vs {w:?}");
        assert_eq!(t.cut, w.cut, "{t:?} vs {w:?}");
    }
}
