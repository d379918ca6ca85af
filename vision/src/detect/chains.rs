//! Repairs of the configurations that the greedy acceptance gets wrong in dense clusters of
//! rods, where the dark area alone is ambiguous and an error leaves unexplained dark area
//! beside it that no rod fits. Each repair is kept only when it explains the photograph
//! better (total score).
//!
//! Here: rows of rods touching end to end show one long dark bar with one continuous
//! highlight; the junctions leave no cue, and the rods may be fitted shifted by part of a
//! length, leaving a stub shorter than a rod at each end of the row (rod3, ordered, lab,
//! 10 px/mm: most of the missed rods). Such a row is refitted shifted onto one stub, with one
//! rod more in the room left at the other end ([`repair`]). And what the repairs share: the
//! maps a trial works on ([`Local`]), trials worked out ahead in parallel and taken over in
//! order ([`in_order`]), rods refitted together ([`refit_together`]).
//!
//! Beside it, one file a repair:
//! - `crowded.rs`: a rod fitted shifted onto part of its neighbour leaves a remainder too
//!   small for a rod, whose seed fails; the rod is refitted together with a rod at that seed.
//! - `turned.rs`: short rods lying face to face fitted by one rod turned by a right angle
//!   across them (rod53: most of the orientation error), refitted as the rods they are.
//! - `doubtful.rs`: a rod accepted with a low agreement, most often fitted turned away from
//!   its angle or crossed by a rod fitted turned over it, fitted afresh.
//! - `highlights.rs`: a rod fitted across two lying face to face, found by their highlights
//!   turned inside it.
//! - `unexplained.rs`: dark area no rod explains, where a rod was missed.
//! - `outside.rs`: a rod fitted centred outside the photograph across what the edge leaves
//!   of rods it cuts, refitted with the rods inside near it.
//! - `edge.rs`: a rod inside fitted turned across the edge over a rod along it and the stubs
//!   of rods the edge cuts, refitted as those.

use std::sync::Mutex;
use std::sync::atomic::{AtomicUsize, Ordering};

use rayon::prelude::*;

use super::accept::Found;
use super::fit::{self, Levels};
use super::model::{Model, Pose};
use super::plane::{Bordered, Plane};

mod crowded;
mod doubtful;
mod edge;
mod highlights;
mod outside;
mod turned;
mod unexplained;
pub use crowded::repair_crowded;
pub use doubtful::repair_doubtful;
pub use edge::repair_along_edge;
pub use highlights::repair_across_highlights;
pub use outside::repair_outside;
pub use turned::repair_turned;
pub use unexplained::repair_unexplained;

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
                return (t, true);
            }
            sum += free.at(x as usize, y as usize);
        }
        if sum < 1.5 {
            return (t, false);
        }
        t += 1.0;
    }
    (t, false)
}

/// Least gain (parts of a rod's area L x W, in score) for a trial that turns, adds or drops
/// rods to be kept, in every repair that asks one: a whole rod seen scores about 0.85 of it.
/// Refits that only nudged rods gained less than 0.04, and one of them turned a rod later
/// (the outside repair, lab rod53 at 6 px/mm, seed 3: 2.96 -> 3.20 degrees); the trials kept
/// on lab seeds 1 and 2 gained 0.10-0.99.
const LEAST_GAIN: f64 = 0.1;

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

impl Context<'_> {
    /// Whether a fit passes the acceptance with its box `b` inside the trial's `window` (the
    /// only pixels a trial may change).
    fn passes(&self, ft: &fit::Fitted, b: Window, window: Window) -> bool {
        f64::from(ft.score.agreement) >= self.min_confidence
            && f64::from(ft.score.visible) >= self.min_visible
            && window.holds(b)
    }

    /// Least gain in score for a trial that turns, adds or drops rods to be kept
    /// ([`LEAST_GAIN`] of a rod's area).
    fn least_gain(&self) -> f64 {
        LEAST_GAIN * self.length * self.width
    }

    /// Half side of the window a trial about a rod may change: wider than any outline its
    /// fits can reach from seeds and offsets about the rod.
    fn trial_reach(&self) -> f64 {
        1.5 * self.length + 2.0 * self.width + 4.0
    }

    /// The grain a kept fit becomes.
    fn found(&self, ft: &fit::Fitted) -> Found {
        Found {
            pose: ft.pose,
            corners: self.model.corners(ft.pose),
            confidence: f64::from(ft.score.agreement),
        }
    }
}

/// The maps with the grains `found` painted, except those in `skip`.
#[cfg(test)]
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

