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

/// The report's steps are the pipeline's, in its order, and their times add up to the
/// call's but for what no step holds (checking the parameters, the tiles' crops, turning the
/// fits into detections): a whole photograph and one in tiles, rods (their repairs and
/// settling) and nuts (neither), all relaxed. In tiles, the corner tile holds slivers of
/// rods that measure 1.7 px/mm: the scale is the median of the tiles' measurements, and the
/// photograph passes.
#[test]
fn the_report_times_each_step_of_the_pipeline() {
    let rods = rod_block(long_rod(), 0.35, 3, 6);
    let nuts = square_lattice(0.3, 5, 4);
    for (scene, tile_pixels) in [(&rods, None), (&rods, Some(60_000)), (&nuts, None)] {
        let image = render(scene, 10.0, &Style::lab());
        let mut params = DetectParams::new(scene.shape, 10.0 / MM);
        if let Some(t) = tile_pixels {
            params.tile_pixels = t;
        }
        let start = std::time::Instant::now();
        let report =
            detect_report(&image, &params).unwrap_or_else(|e| panic!("tiles {tile_pixels:?}: {e}"));
        let elapsed = start.elapsed();
        let steps: Vec<&str> = report.phases.iter().map(|(name, _)| name).collect();
        let is_rod = matches!(scene.shape, vision::GrainShape::Rod { .. });
        // In tiles, every tile measures the scale before any is searched.
        let mut expected = match tile_pixels {
            Some(_) => vec!["scale and holes", "normalise", "axis seeds"],
            None => vec!["normalise", "scale and holes", "axis seeds"],
        };
        expected.insert(0, "levels");
        expected.extend(["residual seeds", "fits", "acceptance"]);
        if is_rod {
            expected.extend(["repair: rows", "repair: outside", "repair: crowded"]);
            expected.extend([
                "repair: turned",
                "repair: doubtful",
                "repair: across highlights",
            ]);
            expected.extend(["repair: unexplained", "repair: along edge"]);
        }
        expected.push("settle");
        if params.relax {
            expected.push("relax");
        }
        expected.push("explained");
        assert_eq!(steps, expected, "tiles {tile_pixels:?}");
        let total = report.phases.total();
        assert!(total <= elapsed, "{total:?} > {elapsed:?}");
        let unheld = elapsed - total;
        assert!(
            unheld < (elapsed / 2).max(std::time::Duration::from_millis(50)),
            "{unheld:?} of {elapsed:?} held by no step (tiles {tile_pixels:?})"
        );
    }
}

/// A photograph in tiles at a wrong scale is still refused on request, with the scale its tiles measured.
#[test]
fn a_wrong_scale_is_refused_in_tiles_too() {
    let scene = rod_block(long_rod(), 0.35, 3, 6);
    let image = render(&scene, 10.0, &Style::lab());
    let mut params = DetectParams::new(scene.shape, 4.0 / MM);
    params.tile_pixels = 20_000;
    params.scale_check = vision::ScaleCheck::Refuse;
    match detect_report(&image, &params) {
        Err(vision::DetectError::ImplausibleScale {
            measured_px_per_mm, ..
        }) => assert!(
            (measured_px_per_mm - 10.0).abs() < 2.5,
            "{measured_px_per_mm}"
        ),
        other => panic!("expected an implausible scale, got {other:?}"),
    }
}
