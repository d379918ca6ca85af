//! Rows of rods touching end to end show one long dark bar with one continuous highlight; the
//! junctions leave no cue, and the rods may be fitted shifted by part of a length, leaving a
//! stub shorter than a rod at each end of the row (rod3, ordered, lab, 10 px/mm: most of the
//! missed rods). Such a row is refitted shifted onto one stub, with one rod more in the room
//! left at the other end ([`repair`]).

use super::{Context, Found, Local, Maps, Window, along, fit, offsets, turn};
use crate::detect::model::Pose;
use crate::detect::plane::Plane;

/// Darkness not yet explained along a rod's axis beyond its end `sign` (+1: the end the axis
/// points to), from the end on: how far it stays dark (pixels, at most `limit`).
fn stub(free: &Plane, pose: Pose, sign: f64, half_length: f64, width: f64, limit: f64) -> f64 {
    stub_to_edge(free, pose, sign, half_length, width, limit).0
}

/// [`stub`], and whether it ends at the photograph's edge rather than on light.
fn stub_to_edge(
    free: &Plane,
    pose: Pose,
    sign: f64,
    half_length: f64,
    width: f64,
    limit: f64,
) -> (f64, bool) {
    let axis = pose.phi.sin_cos();
    let mut t = 0.0;
    while t < limit {
        let mut sum = 0.0;
        for b in [-0.25 * width, 0.0, 0.25 * width] {
            let Some(f) = free_beyond(free, pose, axis, sign * (half_length + t + 0.5), b) else {
                return (t, true);
            };
            sum += f;
        }
        if sum < 1.5 {
            return (t, false);
        }
        t += 1.0;
    }
    (t, false)
}

/// The free darkness at `a` along rod pose `pose`'s axis and `b` across it (pixels), or
/// None outside the photograph; `(s, c)` is the sine and cosine of its angle.
fn free_beyond(free: &Plane, pose: Pose, (s, c): (f64, f64), a: f64, b: f64) -> Option<f32> {
    // Along the axis: (cos phi, -sin phi); across it: (sin phi, cos phi).
    let (x, y) = (pose.x + a * c + b * s, pose.y - a * s + b * c);
    let inside = x >= 0.0 && y >= 0.0 && x < free.width as f64 && y < free.height as f64;
    inside.then(|| free.at(x as usize, y as usize))
}

/// Least room (parts of a length) for the rod a row shifted along itself leaves at the
/// photograph's edge, cut there. Before the highlight was scaled to what of it is seen, rods
/// added mostly outside the photograph with a third of a length cost rod53 0.6 degrees and
/// this was 0.7; since, 0.4 made no lab orientation RMS worse on seeds 1 and 2 and refitted a
/// row shifted onto a rod turned across it (lab rod53 at 6 px/mm 2.52 -> 1.98 degrees on seed
/// 1; 0.25 did about the same).
const EDGE_ROOM: f64 = 0.4;

/// Least dark beyond a rod's end (parts of a length) read as the stub of a rod its row was
/// shifted off. 0.15 found one rod more in lab rod3 at 10 px/mm and lost one at 6 px/mm
/// (seed 1).
const LEAST_STUB: f64 = 0.2;

