//! Measures the detector with and without the joint relaxation on rendered photographs with
//! their truth tables (`facets render` writes PHOTO.truth.csv beside PHOTO.png):
//! `cargo run --profile ci -p vision --example relax_measure -- SHAPE PX_PER_MM PHOTO.png...`
//! with SHAPE square, rod53 or rod3. Prints, per photograph and setting (the old pipeline,
//! with relax, and for rods relax without the repairs), recall, precision, centre and
//! orientation RMS, grains turned by more than 10 degrees and the time. `RELAX_ONLY=relax`
//! (or `old`, `relax, no repairs`) runs one setting, so that a process's CPU time is that
//! setting's; `RELAX_LIST=1` also lists the grains turned and missed.

use std::time::Instant;

use vision::Detection;
use vision::evaluate::matching::{GATE, angle_error, match_centres};
use vision::evaluate::{TURNED_DEG, Truth, score};
use vision::{DetectParams, GrainOutline, GrainShape, detect_report};

fn shape_named(name: &str) -> GrainShape {
    match name {
        "square" => GrainShape::nut(6.9e-3),
        "rod53" => GrainShape::Rod {
            length: 4.9e-3,
            width: 3e-3,
        },
        "rod3" => GrainShape::Rod {
            length: 8.9e-3,
            width: 3e-3,
        },
        other => panic!("unknown shape {other}: square, rod53 or rod3"),
    }
}

fn truth_of(path: &str, shape: GrainShape) -> Vec<Truth> {
    let text = std::fs::read_to_string(path).unwrap_or_else(|e| panic!("{path}: {e}"));
    text.lines()
        .skip(1)
        .filter(|l| !l.trim().is_empty())
        .map(|l| {
            let f: Vec<f64> = l
                .split(',')
                .map(|v| v.trim().parse().expect("a number"))
                .collect();
            Truth {
                outline: GrainOutline {
                    x: f[0] * 1e-3,
                    y: f[1] * 1e-3,
                    theta: f[2],
                    shape,
                },
                cut: f[6] != 0.0,
            }
        })
        .collect()
}

fn main() {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let shape = shape_named(&args[0]);
    let px_per_mm: f64 = args[1].parse().expect("px per mm");
    for photo in &args[2..] {
        let image = image::open(photo).unwrap_or_else(|e| panic!("{photo}: {e}"));
        let truth = truth_of(&photo.replace(".png", ".truth.csv"), shape);
        let base = DetectParams::new(shape, px_per_mm * 1e3);
        let mut settings = vec![
            (
                "old",
                DetectParams {
                    relax: false,
                    ..base
                },
            ),
            ("relax", base),
        ];
        if let GrainShape::Rod { .. } = shape {
            settings.push((
                "relax, no repairs",
                DetectParams {
                    repairs: false,
                    ..base
                },
            ));
        }
        let only = std::env::var("RELAX_ONLY").ok();
        for (name, params) in settings {
            if only.as_ref().is_some_and(|o| o != name) {
                continue;
            }
            let start = Instant::now();
            let report = detect_report(&image, &params).expect("detection");
            let secs = start.elapsed().as_secs_f64();
            let t = score(&truth, &report.grains);
            if std::env::var_os("RELAX_LIST").is_some() {
                list_turned(&truth, &report.grains);
            }
            let relax_s = report
                .phases
                .iter()
                .find(|p| p.0 == "relax")
                .map_or(0.0, |p| p.1.as_secs_f64());
            println!(
                "{photo} [{name}]: recall {:.2} % precision {:.2} % centre RMS {:.3} mm \
                 orientation RMS {:.2} deg (unturned {:.2}) turned {} | {:.2} s (relax {:.2} s)",
                100.0 * t.recall(),
                100.0 * t.precision(),
                t.centre_rms_mm(),
                t.orientation_rms_deg(),
                t.unturned_orientation_rms_deg(),
                t.turned,
                secs,
                relax_s
            );
        }
    }
}

/// Prints the true grains matched turned, and those missed, with their places (mm).
fn list_turned(truth: &[Truth], found: &[Detection]) {
    let t: Vec<[f64; 2]> = truth.iter().map(|t| [t.outline.x, t.outline.y]).collect();
    let d: Vec<[f64; 2]> = found.iter().map(|d| [d.outline.x, d.outline.y]).collect();
    let width = truth[0].outline.shape.width();
    let pairs = match_centres(&t, &d, GATE * width);
    let mut matched = vec![false; truth.len()];
    for p in &pairs {
        matched[p.truth] = true;
        let (tt, dd) = (&truth[p.truth], &found[p.detection]);
        let period = tt.outline.shape.symmetry_period();
        let e = angle_error(dd.outline.theta, tt.outline.theta, period).to_degrees();
        if !tt.cut && e > TURNED_DEG {
            println!(
                "  turned {e:.1} deg at ({:.1}, {:.1}) mm, found at ({:.1}, {:.1})",
                tt.outline.x * 1e3,
                tt.outline.y * 1e3,
                dd.outline.x * 1e3,
                dd.outline.y * 1e3
            );
        }
    }
    for (k, tt) in truth.iter().enumerate() {
        if !matched[k] && !tt.cut {
            println!(
                "  missed at ({:.1}, {:.1}) mm",
                tt.outline.x * 1e3,
                tt.outline.y * 1e3
            );
        }
    }
}