#[cfg(test)]
fn paint(maps: &mut Maps, pose: Pose, cx: &Context) {
    cx.model.paint(
        pose,
        cx.dark,
        &mut maps.explained,
        &mut maps.free,
        &mut maps.free_bordered,
    );
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
            // A rod turned across the row where its next rod would lie: the room the row
            // leaves there is measured with it taken off, and it becomes the rod added.
            let crossing = turned_in_row(found, last, -sign, cx)
                .filter(|&t| !touched[t] && seen(found[t].pose, &local, cx) >= CROSSING_SEEN);
            // A row running into the photograph's edge: its last rod may be cut there, so the
            // room at that end need only hold part of a rod ([`EDGE_ROOM`]).
            let room_beyond = |free: &Plane| stub_to_edge(free, last, -sign, half, width, length);
            let (s2, at_edge) = match crossing {
                Some(t) => local.without(found, t, cx, |l| room_beyond(&l.maps.free)),
                None => room_beyond(&local.maps.free),
            };
            // The rod a crossing one becomes must lie whole in the photograph.
            if crossing.is_some() && at_edge {
                continue;
            }
            let room = s1 + s2;
            let fits = if at_edge {
                room > EDGE_ROOM * length && room < 1.3 * length
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
            let crossing_pose = crossing.map(|t| found[t].pose);
            for p in aligned.iter().chain(&starts).chain(&crossing_pose) {
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
            let members: Vec<usize> = row.iter().copied().chain(crossing).collect();
            for &k in &members {
                local.unpaint(found, k, &members, cx);
            }
            let without = local.save(window);
            let mut old_total = 0.0;
            for &p in aligned.iter().chain(&crossing_pose) {
                let sc = cx.model.score(p, cx.levels.fine, &local.maps.free_bordered);
                old_total += f64::from(sc.total);
                local.paint(p, window, cx);
            }
            local.restore(window, &without);
            let mut new_total = 0.0;
            let mut fitted = Vec::with_capacity(aligned.len() + 1);
            let mut good = true;
            for start in starts {
                let ft = fit::refine(&local.levels(cx), start, 0.5 * cx.levels.factor);
                if !cx.passes(&ft, local.box_of(ft.pose, cx.model), window) {
                    good = false;
                    break;
                }
                new_total += f64::from(ft.score.total);
                local.paint(ft.pose, window, cx);
                fitted.push(ft);
            }
            // A rod turned across the row is only refitted along it for a clear gain.
            let least = if crossing.is_some() {
                cx.least_gain()
            } else {
                0.0
            };
            if !good || new_total <= old_total + least {
                local.restore(window, &original);
                continue;
            }
            let added_to = crossing.unwrap_or(usize::MAX);
            for (k, ft) in row.iter().chain(std::iter::once(&added_to)).zip(&fitted) {
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

/// Offsets of (x, y) from an axis through (ax, ay) at angle `phi`: along it and across it.
fn offsets(ax: f64, ay: f64, phi: f64, x: f64, y: f64) -> (f64, f64) {
    let (s, c) = phi.sin_cos();
    let (dx, dy) = (x - ax, y - ay);
    // The axis points along (cos phi, -sin phi), as in `Pose`.
    (dx * c - dy * s, dx * s + dy * c)
}

/// The edge of the photograph nearest a centre: its direction (a rod's angle lying along
/// it), the unit normal pointing into the photograph, and the centre's distance from it
/// (negative outside).
#[derive(Clone, Copy)]
struct Edge {
    phi: f64,
    inward: (f64, f64),
    depth: f64,
}

fn nearest_edge(p: Pose, plane: &Plane) -> Edge {
    let (w, h) = (plane.width as f64, plane.height as f64);
    let right_angle = std::f64::consts::FRAC_PI_2;
    [
        (0.0, (0.0, 1.0), p.y),
        (0.0, (0.0, -1.0), h - p.y),
        (right_angle, (1.0, 0.0), p.x),
        (right_angle, (-1.0, 0.0), w - p.x),
    ]
    .into_iter()
    .map(|(phi, inward, depth)| Edge { phi, inward, depth })
    .min_by(|a, b| a.depth.total_cmp(&b.depth))
    .expect("four edges")
}

/// Whether a pose's centre lies in the photograph.
fn centred_inside(p: Pose, plane: &Plane) -> bool {
    p.x >= 0.0 && p.y >= 0.0 && p.x < plane.width as f64 && p.y < plane.height as f64
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

/// Most turn between rods one after another in a row. A rod the photograph's edge cuts is
/// fitted up to some 7 degrees off its row (lab rod3 at 10 px/mm, seed 1): at 5 the row
/// stopped before it, and its repair left the cut rod shifted.
const ROW_TURN_DEG: f64 = 8.0;

/// The accepted rods touching `from` end to end beyond its end `sign`, in order.
pub fn chain(found: &[Found], from: usize, sign: f64, length: f64, width: f64) -> Vec<usize> {
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
                at = found[k].pose;
            }
            _ => return out,
        }
    }
}

/// Columns and rows (inclusive) of a window of the plane.
#[derive(Clone, Copy)]
struct Window {
    c0: isize,
    c1: isize,
    r0: isize,
    r1: isize,
}

impl Window {
    fn around(x: f64, y: f64, half_x: f64, half_y: f64, plane: &Plane) -> Window {
        Window {
            c0: ((x - half_x).floor() as isize).max(0),
            c1: ((x + half_x).ceil() as isize).min(plane.width as isize - 1),
            r0: ((y - half_y).floor() as isize).max(0),
            r1: ((y + half_y).ceil() as isize).min(plane.height as isize - 1),
        }
    }

    fn clip(self) -> (isize, isize, isize, isize) {
        (self.c0, self.c1, self.r0, self.r1)
    }

    fn holds(self, other: Window) -> bool {
        other.c0 >= self.c0 && other.c1 <= self.c1 && other.r0 >= self.r0 && other.r1 <= self.r1
    }

    /// Whether the window holds no pixel: the box of a pose wholly outside the plane.
    fn is_empty(self) -> bool {
        self.c0 > self.c1 || self.r0 > self.r1
    }

    /// The smallest window holding both (an empty one adds nothing).
    fn union(self, other: Window) -> Window {
        if other.is_empty() {
            return self;
        }
        if self.is_empty() {
            return other;
        }
        Window {
            c0: self.c0.min(other.c0),
            c1: self.c1.max(other.c1),
            r0: self.r0.min(other.r0),
            r1: self.r1.max(other.r1),
        }
    }

    /// The window `by` pixels wider on every side.
    fn grown(self, by: isize) -> Window {
        Window {
            c0: self.c0 - by,
            c1: self.c1 + by,
            r0: self.r0 - by,
            r1: self.r1 + by,
        }
    }

    fn meets(self, other: Window) -> bool {
        self.c0 <= other.c1 && other.c0 <= self.c1 && self.r0 <= other.r1 && other.r0 <= self.r1
    }

    fn pixels(self) -> impl Iterator<Item = (usize, usize)> {
        (self.r0..=self.r1)
            .flat_map(move |r| (self.c0..=self.c1).map(move |c| (c as usize, r as usize)))
    }
}

/// The coarse level of the free darkness, kept equal to [`Plane::downsample`] of it.
#[derive(Clone)]
struct Coarse {
    plane: Plane,
    bordered: Bordered,
}

impl Coarse {
    fn of(free: &Plane, factor: usize) -> Self {
        let plane = free.downsample(factor);
        let bordered = Bordered::new(&plane);
        Coarse { plane, bordered }
    }
}

/// The maps with their coarse free darkness, changed in place window by window.
struct Local<'m> {
    maps: &'m mut Maps,
    coarse: Coarse,
    factor: usize,
}

impl<'m> Local<'m> {
    /// The maps a repair works on, at the coarse level's factor of `cx`.
    fn new(maps: &'m mut Maps, cx: &Context) -> Self {
        let factor = cx.levels.factor as usize;
        let coarse = Coarse::of(&maps.free, factor);
        Local {
            maps,
            coarse,
            factor,
        }
    }

    /// The search levels reading the free darkness of the moment.
    fn levels<'s>(&'s self, cx: &'s Context) -> Levels<'s> {
        Levels {
            fine_free: &self.maps.free_bordered,
            coarse_free: &self.coarse.bordered,
            ..cx.levels
        }
    }

    /// The box a pose's outline and ring cover.
    fn box_of(&self, pose: Pose, model: &Model) -> Window {
        let (ex, ey) = model.extent(pose.phi);
        Window::around(
            pose.x,
            pose.y,
            f64::from(ex),
            f64::from(ey),
            &self.maps.free,
        )
    }

    /// Recomputes the coarse free darkness over the cells that meet `w`
    /// ([`Plane::block_mean`], what [`Plane::downsample`] gives there).
    fn update_coarse(&mut self, w: Window) {
        let f = self.factor as isize;
        let free = &self.maps.free;
        for cr in w.r0 / f..=w.r1 / f {
            for cc in w.c0 / f..=w.c1 / f {
                let (cc, cr) = (cc as usize, cr as usize);
                let v = free.block_mean(self.factor, cc, cr);
                let coarse = &mut self.coarse;
                coarse.plane.data[cr * coarse.plane.width + cc] = v;
                coarse.bordered.set(cc, cr, v);
            }
        }
    }

    fn paint(&mut self, pose: Pose, clip: Window, cx: &Context) {
        cx.model.paint_within(
            pose,
            cx.dark,
            &mut self.maps.explained,
            &mut self.maps.free,
            &mut self.maps.free_bordered,
            clip.clip(),
        );
    }

    /// The explained and free darkness of window `w`, to restore.
    fn save(&self, w: Window) -> Vec<(f32, f32)> {
        let m = &self.maps;
        w.pixels()
            .map(|(c, r)| {
                let i = r * m.free.width + c;
                (m.explained.data[i], m.free.data[i])
            })
            .collect()
    }

    fn restore(&mut self, w: Window, saved: &[(f32, f32)]) {
        for ((c, r), &(e, f)) in w.pixels().zip(saved) {
            let i = r * self.maps.free.width + c;
            self.maps.explained.data[i] = e;
            self.maps.free.data[i] = f;
            self.maps.free_bordered.set(c, r, f);
        }
        self.update_coarse(w);
    }

    /// Takes grain `g` off the maps: its box repainted from the other grains near it, but
    /// those in `skip`.
    fn unpaint(&mut self, found: &[Found], g: usize, skip: &[usize], cx: &Context) {
        let pose = found[g].pose;
        let b = self.box_of(pose, cx.model);
        for (c, r) in b.pixels() {
            let i = r * self.maps.free.width + c;
            self.maps.explained.data[i] = 0.0;
            self.maps.free.data[i] = cx.dark.data[i];
            self.maps.free_bordered.set(c, r, cx.dark.data[i]);
        }
        // A grain whose outline meets the box: its centre lies within the box's
        // half-diagonal and its own (with ring and slack) of this centre.
        let reach = 2.0 * cx.length.hypot(cx.width) + 8.0;
        for (k, other) in found.iter().enumerate() {
            let q = other.pose;
            if k != g && !skip.contains(&k) && (q.x - pose.x).hypot(q.y - pose.y) < reach {
                self.paint(q, b, cx);
            }
        }
        self.update_coarse(b);
    }

    /// What `read` reads on the maps with rod `g` taken off; the maps are left as they were.
    fn without<R>(
        &mut self,
        found: &[Found],
        g: usize,
        cx: &Context,
        read: impl FnOnce(&Self) -> R,
    ) -> R {
        let b = self.box_of(found[g].pose, cx.model);
        let saved = self.save(b);
        self.unpaint(found, g, &[], cx);
        let out = read(self);
        self.restore(b, &saved);
        out
    }

    /// Takes rod `g` off the maps (as [`Local::unpaint`]) and returns the total its pose
    /// scores on what is left: the figure a trial's fits must beat.
    fn take_off(&mut self, found: &[Found], g: usize, cx: &Context) -> f64 {
        self.unpaint(found, g, &[], cx);
        let pose = found[g].pose;
        f64::from(
            cx.model
                .score(pose, cx.levels.fine, &self.maps.free_bordered)
                .total,
        )
    }

    /// Takes the rods `rods` off the maps together (as [`Local::unpaint`], none repainting
    /// another) and returns the total their poses score on what is left: the figure a set
    /// trial's fits must beat.
    fn take_off_set(&mut self, found: &[Found], rods: &[usize], cx: &Context) -> f64 {
        for &k in rods {
            self.unpaint(found, k, rods, cx);
        }
        rods.iter()
            .map(|&k| {
                let score = cx
                    .model
                    .score(found[k].pose, cx.levels.fine, &self.maps.free_bordered);
                f64::from(score.total)
            })
            .sum()
    }

    /// Paints a fit's pose within its box `b`, on both levels.
    fn place(&mut self, pose: Pose, b: Window, cx: &Context) {
        self.paint(pose, b, cx);
        self.update_coarse(b);
    }
}

/// How far (pixels, along x or y) from a fit's seed the taps of any pose it scores may read,
/// on either level: the farthest offset tried, the fit's drift, the model's reach, and the
/// bilinear neighbours (a coarse pixel stands for `factor` full-resolution ones).
fn fit_reads(cx: &Context, offsets: &[(f64, f64)], step: f64) -> f64 {
    let f = cx.levels.factor;
    let farthest = offsets.iter().map(|o| o.0.hypot(o.1)).fold(0.0, f64::max);
    let taps = (f64::from(cx.levels.fine_model.reach()) + 1.5)
        .max(f64::from(cx.levels.coarse_model.reach()) * f + 1.5 * f);
    farthest + fit::fit_drift(step, f) + taps + 2.0
}

/// A trial's outcome worked out ahead on a copy of the maps, and the pixels it read (of
/// either level, in full-resolution pixels): the sequential pass takes it over when no
/// repair kept before it changed any of them.
struct Guess<T> {
    /// The rod the trial took off, and its pose then.
    rod: usize,
    pose: Pose,
    reads: Window,
    kept: Option<T>,
}

/// Most copies of the maps worked on at once: each is about 12 bytes a pixel (40 MB for a
/// 258 x 120 mm frame at 10 px/mm, 200 MB for a tile of `TILE_PIXELS`).
const MOST_COPIES: usize = 4;

/// Worked out on copies of the maps as they are before the pass (one per worker, at most
/// [`MOST_COPIES`]), in parallel, `trial` for each item, in the items' order; nothing when
/// one thread works, since the sequential pass would then only redo what is guessed.
fn speculate<I: Sync, R: Send>(
    items: &[I],
    local: &Local,
    trial: impl Fn(&mut Local, &I) -> R + Sync,
) -> Option<Vec<R>> {
    let workers = rayon::current_num_threads()
        .min(MOST_COPIES)
        .min(items.len());
    if workers < 2 {
        return None;
    }
    // Each worker takes the next item not yet taken, so uneven trials share out evenly.
    let next = AtomicUsize::new(0);
    let results: Vec<Mutex<Option<R>>> = items.iter().map(|_| Mutex::new(None)).collect();
    let factor = local.factor;
    (0..workers).into_par_iter().for_each(|_| {
        let mut maps = local.maps.clone();
        let mut copy = Local {
            maps: &mut maps,
            coarse: local.coarse.clone(),
            factor,
        };
        loop {
            let k = next.fetch_add(1, Ordering::Relaxed);
            let Some(item) = items.get(k) else {
                break;
            };
            let result = trial(&mut copy, item);
            *results[k].lock().unwrap_or_else(|e| e.into_inner()) = Some(result);
        }
    });
    Some(
        results
            .into_iter()
            .map(|r| {
                r.into_inner()
                    .unwrap_or_else(|e| e.into_inner())
                    .expect("every item is worked out")
            })
            .collect(),
    )
}

/// The guess for rod `rod` at `pose`, if there is one and no window in `changed` meets
/// what it read.
fn usable<'g, T>(
    guesses: &'g [Guess<T>],
    rod: usize,
    pose: Pose,
    changed: &[Window],
) -> Option<&'g Guess<T>> {
    guesses
        .iter()
        .find(|g| g.rod == rod && g.pose == pose)
        .filter(|g| !changed.iter().any(|c| c.meets(g.reads)))
}

