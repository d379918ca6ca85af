//! The maps a trial works on, changed in place and restored window by window, with their
//! coarse level kept up to date; and the count of what they leave unexplained in a square.

use super::{Context, Found, Maps};
use crate::detect::fit::Levels;
use crate::detect::model::{Model, Pose};
use crate::detect::plane::{Bordered, Plane};

/// Columns and rows (inclusive) of a window of the plane.
#[derive(Clone, Copy)]
pub(super) struct Window {
    c0: isize,
    c1: isize,
    r0: isize,
    r1: isize,
}

impl Window {
    pub(super) fn around(x: f64, y: f64, half_x: f64, half_y: f64, plane: &Plane) -> Window {
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

    pub(super) fn holds(self, other: Window) -> bool {
        other.c0 >= self.c0 && other.c1 <= self.c1 && other.r0 >= self.r0 && other.r1 <= self.r1
    }

    /// Whether the window holds no pixel: the box of a pose wholly outside the plane.
    fn is_empty(self) -> bool {
        self.c0 > self.c1 || self.r0 > self.r1
    }

    /// The smallest window holding both (an empty one adds nothing).
    pub(super) fn union(self, other: Window) -> Window {
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
    pub(super) fn grown(self, by: isize) -> Window {
        Window {
            c0: self.c0 - by,
            c1: self.c1 + by,
            r0: self.r0 - by,
            r1: self.r1 + by,
        }
    }

    pub(super) fn meets(self, other: Window) -> bool {
        self.c0 <= other.c1 && other.c0 <= self.c1 && self.r0 <= other.r1 && other.r0 <= self.r1
    }

    fn pixels(self) -> impl Iterator<Item = (usize, usize)> {
        (self.r0..=self.r1)
            .flat_map(move |r| (self.c0..=self.c1).map(move |c| (c as usize, r as usize)))
    }
}

/// The coarse level of the free darkness, kept equal to [`Plane::downsample`] of it.
#[derive(Clone)]
pub(super) struct Coarse {
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
pub(super) struct Local<'m> {
    pub(super) maps: &'m mut Maps,
    pub(super) coarse: Coarse,
    pub(super) factor: usize,
}

impl<'m> Local<'m> {
    /// The maps a repair works on, at the coarse level's factor of `cx`.
    pub(super) fn new(maps: &'m mut Maps, cx: &Context) -> Self {
        let factor = cx.levels.factor as usize;
        let coarse = Coarse::of(&maps.free, factor);
        Local {
            maps,
            coarse,
            factor,
        }
    }

    /// The search levels reading the free darkness of the moment.
    pub(super) fn levels<'s>(&'s self, cx: &'s Context) -> Levels<'s> {
        Levels {
            fine_free: &self.maps.free_bordered,
            coarse_free: &self.coarse.bordered,
            ..cx.levels
        }
    }

    /// The box a pose's outline and ring cover.
    pub(super) fn box_of(&self, pose: Pose, model: &Model) -> Window {
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

    pub(super) fn paint(&mut self, pose: Pose, clip: Window, cx: &Context) {
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
    pub(super) fn save(&self, w: Window) -> Vec<(f32, f32)> {
        let m = &self.maps;
        w.pixels()
            .map(|(c, r)| {
                let i = r * m.free.width + c;
                (m.explained.data[i], m.free.data[i])
            })
            .collect()
    }

    pub(super) fn restore(&mut self, w: Window, saved: &[(f32, f32)]) {
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
    pub(super) fn unpaint(&mut self, found: &[Found], g: usize, skip: &[usize], cx: &Context) {
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
    pub(super) fn without<R>(
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
    pub(super) fn take_off(&mut self, found: &[Found], g: usize, cx: &Context) -> f64 {
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
    pub(super) fn take_off_set(&mut self, found: &[Found], rods: &[usize], cx: &Context) -> f64 {
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
    pub(super) fn place(&mut self, pose: Pose, b: Window, cx: &Context) {
        self.paint(pose, b, cx);
        self.update_coarse(b);
    }
}

/// Unexplained dark pixels (free darkness above one half) in a square, counted every pixel.
pub(super) struct Unexplained {
    pub(super) count: f64,
    /// Their mean position (the square's centre when there are none).
    pub(super) middle: (f64, f64),
}

/// [`Unexplained`] in the square of side `side` centred on (x, y).
pub(super) fn unexplained_near(free: &Plane, x: f64, y: f64, side: f64) -> Unexplained {
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
