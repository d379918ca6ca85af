//! Rows of rods touching end to end show one long dark bar with one continuous highlight: the
//! junctions leave no cue, and the greedy acceptance may fit the rods shifted by part of a
//! length, leaving a stub of unexplained dark area shorter than a rod at each end of the row
//! (rod3, ordered, lab, 10 px/mm: most of the missed rods). Such a row is refitted shifted
//! onto one stub, with one rod more in the room left at the other end, and kept when it
//! explains the photograph better.

use super::accept::Found;
use super::fit::{self, Levels};
use super::model::{Model, Pose};
use super::plane::{Bordered, Plane};

/// The maps the acceptance keeps: explained opacity and the darkness it leaves free.
#[derive(Clone)]
pub struct Maps {
    pub explained: Plane,
    pub free: Plane,
    pub free_bordered: Bordered,
}

/// Darkness not yet explained along a rod's axis beyond its end `sign` (+1: the end the axis
/// points to), from the end on: how far it stays dark (pixels, at most `limit`).
fn stub(free: &Plane, pose: Pose, sign: f64, half_length: f64, width: f64, limit: f64) -> f64 {
    let (s, c) = pose.phi.sin_cos();
    let (ux, uy) = (c, -s);
    // Across the axis: (sin phi, cos phi).
    let (vx, vy) = (s, c);
    let mut t = 0.0;
    while t < limit {
        let a = sign * (half_length + t + 0.5);
        let mut sum = 0.0;
        for b in [-0.25 * width, 0.0, 0.25 * width] {
            let (x, y) = (pose.x + a * ux + b * vx, pose.y + a * uy + b * vy);
            if x < 0.0 || y < 0.0 || x >= free.width as f64 || y >= free.height as f64 {
                return t;
            }
            sum += free.at(x as usize, y as usize);
        }
        if sum < 1.5 {
            return t;
        }
        t += 1.0;
    }
    t
}

/// What a repair needs besides the accepted rods and the maps.
pub struct Context<'a> {
    pub dark: &'a Plane,
    pub levels: Levels<'a>,
    pub model: &'a Model,
    pub min_confidence: f64,
    pub min_visible: f64,
    pub length: f64,
    pub width: f64,
}

/// The maps with the grains `found` painted, except those in `skip`.
fn painted(found: &[Found], skip: &[usize], cx: &Context) -> Maps {
    let mut maps = Maps {
        explained: Plane::new(cx.dark.width, cx.dark.height, 0.0),
        free: cx.dark.clone(),
        free_bordered: Bordered::new(cx.dark),
    };
    for (k, g) in found.iter().enumerate() {
        if !skip.contains(&k) {
            paint(&mut maps, g.pose, cx);
        }
    }
    maps
}

fn paint(maps: &mut Maps, pose: Pose, cx: &Context) {
    cx.model.paint(
        pose,
        cx.dark,
        &mut maps.explained,
        &mut maps.free,
        &mut maps.free_bordered,
    );
}