/// What a kept trial did to the maps, done again: the rods `rods` taken off (together: none
/// is painted back under another), `fits` painted. Returns the pixels it changed (of either
/// level).
fn replay(
    local: &mut Local,
    found: &[Found],
    rods: &[usize],
    fits: &[fit::Fitted],
    cx: &Context,
) -> Window {
    let mut changed = rods
        .iter()
        .map(|&k| local.box_of(found[k].pose, cx.model))
        .reduce(Window::union)
        .expect("a kept trial takes a rod off");
    for &k in rods {
        local.unpaint(found, k, rods, cx);
    }
    for ft in fits {
        let b = local.box_of(ft.pose, cx.model);
        local.place(ft.pose, b, cx);
        changed = changed.union(b);
    }
    changed.grown(cx.levels.factor as isize + 1)
}

/// A kept trial taken over: the rods `rods` taken off and `fits` painted ([`replay`]), the
/// fits written over those rods in order and the rest added, all of them touched. Returns
/// the pixels it changed.
fn take_over(
    local: &mut Local,
    found: &mut Vec<Found>,
    touched: &mut Vec<bool>,
    rods: &[usize],
    fits: &[fit::Fitted],
    cx: &Context,
) -> Window {
    let changed = replay(local, found, rods, fits, cx);
    for (k, ft) in fits.iter().enumerate() {
        match rods.get(k) {
            Some(&h) => {
                found[h] = cx.found(ft);
                touched[h] = true;
            }
            None => {
                found.push(cx.found(ft));
                touched.push(true);
            }
        }
    }
    changed
}

