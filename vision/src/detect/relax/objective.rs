//! The objective the relaxation lowers, over the whole frame:
//!
//! E = sum over pixels of (darkness - rendered darkness)^2 + overlap cost,
//!
//! where the rendered darkness of a pixel is the sum of every grain's dark coverage (its
//! outline's less its hole), at most 1, and the overlap cost charges the outline coverage
//! beyond 1 (`overlap`). The canvas keeps both sums for the grains as they are, so a change
//! of a few poses is priced on the pixels it touches alone.

use super::super::model::{Model, Pose};
use super::super::plane::{Bordered, Plane};
use super::overlap;

/// Both sums of every grain's rendering over the frame, and the darkness they are judged on.
pub struct Canvas<'a> {
    dark: &'a Plane,
    model: &'a Model,
    /// Sum of the grains' dark coverage (outline less hole).
    rendered: Plane,
    /// Sum of the grains' outline coverage.
    covered: Plane,
    /// Changes of both sums over the box a change touches, zero between uses.
    scratch_rendered: Vec<f32>,
    scratch_covered: Vec<f32>,
}

/// The misfit and overlap cost of one pixel.
#[inline]
fn pixel_energy(dark: f32, rendered: f32, covered: f32) -> f64 {
    let misfit = f64::from(dark - rendered.min(1.0));
    misfit * misfit + overlap::cost(covered)
}

/// The pixels near a grain's outline, with its outline's and its dark coverage of each: what
/// a small move of it can change.
pub struct Band {
    pose: Pose,
    reach: f64,
    pixels: Vec<(usize, usize, f32, f32)>,
}

/// Columns `c0..=c1`, rows `r0..=r1`.
type Box4 = (isize, isize, isize, isize);

impl<'a> Canvas<'a> {
    /// The canvas of the grains at `poses` on `dark`.
    pub fn new(dark: &'a Plane, model: &'a Model, poses: impl Iterator<Item = Pose>) -> Self {
        let mut canvas = Canvas {
            dark,
            model,
            rendered: Plane::new(dark.width, dark.height, 0.0),
            covered: Plane::new(dark.width, dark.height, 0.0),
            scratch_rendered: Vec::new(),
            scratch_covered: Vec::new(),
        };
        for p in poses {
            canvas.apply(&[], &[p]);
        }
        canvas
    }

    /// The objective over the whole frame.
    #[cfg(test)]
    pub fn energy(&self) -> f64 {
        self.dark
            .data
            .iter()
            .zip(&self.rendered.data)
            .zip(&self.covered.data)
            .map(|((&d, &r), &c)| pixel_energy(d, r, c))
            .sum()
    }

    /// The box of pixels the poses' outlines may cover, `None` when none lies in the frame.
    fn touched(&self, poses: &[Pose]) -> Option<Box4> {
        let (w, h) = (self.dark.width, self.dark.height);
        let mut held: Option<Box4> = None;
        for &p in poses {
            let (c0, c1, r0, r1) = self.model.painted_box(p, w, h);
            if c0 > c1 || r0 > r1 {
                continue;
            }
            held = Some(held.map_or((c0, c1, r0, r1), |b| {
                (b.0.min(c0), b.1.max(c1), b.2.min(r0), b.3.max(r1))
            }));
        }
        held
    }

    /// Adds `sign` times each pose's rendering to the scratch sums over `b`.
    fn render_into(&mut self, poses: &[Pose], sign: f32, b: Box4) {
        let (w, h) = (self.dark.width, self.dark.height);
        let bw = (b.1 - b.0 + 1) as usize;
        let model = self.model;
        for &p in poses {
            let (sr, sc) = (&mut self.scratch_rendered, &mut self.scratch_covered);
            model.each_covered(p, w, h, b, |c, r, cov| {
                let i = (r - b.2 as usize) * bw + (c - b.0 as usize);
                sc[i] += sign * cov;
                sr[i] += sign * cov * (1.0 - model.hole_at(p, c, r));
            });
        }
    }

    /// The change of the objective if the grains at `removed` were taken away and grains put
    /// at `added`; the canvas is left as it was.
    pub fn change(&mut self, removed: &[Pose], added: &[Pose]) -> f64 {
        let all: Vec<Pose> = removed.iter().chain(added).copied().collect();
        let Some(b) = self.touched(&all) else {
            return 0.0;
        };
        let (bw, bh) = ((b.1 - b.0 + 1) as usize, (b.3 - b.2 + 1) as usize);
        self.scratch_rendered.clear();
        self.scratch_rendered.resize(bw * bh, 0.0);
        self.scratch_covered.clear();
        self.scratch_covered.resize(bw * bh, 0.0);
        self.render_into(removed, -1.0, b);
        self.render_into(added, 1.0, b);
        let w = self.dark.width;
        let mut delta = 0.0;
        for j in 0..bh {
            let row = (b.2 as usize + j) * w + b.0 as usize;
            for i in 0..bw {
                let (dr, dc) = (
                    self.scratch_rendered[j * bw + i],
                    self.scratch_covered[j * bw + i],
                );
                if dr == 0.0 && dc == 0.0 {
                    continue;
                }
                let (d, r, c) = (
                    self.dark.data[row + i],
                    self.rendered.data[row + i],
                    self.covered.data[row + i],
                );
                delta += pixel_energy(d, r + dr, c + dc) - pixel_energy(d, r, c);
            }
        }
        delta
    }