/// Repairs rows of rods shifted along themselves; `found` and `maps` are updated together.
/// Rods are looked at in the order found, each repaired at most once, so the outcome does
/// not depend on the thread count. Returns the number of rows repaired.
pub fn repair(found: &mut Vec<Found>, maps: &mut Maps, cx: &Context) -> usize {
    let (length, width) = (cx.length, cx.width);
    let half = 0.5 * length;
    let mut touched = vec![false; found.len()];
    let mut repaired = 0;
    for g in 0..found.len() {
        for sign in [1.0, -1.0] {
            if touched[g] {
                break;
            }
            let s1 = stub(&maps.free, found[g].pose, sign, half, width, length);
            if s1 < 0.2 * length || s1 > 0.8 * length {
                continue;
            }
            // The row beyond the other end, its poses turned to point as this one's.
            // Its far end must show the other stub, the two making about one rod: then the
            // row shifted onto this stub leaves room for one rod at the far end.
            let row = chain(found, g, -sign, length, width);
            if row.iter().any(|&k| touched[k]) {
                continue;
            }
            let phi = found[g].pose.phi;
            let aligned: Vec<Pose> = row
                .iter()
                .map(|&k| {
                    let p = found[k].pose;
                    let turned = (p.phi - phi).cos() < 0.0;
                    Pose {
                        phi: if turned {
                            p.phi + std::f64::consts::PI
                        } else {
                            p.phi
                        },
                        ..p
                    }
                })
                .collect();
            let last = *aligned.last().expect("the row holds its first rod");
            let s2 = stub(&maps.free, last, -sign, half, width, length);
            if s2 < 0.2 * length || (s1 + s2 - length).abs() > 0.3 * length {
                continue;
            }
            let without = painted(found, &row, cx);
            let mut old = without.clone();
            let mut old_total = 0.0;
            for &p in &aligned {
                let sc = cx.model.score(p, cx.levels.fine, &old.free_bordered);
                old_total += f64::from(sc.total);
                paint(&mut old, p, cx);
            }
            let mut new = without;
            let mut new_total = 0.0;
            let mut fitted = Vec::with_capacity(aligned.len() + 1);
            let starts = aligned
                .iter()
                .map(|&p| along(p, sign * s1))
                .chain(std::iter::once(along(last, sign * s1 - sign * length)));
            let mut good = true;
            for start in starts {
                let levels = Levels {
                    fine_free: &new.free_bordered,
                    ..cx.levels
                };
                let ft = fit::refine(&levels, start, 0.5 * cx.levels.factor);
                if f64::from(ft.score.agreement) < cx.min_confidence
                    || f64::from(ft.score.visible) < cx.min_visible
                {
                    good = false;
                    break;
                }
                new_total += f64::from(ft.score.total);
                paint(&mut new, ft.pose, cx);
                fitted.push(ft);
            }
            if !good || new_total <= old_total {
                continue;
            }
            for (k, ft) in row.iter().chain(std::iter::once(&usize::MAX)).zip(&fitted) {
                let g = Found {
                    pose: ft.pose,
                    corners: cx.model.corners(ft.pose),
                    confidence: f64::from(ft.score.agreement),
                };
                if *k == usize::MAX {
                    found.push(g);
                    touched.push(true);
                } else {
                    found[*k] = g;
                    touched[*k] = true;
                }
            }
            *maps = new;
            repaired += 1;
        }
    }
    repaired
}

/// Offsets of (x, y) from an axis through (ax, ay) at angle `phi`: along it and across it.
fn offsets(ax: f64, ay: f64, phi: f64, x: f64, y: f64) -> (f64, f64) {
    let (s, c) = phi.sin_cos();
    let (dx, dy) = (x - ax, y - ay);
    // The axis points along (cos phi, -sin phi), as in `Pose`.
    (dx * c - dy * s, dx * s + dy * c)
}

/// Angle between two axes, modulo half a turn.
fn turn(a: f64, b: f64) -> f64 {
    let d = (a - b).rem_euclid(std::f64::consts::PI);
    d.min(std::f64::consts::PI - d)
}

/// Shifts `pose` by `d` pixels along its axis.
fn along(pose: Pose, d: f64) -> Pose {
    let (s, c) = pose.phi.sin_cos();
    Pose {
        x: pose.x + d * c,
        y: pose.y - d * s,
        phi: pose.phi,
    }
}

/// The accepted rods touching `from` end to end beyond its end `sign`, in order.
pub fn chain(found: &[Found], from: usize, sign: f64, length: f64, width: f64) -> Vec<usize> {
    let mut out = vec![from];
    let mut at = found[from].pose;
    loop {
        let next = along(at, sign * length);
        let hit = (0..found.len()).find(|&k| {
            let p = found[k].pose;
            if out.contains(&k) || turn(p.phi, at.phi) > 5f64.to_radians() {
                return false;
            }
            let (a, b) = offsets(next.x, next.y, at.phi, p.x, p.y);
            a.abs() < 0.25 * length && b.abs() < 0.25 * width
        });
        match hit {
            Some(k) if out.len() < 8 => {
                out.push(k);
                at = found[k].pose;
            }
            _ => return out,
        }
    }
}