/// The trials of a repair that, about each item (a rod or a spot), takes a set of rods off
/// and fits them afresh: worked out ahead and taken over in order by [`in_order`].
trait SetTrials: Sync {
    type Item: Sync;
    /// What picks a trial's rods besides the maps: the rods (see [`SetTrials::rods`]) and
    /// whatever else the trial depends on.
    type Near: PartialEq + Send;
    /// What a trial kept, of which [`Parts::parts`] tells the rods and the fits.
    type Kept: Clone + Send + Parts<Self::Near>;
    /// Whether `item` is passed over, the rods `touched` being repaired already.
    fn passed_over(&self, item: &Self::Item, touched: &[bool]) -> bool;
    /// What picks the trial about `item`, the rods `touched` left out.
    fn near(
        &self,
        found: &[Found],
        touched: &[bool],
        item: &Self::Item,
        cx: &Context,
    ) -> Self::Near;
    /// The rods a trial takes off, of those that `near` picks.
    fn rods<'n>(&self, near: &'n Self::Near) -> &'n [usize];
    /// What the trial reads, of either level.
    fn reads(
        &self,
        local: &Local,
        found: &[Found],
        near: &Self::Near,
        item: &Self::Item,
        cx: &Context,
    ) -> Window;
    /// The trial, leaving the maps as they were.
    fn run(
        &self,
        local: &mut Local,
        found: &[Found],
        near: &Self::Near,
        item: &Self::Item,
        cx: &Context,
    ) -> Self::Kept;
}

