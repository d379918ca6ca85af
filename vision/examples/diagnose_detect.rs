//! Why grains are missed or mis-oriented: renders one benchmark photograph (or a smaller
//! frame), detects, and classifies every miss, false detection and large angle error.
//!
//! `cargo run --release -p vision --example diagnose_detect -- rod3 disordered 10 lab 100 60 /tmp/diag`
//! (shape, packing, px/mm, style, frame width and height in mm, output folder for crops,
//! packing seed, render seed, and optionally points x,y in mm to crop instead of the worst
//! cases).

use std::time::Instant;

use image::{Rgb, RgbImage};
use imageproc::drawing::draw_line_segment_mut;
use vision::evaluate::bench::{shapes, truth_in_frame};
use vision::evaluate::matching::{angle_error, match_centres};
use vision::packing::{Packing, generate};
use vision::render::{Style, render};
use vision::{DetectParams, Frame, GrainOutline, detect};

fn main() {
    let a: Vec<String> = std::env::args().collect();
    let arg = |i: usize, d: &str| a.get(i).cloned().unwrap_or_else(|| d.to_string());
    let shape_name = arg(1, "rod3");
    let packing = if arg(2, "disordered") == "ordered" {
        Packing::Ordered
    } else {
        Packing::Disordered
    };
    let px_per_mm: f64 = arg(3, "10").parse().expect("px/mm");
    let style = Style::named(&arg(4, "lab")).expect("style");
    let width_mm: f64 = arg(5, "100").parse().expect("width");
    let height_mm: f64 = arg(6, "60").parse().expect("height");
    let out = std::path::PathBuf::from(arg(7, "/tmp/diag"));
    let seed: u64 = arg(8, "1").parse().expect("seed");
    // The benchmark packs with its seed plus the packing's index (ordered 0, disordered 1)
    // and renders with its seed: `rod3 disordered 10 lab 258 120 /tmp/diag 2 1` is its photograph.
    let render_seed: u64 = arg(9, &seed.to_string()).parse().expect("render seed");
    std::fs::create_dir_all(&out).expect("output folder");
    let shape = shapes()
        .into_iter()
        .find(|(n, _)| *n == shape_name)
        .expect("shape")
        .1;
    let frame = Frame {
        width: width_mm * 1e-3,
        height: height_mm * 1e-3,
        scale: px_per_mm * 1e3,
    };
    let packed = generate(shape, packing, &frame, seed);
    let photo = render(&packed.grains, &frame, &style, render_seed).to_image(16);
    let params = DetectParams::new(shape, frame.scale);
    let start = Instant::now();
    let found = detect(&photo, &params).expect("detect");
    let secs = start.elapsed().as_secs_f64();
    let truth = truth_in_frame(&packed, &frame);
    // The photograph and both tables, for a closer look with other tools (mm, degrees).
    photo
        .to_luma8()
        .save(out.join("photo.png"))
        .expect("save photo");
    let table = |rows: Vec<(&GrainOutline, bool)>| {
        std::iter::once("index,x_mm,y_mm,theta_deg,cut".to_string())
            .chain(rows.iter().enumerate().map(|(i, (o, cut))| {
                let (x, y, theta) = (o.x * 1e3, o.y * 1e3, o.theta.to_degrees());
                format!("{i},{x:.3},{y:.3},{theta:.2},{cut}")
            }))
            .collect::<Vec<_>>()
            .join("\n")
    };
    let truth_rows = truth.iter().map(|t| (&t.outline, t.cut)).collect();
    std::fs::write(out.join("truth.csv"), table(truth_rows)).expect("save truth");
    let found_rows = found.iter().map(|d| (&d.outline, d.cut)).collect();
    std::fs::write(out.join("found.csv"), table(found_rows)).expect("save found");
    let tc: Vec<[f64; 2]> = truth.iter().map(|t| [t.outline.x, t.outline.y]).collect();
    let dc: Vec<[f64; 2]> = found.iter().map(|d| [d.outline.x, d.outline.y]).collect();
    let w = shape.width();
    let pairs = match_centres(&tc, &dc, 0.5 * w);
    let mut t_match = vec![None; truth.len()];
    let mut d_match = vec![None; found.len()];
    for p in &pairs {
        t_match[p.truth] = Some(p.detection);
        d_match[p.detection] = Some(p.truth);
    }
    let period = shape.symmetry_period();
    let uncut = truth.iter().filter(|t| !t.cut).count();
    let missed: Vec<usize> = (0..truth.len())
        .filter(|&i| !truth[i].cut && t_match[i].is_none())
        .collect();
    let false_d: Vec<usize> = (0..found.len())
        .filter(|&j| !found[j].cut && d_match[j].is_none())
        .collect();
    let mut sq = 0.0;
    let mut n = 0;
    let mut big_angle = Vec::new();
    for p in &pairs {
        if truth[p.truth].cut {
            continue;
        }
        let e = angle_error(
            found[p.detection].outline.theta,
            truth[p.truth].outline.theta,
            period,
        );
        sq += e * e;
        n += 1;
        if e.abs().to_degrees() > 3.0 {
            big_angle.push((p.truth, p.detection, e.to_degrees()));
        }
    }
    println!(
        "{} px, {:.2} s: truth uncut {uncut}, detections {}, missed {}, false {}, angle RMS {:.2} deg, |err| > 3 deg: {}",
        photo.width() * photo.height(),
        secs,
        found.len(),
        missed.len(),
        false_d.len(),
        (sq / n as f64).sqrt().to_degrees(),
        big_angle.len()
    );
    let near = |p: [f64; 2], list: &[[f64; 2]], r: f64| -> Vec<usize> {
        (0..list.len())
            .filter(|&k| (list[k][0] - p[0]).hypot(list[k][1] - p[1]) < r)
            .collect()
    };
    let l = shape.length();
    println!("-- missed (truth index: nearest detection distance/D, its angle error, its match)");
    for &i in &missed {
        let nd = near(tc[i], &dc, l);
        let desc: Vec<String> = nd
            .iter()
            .map(|&j| {
                let d = (dc[j][0] - tc[i][0]).hypot(dc[j][1] - tc[i][1]) / w;
                let e = angle_error(found[j].outline.theta, truth[i].outline.theta, period)
                    .to_degrees();
                format!(
                    "d{j}@{d:.2}D,{e:.0}deg,{}",
                    match d_match[j] {
                        Some(t) => format!("matched t{t}"),
                        None => "false".into(),
                    }
                )
            })
            .collect();
        println!(
            "t{i} ({:.1},{:.1}) mm {:.0} deg: {}",
            tc[i][0] * 1e3,
            tc[i][1] * 1e3,
            truth[i].outline.theta.to_degrees(),
            desc.join("; ")
        );
    }
    println!("-- false (detection: nearby truths and whether matched)");
    for &j in &false_d {
        let nt = near(dc[j], &tc, l);
        let desc: Vec<String> = nt
            .iter()
            .map(|&i| {
                let d = (dc[j][0] - tc[i][0]).hypot(dc[j][1] - tc[i][1]) / w;
                let e = angle_error(found[j].outline.theta, truth[i].outline.theta, period)
                    .to_degrees();
                format!(
                    "t{i}@{d:.2}D,{e:.0}deg,{}",
                    if t_match[i].is_some() { "m" } else { "MISSED" }
                )
            })
            .collect();
        println!(
            "d{j} ({:.1},{:.1}) conf {:.2}: {}",
            dc[j][0] * 1e3,
            dc[j][1] * 1e3,
            found[j].confidence,
            desc.join("; ")
        );
    }
    println!("-- angle errors > 3 deg (truth, detection, error, centre error/D, confidence)");
    for &(i, j, e) in &big_angle {
        let d = (dc[j][0] - tc[i][0]).hypot(dc[j][1] - tc[i][1]) / w;
        println!(
            "t{i} d{j} ({:.1},{:.1}): {e:.1} deg, {d:.2} D, conf {:.2}",
            tc[i][0] * 1e3,
            tc[i][1] * 1e3,
            found[j].confidence
        );
        if e.abs() > 45.0 {
            // What a turned rod was fitted across: the detections around its truth.
            for k in near(tc[i], &dc, l) {
                let m = d_match[k].map_or("false".to_string(), |t| {
                    let et = angle_error(found[k].outline.theta, truth[t].outline.theta, period);
                    format!("t{t} err {:.0} deg", et.to_degrees())
                });
                println!(
                    "    d{k} ({:.2},{:.2}) {:.0} deg conf {:.2}: {m}",
                    dc[k][0] * 1e3,
                    dc[k][1] * 1e3,
                    found[k].outline.theta.to_degrees(),
                    found[k].confidence
                );
            }
            for k in near(tc[i], &tc, l) {
                println!(
                    "    t{k} ({:.2},{:.2}) {:.0} deg",
                    tc[k][0] * 1e3,
                    tc[k][1] * 1e3,
                    truth[k].outline.theta.to_degrees()
                );
            }
        }
    }
    // Classes of failure, counted: a matched rod turned by more than 45 degrees (usually
    // fitted across two neighbours), one tilted by 10-45; a miss beside a false detection
    // parallel to it (shifted along a row or onto a seam) or turned, or with no false
    // detection within a width (its area taken by its neighbours' fits); misses within a
    // length of the photograph's edge are counted apart as well.
    let turned = big_angle.iter().filter(|b| b.2.abs() > 45.0).count();
    let tilted = big_angle
        .iter()
        .filter(|b| (10.0..=45.0).contains(&b.2.abs()))
        .count();
    let (mut shifted, mut beside_turned, mut covered, mut at_edge) = (0, 0, 0, 0);
    let (fw, fh) = (width_mm * 1e-3, height_mm * 1e-3);
    for &i in &missed {
        let [x, y] = tc[i];
        if x < l || y < l || x > fw - l || y > fh - l {
            at_edge += 1;
        }
        let nearest = false_d
            .iter()
            .map(|&j| ((dc[j][0] - x).hypot(dc[j][1] - y), j))
            .filter(|&(d, _)| d < w)
            .min_by(|a, b| a.0.total_cmp(&b.0));
        match nearest {
            Some((_, j)) => {
                let e = angle_error(found[j].outline.theta, truth[i].outline.theta, period);
                if e.abs().to_degrees() < 10.0 {
                    shifted += 1;
                } else {
                    beside_turned += 1;
                }
            }
            None => covered += 1,
        }
    }
    println!(
        "-- classes: matched turned > 45 deg {turned}, tilted 10-45 deg {tilted}; missed {} = \
         beside a parallel false detection {shifted} + beside a turned one {beside_turned} + \
         none within D {covered} (within L of the edge: {at_edge}); false {}",
        missed.len(),
        false_d.len()
    );
    // Crops around the turned rods, then the misses and false detections: truth blue,
    // detections green (matched) or red (false).
    let rgb = photo.to_rgb8();
    let rows = rgb.height() as f64;
    let draw = |img: &mut RgbImage, o: &GrainOutline, colour: Rgb<u8>, ox: f64, oy: f64| {
        let s = frame.scale;
        let (ha, hb) = (0.5 * o.shape.length() * s, 0.5 * o.shape.width() * s);
        let (sn, cs) = o.theta.sin_cos();
        let (px, py) = (o.x * s - ox, rows - o.y * s - oy);
        let c = [(ha, hb), (-ha, hb), (-ha, -hb), (ha, -hb)]
            .map(|(u, v)| ((px + u * cs + v * sn) as f32, (py - u * sn + v * cs) as f32));
        for k in 0..4 {
            draw_line_segment_mut(img, c[k], c[(k + 1) % 4], colour);
        }
    };
    let centres: Vec<[f64; 2]> = big_angle
        .iter()
        .filter(|b| b.2.abs() > 45.0)
        .map(|&(i, _, _)| tc[i])
        .chain(missed.iter().map(|&i| tc[i]))
        .chain(false_d.iter().map(|&j| dc[j]))
        .chain(
            big_angle
                .iter()
                .filter(|b| b.2.abs() <= 45.0)
                .map(|&(i, _, _)| tc[i]),
        )
        .take(24)
        .collect();
    // Points (mm) given after the render seed, as x,y, are cropped instead.
    let asked: Vec<[f64; 2]> = a
        .iter()
        .skip(10)
        .map(|p| {
            let (x, y) = p.split_once(',').expect("a point to crop is x,y in mm");
            [
                x.parse::<f64>().expect("x in mm") * 1e-3,
                y.parse::<f64>().expect("y in mm") * 1e-3,
            ]
        })
        .collect();
    let centres = if asked.is_empty() { centres } else { asked };
    let half = (2.0 * l * frame.scale) as i64;
    // Crops are drawn about 30 px per mm at any scale, so outlines stay apart.
    let zoom = (30.0 / px_per_mm).ceil().max(3.0) as u32;
    for (k, c) in centres.iter().enumerate() {
        let (cx, cy) = (
            (c[0] * frame.scale) as i64,
            (rows - c[1] * frame.scale) as i64,
        );
        let x0 = (cx - half).clamp(0, rgb.width() as i64 - 1);
        let y0 = (cy - half).clamp(0, rgb.height() as i64 - 1);
        let x1 = (cx + half).min(rgb.width() as i64);
        let y1 = (cy + half).min(rgb.height() as i64);
        let mut crop = image::imageops::crop_imm(
            &rgb,
            x0 as u32,
            y0 as u32,
            (x1 - x0) as u32,
            (y1 - y0) as u32,
        )
        .to_image();
        for t in &truth {
            draw(
                &mut crop,
                &t.outline,
                Rgb([40, 90, 255]),
                x0 as f64,
                y0 as f64,
            );
        }
        for (j, d) in found.iter().enumerate() {
            let colour = if d_match[j].is_some() {
                Rgb([0, 200, 60])
            } else {
                Rgb([255, 30, 30])
            };
            draw(&mut crop, &d.outline, colour, x0 as f64, y0 as f64);
        }
        let big = image::imageops::resize(
            &crop,
            crop.width() * zoom,
            crop.height() * zoom,
            image::imageops::FilterType::Nearest,
        );
        big.save(out.join(format!("case{k:02}.png"))).expect("save");
    }
}