    /// The pixels near the outline of the grain at `pose` (which the canvas holds): where a
    /// move of it by up to `reach` pixels less the anti-aliasing ramp can change anything.
    pub fn band(&self, pose: Pose, reach: f64) -> Band {
        let (w, h) = (self.dark.width, self.dark.height);
        let model = self.model;
        let r = reach as f32 + model.softness();
        let (c0, c1, r0, r1) = model.painted_box(pose, w, h);
        let grow = reach.ceil() as isize + 1;
        let (c0, c1) = ((c0 - grow).max(0), (c1 + grow).min(w as isize - 1));
        let (r0, r1) = ((r0 - grow).max(0), (r1 + grow).min(h as isize - 1));
        let mut pixels = Vec::new();
        let coverage = model.coverage_of(pose);
        let near = model.near_edge_of(pose, r);
        for row in r0.max(0)..=r1 {
            for col in c0.max(0)..=c1 {
                let (c, rr) = (col as usize, row as usize);
                if near(c, rr) {
                    let (cov, hole) = coverage(c, rr);
                    pixels.push((c, rr, cov, cov * (1.0 - hole)));
                }
            }
        }
        Band {
            pose,
            reach,
            pixels,
        }
    }

    /// The change of the objective if the grain at `band.pose` moved to `to`, priced on the
    /// band alone when `to` lies within its reach, else on everything the move touches.
    pub fn change_near(&mut self, band: &Band, to: Pose) -> f64 {
        let moved = (to.x - band.pose.x).abs()
            + (to.y - band.pose.y).abs()
            + (to.phi - band.pose.phi).abs() * f64::from(self.model.reach());
        if moved > band.reach - 1.0 {
            return self.change(&[band.pose], &[to]);
        }
        let w = self.dark.width;
        let mut delta = 0.0;
        let coverage = self.model.coverage_of(to);
        for &(c, r, cov_from, dark_from) in &band.pixels {
            let (cov, hole) = coverage(c, r);
            let (dc, dr) = (cov - cov_from, cov * (1.0 - hole) - dark_from);
            if dc == 0.0 && dr == 0.0 {
                continue;
            }
            let i = r * w + c;
            let (d, rr, cc) = (
                self.dark.data[i],
                self.rendered.data[i],
                self.covered.data[i],
            );
            delta += pixel_energy(d, rr + dr, cc + dc) - pixel_energy(d, rr, cc);
        }
        delta
    }

    /// Takes the grains at `removed` away and puts grains at `added`.
    pub fn apply(&mut self, removed: &[Pose], added: &[Pose]) {
        let (w, h) = (self.dark.width, self.dark.height);
        let all = (0, isize::MAX, 0, isize::MAX);
        let model = self.model;
        for (poses, sign) in [(removed, -1.0f32), (added, 1.0)] {
            for &p in poses {
                let (rendered, covered) = (&mut self.rendered, &mut self.covered);
                model.each_covered(p, w, h, all, |c, r, cov| {
                    let i = r * w + c;
                    covered.data[i] += sign * cov;
                    rendered.data[i] += sign * cov * (1.0 - model.hole_at(p, c, r));
                });
            }
        }
    }

    /// The darkness no grain explains (the darkness times what no outline covers), as the
    /// acceptance's free darkness.
    pub fn free(&self) -> Plane {
        Plane {
            data: self
                .dark
                .data
                .iter()
                .zip(&self.covered.data)
                .map(|(&d, &c)| d * (1.0 - c.clamp(0.0, 1.0)))
                .collect(),
            ..*self.dark
        }
    }

    /// Whether the pixel is dark and no outline covers it: where a grain may be missing.
    pub fn unexplained(&self, col: usize, row: usize) -> bool {
        let i = row * self.dark.width + col;
        self.dark.data[i] > 0.5 && self.covered.data[i] < 0.5
    }

    /// Brings `free` (the darkness no outline covers, as [`Canvas::free`] gives it) up to date
    /// over the pixels of a grain just put at `pose`.
    pub fn paint_free(&self, pose: Pose, free: &mut Bordered) {
        let (w, h) = (self.dark.width, self.dark.height);
        let all = (0, isize::MAX, 0, isize::MAX);
        self.model.each_covered(pose, w, h, all, |c, r, _| {
            let i = r * w + c;
            free.set(
                c,
                r,
                self.dark.data[i] * (1.0 - self.covered.data[i].clamp(0.0, 1.0)),
            );
        });
    }

    pub fn width(&self) -> usize {
        self.dark.width
    }

    pub fn height(&self) -> usize {
        self.dark.height
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::GrainShape;

    /// The change a move is priced at is the change of the whole frame's objective once it
    /// is made, for a move, a removal and an addition, near the edge too.
    #[test]
    fn a_change_is_priced_as_the_whole_frame_changes() {
        let model = Model::new(GrainShape::nut(6.9e-3), 1e4);
        let mut dark = Plane::new(200, 160, 0.1);
        for (i, d) in dark.data.iter_mut().enumerate() {
            *d = ((i * 7919) % 101) as f32 / 100.0;
        }
        let at = |x: f64, y: f64, deg: f64| Pose {
            x,
            y,
            phi: deg.to_radians(),
        };
        let poses = [
            at(60.0, 60.0, 0.0),
            at(128.0, 62.0, 5.0),
            at(10.0, 150.0, 30.0),
        ];
        let mut canvas = Canvas::new(&dark, &model, poses.iter().copied());
        for (removed, added) in [
            (vec![poses[0]], vec![at(70.0, 61.0, 45.0)]),
            (vec![poses[2]], vec![]),
            (vec![], vec![at(180.0, 120.0, 12.0)]),
        ] {
            let before = canvas.energy();
            let priced = canvas.change(&removed, &added);
            canvas.apply(&removed, &added);
            let after = canvas.energy();
            assert!(
                (after - before - priced).abs() < 1e-3 * (1.0 + priced.abs()),
                "priced {priced}, changed {}",
                after - before
            );
        }
    }
}