/// What a [`SetTrials`] trial kept, read as the rods it took off and the fits it painted;
/// none of either when it kept nothing. `near` is what picked the trial's rods.
trait Parts<N> {
    fn parts<'k>(&'k self, near: &'k N) -> (&'k [usize], &'k [fit::Fitted]);
}

/// The rods taken off and the fits of a trial that keeps them as they are.
impl<N> Parts<N> for Option<(Vec<usize>, Vec<fit::Fitted>)> {
    fn parts<'k>(&'k self, _: &'k N) -> (&'k [usize], &'k [fit::Fitted]) {
        self.as_ref()
            .map_or((&[], &[]), |(set, fits)| (set.as_slice(), fits.as_slice()))
    }
}

/// A [`SetTrials`] trial worked out ahead: what picked its rods and their poses then, what
/// it read, and what it kept.
struct SetGuess<N, K> {
    near: N,
    poses: Vec<Pose>,
    reads: Window,
    kept: K,
}

/// `trial` about each of `items` in order, each kept one taken over ([`take_over`]). The
/// trials are worked out ahead in parallel on copies of the maps ([`speculate`]); a guess
/// holds when the same rods are picked the same way, at the same poses, and no trial kept
/// since changed what it read; else the trial is done again. The outcome is the sequential
/// one whatever the thread count. Returns the number of trials kept.
fn in_order<T: SetTrials>(
    trial: &T,
    items: &[T::Item],
    found: &mut Vec<Found>,
    local: &mut Local,
    cx: &Context,
) -> usize {
    let before: &[Found] = found;
    let untouched = vec![false; found.len()];
    let guesses = speculate(items, local, |local, item| {
        let near = trial.near(before, &untouched, item, cx);
        SetGuess {
            poses: trial.rods(&near).iter().map(|&k| before[k].pose).collect(),
            reads: trial.reads(local, before, &near, item, cx),
            kept: trial.run(local, before, &near, item, cx),
            near,
        }
    });
    let mut changed: Vec<Window> = Vec::new();
    let mut touched = vec![false; found.len()];
    let mut repaired = 0;
    for (i, item) in items.iter().enumerate() {
        if trial.passed_over(item, &touched) {
            continue;
        }
        let near = trial.near(found, &touched, item, cx);
        let guess = guesses.as_ref().map(|all| &all[i]).filter(|guess| {
            guess.near == near
                && trial
                    .rods(&near)
                    .iter()
                    .zip(&guess.poses)
                    .all(|(&k, &p)| found[k].pose == p)
                && !changed.iter().any(|c| c.meets(guess.reads))
        });
        let kept = match guess {
            Some(guess) => guess.kept.clone(),
            None => trial.run(local, found, &near, item, cx),
        };
        let (off, fits) = kept.parts(&near);
        if fits.is_empty() {
            continue;
        }
        changed.push(take_over(local, found, &mut touched, off, fits, cx));
        repaired += 1;
    }
    repaired
}