/// Repairs rows of rods shifted along themselves; `found` and `maps` are updated together.
/// A row may also have been shifted onto a rod fitted turned across it where its next rod
/// lies (the rod along the row in that place is missed): that rod is refitted along the row
/// in the room the shifted row leaves, when it gains [`Context::least_gain`].
/// The rods `tried` are looked at in their order, each repaired at most once, so the outcome
/// does not depend on the thread count. Returns the number of rows repaired.
pub fn repair(
    found: &mut Vec<Found>,
    maps: &mut Maps,
    cx: &Context,
    tried: impl Iterator<Item = usize>,
) -> usize {
    let (length, width) = (cx.length, cx.width);
    let half = 0.5 * length;
    let mut local = Local::new(maps, cx);
    let (ex, ey) = cx.model.extent(std::f64::consts::FRAC_PI_4);
    // Beyond a centre, the farthest an outline (and its ring) reaches, with a rod length's
    // slack for the refinement's moves (4 px of slack lost a repair in rod3 ordered lab).
    let pad = f64::from(ex.max(ey)) + length;
    // A rod beside the row refitted along its own axis, up to half of L - D either way.
    let shifts: Vec<(f64, f64)> = (-3..=3)
        .map(|k| (f64::from(k) / 6.0 * (length - width).max(0.0), 0.0))
        .collect();
    let step = (0.15 * width).max(cx.levels.factor);
    let mut touched = vec![false; found.len()];
    let mut repaired = 0;
    for g in tried {
        for sign in [1.0, -1.0] {
            if touched[g] {
                break;
            }
            let s1 = stub(&local.maps.free, found[g].pose, sign, half, width, length);
            if s1 < LEAST_STUB * length || s1 > 0.8 * length {
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
            let aligned: Vec<Pose> = row.iter().map(|&k| facing(found[k].pose, phi)).collect();
            let last = *aligned.last().expect("the row holds its first rod");
            // A rod turned across the row where its next rod would lie: the room the row
            // leaves there is measured with it taken off, and it becomes the rod added.
            let crossing = turned_in_row(found, last, -sign, cx)
                .filter(|&t| !touched[t] && seen(found[t].pose, &local, cx) >= CROSSING_SEEN);
            // Else a rod of its own beside the row's axis reaching over its end: the room is
            // measured with it taken off, and it is fitted again after the row.
            let beside = match crossing {
                Some(_) => None,
                None => over_end(found, &row, last, -sign, cx).filter(|&t| !touched[t]),
            };
            // The rod off the row that the trial takes off with it.
            let other = crossing.or(beside);
            // A row running into the photograph's edge: its last rod may be cut there, so the
            // room at that end need only hold part of a rod ([`EDGE_ROOM`]).
            let room_beyond = |free: &Plane| stub_to_edge(free, last, -sign, half, width, length);
            let (s2, at_edge) = match other {
                Some(t) => local.without(found, t, cx, |l| room_beyond(&l.maps.free)),
                None => room_beyond(&local.maps.free),
            };
            // The rod a crossing one becomes, or the rod added beside one, must lie whole in
            // the photograph.
            if other.is_some() && at_edge {
                continue;
            }
            let room = s1 + s2;
            // At the edge, the rod added there may be a rod the edge cuts that was fitted
            // right, and the stub the unexplained side of a rod lying across its end.
            let fits = if at_edge {
                room > EDGE_ROOM * length
                    && room < 1.3 * length
                    && !wider_than_rod(&local.maps.free, found[g].pose, sign, half, s1, width)
            } else {
                s2 >= LEAST_STUB * length && (room - length).abs() <= 0.3 * length
            };
            if !fits {
                continue;
            }
            // The rod added in the room left; at the edge, none when less of it than a stub
            // would lie inside the photograph: the row's last rod reached so far beyond the
            // edge that the room is outside it. With more inside, the rod must be fitted there:
            // dropped with a third of it inside (at 0.4), it let a row lying right at the edge
            // be shifted off it onto a rod standing across its far end.
            let added = along(last, sign * s1 - sign * length);
            let adds = !at_edge || inside(&local.maps.free, added, half) >= LEAST_STUB * length;
            let starts: Vec<Pose> = aligned
                .iter()
                .map(|&p| along(p, sign * s1))
                .chain(adds.then_some(added))
                .collect();
            // The maps change in a window holding the row before and after, undone there
            // when the repair is not kept.
            let (mut x0, mut x1, mut y0, mut y1) = (f64::MAX, f64::MIN, f64::MAX, f64::MIN);
            let other_pose = other.map(|t| found[t].pose);
            for p in aligned.iter().chain(&starts).chain(&other_pose) {
                (x0, x1) = (x0.min(p.x), x1.max(p.x));
                (y0, y1) = (y0.min(p.y), y1.max(p.y));
            }
            let window = Window::around(
                0.5 * (x0 + x1),
                0.5 * (y0 + y1),
                0.5 * (x1 - x0) + pad,
                0.5 * (y1 - y0) + pad,
                &local.maps.free,
            );
            let original = local.save(window);
            let members: Vec<usize> = row.iter().copied().chain(other).collect();
            for &k in &members {
                local.unpaint(found, k, &members, cx);
            }
            let without = local.save(window);
            let mut old_total = 0.0;
            for &p in aligned.iter().chain(&other_pose) {
                let sc = cx.model.score(p, cx.levels.fine, &local.maps.free_bordered);
                old_total += f64::from(sc.total);
                local.paint(p, window, cx);
            }
            local.restore(window, &without);
            let mut new_total = 0.0;
            let mut fitted = Vec::with_capacity(aligned.len() + 1);
            let mut good = true;
            for start in starts {
                let ft = fit::refine(&local.levels(cx), start);
                if !cx.passes(&ft, local.box_of(ft.pose, cx.model), window) {
                    good = false;
                    break;
                }
                new_total += f64::from(ft.score.total);
                local.paint(ft.pose, window, cx);
                fitted.push(ft);
            }
            // The rod beside, pushed into the row's end, comes back along its own axis.
            if let (true, Some(t)) = (good, beside) {
                let p = found[t].pose;
                let ft = fit::fit(&local.levels(cx), (p.x, p.y), &shifts, step, Some(p.phi));
                good = cx.passes(&ft, local.box_of(ft.pose, cx.model), window);
                new_total += f64::from(ft.score.total);
                local.paint(ft.pose, window, cx);
                fitted.push(ft);
            }
            // A rod turned across the row is only refitted along it, and a rod is only added
            // beside one, for a clear gain.
            let least = if other.is_some() {
                cx.least_gain()
            } else {
                0.0
            };
            if !good || new_total <= old_total + least {
                local.restore(window, &original);
                continue;
            }
            let added_to = crossing.unwrap_or(usize::MAX);
            let targets = row.iter().chain(std::iter::once(&added_to)).chain(&beside);
            for (k, ft) in targets.zip(&fitted) {
                let g = cx.found(ft);
                if *k == usize::MAX {
                    found.push(g);
                    touched.push(true);
                } else {
                    found[*k] = g;
                    touched[*k] = true;
                }
            }
            repaired += 1;
        }
    }
    repaired
}

/// Whether the dark area beyond a rod's end `sign` (the stub, `stub` long) is mostly
/// unexplained beside the rod's sides too, a quarter of a width out from them: the side of
/// a rod lying across the end, not the end of a rod of the row, whose neighbours explain
/// what lies beside it. Lab rod53 at 10 px/mm: rods the bottom edge cuts were slid in from
/// it over the unfitted rod across their ends, a rod added in their place (seeds 26, 27).
fn wider_than_rod(free: &Plane, pose: Pose, sign: f64, half: f64, stub: f64, width: f64) -> bool {
    let axis = pose.phi.sin_cos();
    let (mut dark, mut all) = (0, 0);
    let mut t = 0.0;
    while t < stub {
        for b in [-0.75 * width, 0.75 * width] {
            if let Some(f) = free_beyond(free, pose, axis, sign * (half + t + 0.5), b) {
                all += 1;
                dark += usize::from(f > 0.5);
            }
        }
        t += 1.0;
    }
    all > 0 && 2 * dark > all
}

/// Least part of a rod turned across a row that must be seen for it to be refitted along
/// the row: the totals compared are read on what is seen, so a rod the edge cuts by more
/// counts too little against a whole one (lab rod53 at 10 px/mm, seed 3: a true rod
/// standing across the top edge, 0.67 seen, was replaced by one along the row).
const CROSSING_SEEN: f64 = 0.9;

/// The part of rod pose `p`'s outline inside the photograph.
fn seen(p: Pose, local: &Local, cx: &Context) -> f64 {
    let score = cx.model.score(p, cx.levels.fine, &local.maps.free_bordered);
    f64::from(score.visible)
}

/// Least turn (degrees) of a rod lying across a row where its next rod would lie.
const CROSSING_DEG: f64 = 60.0;

/// The rod turned across the row of `last` beyond its end `sign`, lying where the row's
/// next rod would: its centre about half a width past that end, within half a width of the
/// row's axis.
fn turned_in_row(found: &[Found], last: Pose, sign: f64, cx: &Context) -> Option<usize> {
    let at = 0.5 * (cx.length + cx.width);
    (0..found.len()).find(|&k| {
        let p = found[k].pose;
        let (a, b) = offsets(last.x, last.y, last.phi, p.x, p.y);
        turn(p.phi, last.phi) > CROSSING_DEG.to_radians()
            && (sign * a - at).abs() < 0.3 * cx.length
            && b.abs() < 0.5 * cx.width
    })
}

/// The rod, not of the `row`, whose outline holds the point a quarter of a width beyond the
/// end `sign` of the row's `last` rod, on its axis: a rod standing beside the row's end and
/// fitted pushed into it (lab rod3 at 10 px/mm, seed 72 ordered: a rod standing on the last
/// rod's side, 3 mm off the row's axis, fitted 3 mm into the row's end, the row of four
/// fitted as three shifted by a third of a length).
fn over_end(found: &[Found], row: &[usize], last: Pose, sign: f64, cx: &Context) -> Option<usize> {
    let q = along(last, sign * (0.5 * cx.length + 0.25 * cx.width));
    (0..found.len()).find(|&k| !row.contains(&k) && cx.model.covers(found[k].pose, (q.x, q.y)))
}

/// Rod pose `p` turned by a half turn if that points it within a right angle of `phi`: the
/// same rod, pointing the way a row runs.
fn facing(p: Pose, phi: f64) -> Pose {
    if (p.phi - phi).cos() < 0.0 {
        Pose {
            phi: p.phi + std::f64::consts::PI,
            ..p
        }
    } else {
        p
    }
}

/// Length of a rod's axis (half length `half`) inside the plane, in pixels.
fn inside(plane: &Plane, pose: Pose, half: f64) -> f64 {
    let (s, c) = pose.phi.sin_cos();
    let (ux, uy) = (c, -s);
    // The axis is pose + t u for t in [-half, half]; each bound of the plane clips t.
    let (mut lo, mut hi) = (-half, half);
    for (p, u, bound) in [
        (pose.x, ux, plane.width as f64),
        (pose.y, uy, plane.height as f64),
    ] {
        if u.abs() < 1e-12 {
            if p < 0.0 || p > bound {
                return 0.0;
            }
            continue;
        }
        let (t0, t1) = ((0.0 - p) / u, (bound - p) / u);
        lo = lo.max(t0.min(t1));
        hi = hi.min(t0.max(t1));
    }
    (hi - lo).max(0.0)
}

/// Most turn between rods one after another in a row. A rod the photograph's edge cuts is
/// fitted up to some 7 degrees off its row (lab rod3 at 10 px/mm, seed 1): at 5 the row
/// stopped before it, and its repair left the cut rod shifted.
const ROW_TURN_DEG: f64 = 8.0;

/// The accepted rods touching `from` end to end beyond its end `sign`, in order.
pub(super) fn chain(
    found: &[Found],
    from: usize,
    sign: f64,
    length: f64,
    width: f64,
) -> Vec<usize> {
    let mut out = vec![from];
    let mut at = found[from].pose;
    loop {
        let next = along(at, sign * length);
        let hit = (0..found.len()).find(|&k| {
            let p = found[k].pose;
            if out.contains(&k) || turn(p.phi, at.phi) > ROW_TURN_DEG.to_radians() {
                return false;
            }
            let (a, b) = offsets(next.x, next.y, at.phi, p.x, p.y);
            a.abs() < 0.25 * length && b.abs() < 0.25 * width
        });
        match hit {
            Some(k) if out.len() < 8 => {
                out.push(k);
                // A rod is the same turned by a half turn: the walk goes on the way the row
                // runs, whichever way round the rod was fitted. Taken as fitted, a rod fitted
                // the other way round sent the walk back, and rows stopped at their second
                // rod (lab rod3 at 10 px/mm, seed 72 ordered: a row of four seen as two).
                at = facing(found[k].pose, at.phi);
            }
            _ => return out,
        }
    }
}