/// Pixels changed by a kept trial (of either level): the box of the rod taken off and those
/// of the fits painted.
fn changed_by(local: &Local, old: Pose, fits: &[fit::Fitted], cx: &Context) -> Window {
    fits.iter()
        .fold(local.box_of(old, cx.model), |w, ft| {
            w.union(local.box_of(ft.pose, cx.model))
        })
        .grown(cx.levels.factor as isize + 1)
}

/// The trial of [`repair_doubtful`] for a doubtful rod and the rods turned like it near it
/// (`rods`, the doubtful one first): all are taken off; a rod is fitted afresh at each of
/// their centres, at the angle `axis` or over every angle, and up to two more at the middle
/// of what they leave unexplained while that is at least a third of a rod (each agreeing as
/// clearly as [`repair_crowded`] asks of an added rod). Kept when at least as many rods pass
/// the acceptance and they score more than the old poses did on the maps without them:
/// returned with what they score more (their gain), the refits first. Either way the maps
/// are left as they were ([`replay`] paints a kept trial's fits). `search` is the fits'
/// offsets and first step, and the half side of the window the trial may change around
/// each rod.
///
/// At `spots`, rods are fitted before the others: with its neighbours taken off, a rod their
/// fits had eaten into is found whole, where fitted after them it is not. A needed spot
/// ([`repair_unexplained`]) fails the trial unless its rod agrees as clearly as an added
/// rod; another ([`repair_across_highlights`]) is passed over if it is already explained
/// or its rod does not agree so, and the trial fails if every spot is passed over.
fn refit_together(
    local: &mut Local,
    found: &[Found],
    rods: &[usize],
    cx: &Context,
    search: (&[(f64, f64)], f64, f64),
    axis: Option<f64>,
    spots: &[Spot],
) -> Option<(Vec<fit::Fitted>, f64)> {
    let (offsets, step, reach) = search;
    let free = &local.maps.free;
    let window = rods
        .iter()
        .map(|&k| {
            let p = found[k].pose;
            Window::around(p.x, p.y, reach, reach, free)
        })
        .reduce(Window::union)?;
    let saved = local.save(window);
    let old_total = local.take_off_set(found, rods, cx);
    let mut fitted = Vec::with_capacity(rods.len() + 2);
    let mut new_total = 0.0;
    for spot in spots {
        let (sx, sy) = (spot.at.0 as usize, spot.at.1 as usize);
        let explained = sx >= local.maps.free.width
            || sy >= local.maps.free.height
            || local.maps.free.at(sx, sy) <= 0.5;
        if explained && !spot.needed {
            continue;
        }
        let ft = match (spot.fixed, spot.axis.or(axis)) {
            (true, Some(phi)) => {
                let (x, y) = spot.at;
                let pose = Pose { x, y, phi };
                let score = cx
                    .model
                    .score(pose, cx.levels.fine, &local.maps.free_bordered);
                fit::Fitted { pose, score }
            }
            (_, axis) => fit::fit(
                &local.levels(cx),
                spot.at,
                spot.offsets.unwrap_or(offsets),
                step,
                axis,
            ),
        };
        let b = local.box_of(ft.pose, cx.model);
        if !(cx.passes(&ft, b, window) && ft.score.agreement >= ADDED_AGREEMENT) {
            if spot.needed {
                local.restore(window, &saved);
                return None;
            }
            continue;
        }
        new_total += f64::from(ft.score.total);
        local.place(ft.pose, b, cx);
        fitted.push(ft);
    }
    let at_spots = fitted.len();
    if at_spots == 0 && !spots.is_empty() {
        // Without a rod at a spot, the trial is a refit the caller did not ask for.
        local.restore(window, &saved);
        return None;
    }
    for &k in rods {
        let p = found[k].pose;
        let ft = fit::fit(&local.levels(cx), (p.x, p.y), offsets, step, axis);
        let b = local.box_of(ft.pose, cx.model);
        if cx.passes(&ft, b, window) {
            new_total += f64::from(ft.score.total);
            local.place(ft.pose, b, cx);
            fitted.push(ft);
        }
    }
    let n = rods.len() as f64;
    let (mx, my) = rods.iter().fold((0.0, 0.0), |(x, y), &k| {
        (x + found[k].pose.x / n, y + found[k].pose.y / n)
    });
    // Rods more where their place is left unexplained: n rods fitted across n + 1 leave one,
    // a seed that failed above another.
    for _ in 0..2 {
        let left = unexplained_near(&local.maps.free, mx, my, 2.0 * cx.length);
        if left.count < cx.length * cx.width / 3.0 {
            break;
        }
        let ft = fit::fit(&local.levels(cx), left.middle, offsets, step, axis);
        let b = local.box_of(ft.pose, cx.model);
        if !(cx.passes(&ft, b, window) && ft.score.agreement >= ADDED_AGREEMENT) {
            break;
        }
        new_total += f64::from(ft.score.total);
        local.place(ft.pose, b, cx);
        fitted.push(ft);
    }
    let kept = fitted.len() >= rods.len() && new_total > old_total;
    local.restore(window, &saved);
    // The rods at the spots are added ones: after the refits.
    fitted.rotate_left(at_spots);
    kept.then_some((fitted, new_total - old_total))
}

/// A rod fitted by [`refit_together`] before the refits: where, at what angle (else the
/// trial's), and from which offsets (else the trial's).
#[derive(Clone, Copy)]
struct Spot<'a> {
    at: (f64, f64),
    axis: Option<f64>,
    offsets: Option<&'a [(f64, f64)]>,
    /// Whether the trial fails without a rod here; else a spot already explained, or whose
    /// fit does not agree as an added rod must, is passed over.
    needed: bool,
    /// Whether the rod is placed at `at` and its angle as it is, not fitted: where rods
    /// refined together as a row end to end put it.
    fixed: bool,
}

/// The `most` rods not yet touched nearest to `at` within `within` (nearest first, ties in
/// the order found).
fn nearest(
    found: &[Found],
    touched: &[bool],
    at: (f64, f64),
    within: f64,
    most: usize,
) -> Vec<usize> {
    nearest_where(found, touched, at, within, most, |_| true)
}

/// [`nearest`], of the rods that `keep` keeps.
fn nearest_where(
    found: &[Found],
    touched: &[bool],
    at: (f64, f64),
    within: f64,
    most: usize,
    keep: impl Fn(usize) -> bool,
) -> Vec<usize> {
    let mut near: Vec<(f64, usize)> = (0..found.len())
        .filter(|&k| !touched[k] && keep(k))
        .map(|k| {
            let p = found[k].pose;
            ((p.x - at.0).hypot(p.y - at.1), k)
        })
        .filter(|&(d, _)| d < within)
        .collect();
    near.sort_by(|a, b| a.0.total_cmp(&b.0).then(a.1.cmp(&b.1)));
    near.into_iter().take(most).map(|(_, k)| k).collect()
}

/// Rod `g`, then the `most` other rods not yet touched nearest to it within `within` that
/// `keep` keeps: the rods a set trial about `g` takes off.
fn with_nearest(
    found: &[Found],
    touched: &[bool],
    g: usize,
    within: f64,
    most: usize,
    keep: impl Fn(usize) -> bool,
) -> Vec<usize> {
    let p = found[g].pose;
    let near = nearest_where(found, touched, (p.x, p.y), within, most, |k| {
        k != g && keep(k)
    });
    std::iter::once(g).chain(near).collect()
}

/// Least agreement of a rod that [`repair_crowded`] adds.
const ADDED_AGREEMENT: f32 = 0.8;

/// Unexplained dark pixels (free darkness above one half) in a square, counted every pixel.
struct Unexplained {
    count: f64,
    /// Their mean position (the square's centre when there are none).
    middle: (f64, f64),
}

/// [`Unexplained`] in the square of side `side` centred on (x, y).
fn unexplained_near(free: &Plane, x: f64, y: f64, side: f64) -> Unexplained {
    let h = 0.5 * side;
    let (c0, c1) = (
        (x - h).max(0.0) as usize,
        ((x + h) as usize).min(free.width),
    );
    let (r0, r1) = (
        (y - h).max(0.0) as usize,
        ((y + h) as usize).min(free.height),
    );
    let (mut n, mut sx, mut sy) = (0.0, 0.0, 0.0);
    for r in r0..r1 {
        for c in c0..c1 {
            if free.at(c, r) > 0.5 {
                n += 1.0;
                sx += c as f64 + 0.5;
                sy += r as f64 + 0.5;
            }
        }
    }
    let middle = if n > 0.0 { (sx / n, sy / n) } else { (x, y) };
    Unexplained { count: n, middle }
}

#[cfg(test)]
mod tests;
