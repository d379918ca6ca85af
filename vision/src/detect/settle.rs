//! The grains settled against their final neighbours. The acceptance fits each grain against
//! the grains accepted before it, and the repairs refit a rod against the rods of the moment:
//! a grain fitted before its neighbours took their places read their darkness as its own and
//! leans into it. Each grain is refined once more from its pose, on the darkness every other
//! grain leaves where it ended up, a few sweeps over them all.
//!
//! In parallel, and the same whatever the thread count: the photograph is cut into square
//! tiles wider than what one grain's refinement reads and paints, twice over, coloured as a
//! 2 x 2 checkerboard. The tiles of one colour are settled at once, none reading what another
//! changes; the grains of a tile one after another, each against the others as they are.

use rayon::prelude::*;

use super::accept::{Found, Maps};
use super::fit::{self, Levels};
use super::model::{Model, Pose};
use super::plane::{Bordered, Plane};

/// What settling reads besides the grains and the maps.
pub struct Settling<'a> {
    pub dark: &'a Plane,
    /// The fit's levels; the refinement reads the full-resolution ones.
    pub levels: Levels<'a>,
    pub min_confidence: f64,
    pub min_visible: f64,
}

/// Sweeps over every grain. Lab rod53, seeds 22-29, orientation RMS of the rods not fitted
/// turned at 10 and 6 px/mm: 0.62 and 0.97 degrees before, 0.32 and 0.45 after one sweep,
/// 0.27 and 0.38 after two, 0.27 and 0.37 after three.
pub const SWEEPS: usize = 2;

/// Columns `c0..c1` and rows `r0..r1` of the photograph (half-open).
#[derive(Clone, Copy, Debug, PartialEq)]
struct Span {
    c0: usize,
    c1: usize,
    r0: usize,
    r1: usize,
}

impl Span {
    /// This span grown by `by` pixels on every side, within a `width` x `height` plane.
    fn grown(self, by: usize, width: usize, height: usize) -> Span {
        Span {
            c0: self.c0.saturating_sub(by),
            c1: (self.c1 + by).min(width),
            r0: self.r0.saturating_sub(by),
            r1: (self.r1 + by).min(height),
        }
    }

    /// The smallest span within this one that holds the pixels of these centres (those
    /// outside it taken to its nearest pixel).
    fn holding(self, centres: impl Iterator<Item = Pose>) -> Span {
        let mut held: Option<Span> = None;
        for p in centres {
            let c = (p.x.floor().max(0.0) as usize).clamp(self.c0, self.c1 - 1);
            let r = (p.y.floor().max(0.0) as usize).clamp(self.r0, self.r1 - 1);
            let here = Span {
                c0: c,
                c1: c + 1,
                r0: r,
                r1: r + 1,
            };
            held = Some(held.map_or(here, |h| Span {
                c0: h.c0.min(c),
                c1: h.c1.max(c + 1),
                r0: h.r0.min(r),
                r1: h.r1.max(r + 1),
            }));
        }
        held.unwrap_or(self)
    }

    fn width(self) -> usize {
        self.c1 - self.c0
    }

    fn height(self) -> usize {
        self.r1 - self.r0
    }

    /// The pixels of `plane` in this span, as a plane of its own.
    fn crop(self, plane: &Plane) -> Plane {
        let mut data = Vec::with_capacity(self.width() * self.height());
        for r in self.r0..self.r1 {
            data.extend_from_slice(
                &plane.data[r * plane.width + self.c0..r * plane.width + self.c1],
            );
        }
        Plane {
            width: self.width(),
            height: self.height(),
            data,
        }
    }
}

/// Refines every grain `sweeps` times against the others (see the module's text); a grain
/// moves where it scores more and passes the acceptance. Returns how many moves were taken.
pub fn settle(found: &mut [Found], maps: &mut Maps, cx: &Settling, sweeps: usize) -> usize {
    if sweeps == 0 {
        return 0;
    }
    let model = cx.levels.fine_model;
    let (width, height) = (cx.dark.width, cx.dark.height);
    // Farthest a grain's taps or paint lie from its centre, how far its refinement moves it,
    // and the margins around a tile: what its grains read (with the bilinear neighbours and
    // the taps' inside test) and what they may paint.
    let spread = f64::from(model.reach()) + 2.0;
    let drift = fit::refine_drift(cx.levels.factor);
    let read = (spread + drift + 3.0).ceil() as usize;
    let write = (spread + drift + 1.0).ceil() as usize;
    // The tiles of a colour lie a tile apart: wider than a read and a write margin, none
    // reads what another paints.
    let side = read + write + 1;
    let (tiles_x, tiles_y) = (width.div_ceil(side).max(1), height.div_ceil(side).max(1));
    let tile_of = |p: Pose| {
        let col = (p.x.max(0.0) as usize / side).min(tiles_x - 1);
        let row = (p.y.max(0.0) as usize / side).min(tiles_y - 1);
        (col, row)
    };
    let mut cover = coverage(found, model, width, height);
    let mut moves = 0;
    for _ in 0..sweeps {
        let mut members: Vec<Vec<usize>> = vec![Vec::new(); tiles_x * tiles_y];
        for (g, f) in found.iter().enumerate() {
            let (col, row) = tile_of(f.pose);
            members[row * tiles_x + col].push(g);
        }
        for colour in 0..4 {
            let tiles: Vec<usize> = (0..tiles_x * tiles_y)
                .filter(|&t| (t % tiles_x) % 2 + 2 * ((t / tiles_x) % 2) == colour)
                .filter(|&t| !members[t].is_empty())
                .collect();
            let settled: Vec<Settled> = tiles
                .par_iter()
                .map(|&t| {
                    let tile = Span {
                        c0: (t % tiles_x) * side,
                        c1: ((t % tiles_x + 1) * side).min(width),
                        r0: (t / tiles_x) * side,
                        r1: ((t / tiles_x + 1) * side).min(height),
                    };
                    // Only what the tile's grains read is cropped: a fraction of the tile
                    // and its margins when it holds a few grains.
                    let held = tile.holding(members[t].iter().map(|&g| found[g].pose));
                    settle_tile(
                        found,
                        &members[t],
                        held.grown(read, width, height),
                        held.grown(write, width, height),
                        &cover,
                        cx,
                    )
                })
                .collect();
            for s in settled {
                moves += s.moved.len();
                for (g, f) in s.moved {
                    found[g] = f;
                }
                s.cover.write(&mut cover);
            }
        }
    }
    // The maps as painting the grains where they ended up gives them.
    maps.explained = cover;
    maps.explained
        .data
        .par_iter_mut()
        .zip(maps.free.data.par_iter_mut())
        .zip(cx.dark.data.par_iter())
        .for_each(|((e, f), &d)| {
            *e = e.min(1.0);
            *f = d * (1.0 - *e);
        });
    maps.free_bordered = Bordered::new(&maps.free);
    moves
}

/// The coverage of every grain's outline summed (not clamped at 1, so that a grain's own
/// can be taken off again), in parallel over bands of rows, each summed in the grains' order.
fn coverage(found: &[Found], model: &Model, width: usize, height: usize) -> Plane {
    let mut cover = Plane::new(width, height, 0.0);
    const BAND: usize = 64;
    cover
        .data
        .par_chunks_mut(BAND * width.max(1))
        .enumerate()
        .for_each(|(b, band)| {
            let r0 = (b * BAND) as isize;
            let clip = (0, width as isize - 1, r0, r0 + BAND as isize - 1);
            for f in found {
                model.each_covered(f.pose, width, height, clip, |c, r, cov| {
                    band[(r - r0 as usize) * width + c] += cov;
                });
            }
        });
    cover
}

/// A tile's grains moved, and the coverage over what they may have painted.
struct Settled {
    moved: Vec<(usize, Found)>,
    cover: Patch,
}

/// A plane's values over a span of the photograph.
struct Patch {
    span: Span,
    values: Plane,
}

impl Patch {
    fn write(&self, plane: &mut Plane) {
        let s = self.span;
        for r in s.r0..s.r1 {
            let line = &self.values.data[(r - s.r0) * s.width()..(r - s.r0 + 1) * s.width()];
            plane.data[r * plane.width + s.c0..r * plane.width + s.c1].copy_from_slice(line);
        }
    }
}

/// Settles the grains `members` of a tile one after another on the maps cropped to `window`,
/// and returns those moved and the coverage over `written`.
fn settle_tile(
    found: &[Found],
    members: &[usize],
    window: Span,
    written: Span,
    cover: &Plane,
    cx: &Settling,
) -> Settled {
    let model = cx.levels.fine_model;
    let origin = (window.c0 as f64, window.r0 as f64);
    let dark = window.crop(cx.dark);
    let dark_bordered = Bordered::new(&dark);
    let mut cover = window.crop(cover);
    let mut free = Plane {
        data: dark
            .data
            .iter()
            .zip(&cover.data)
            .map(|(&d, &e)| d * (1.0 - e.min(1.0)))
            .collect(),
        ..dark
    };
    let mut free_bordered = Bordered::new(&free);
    let all = (0, isize::MAX, 0, isize::MAX);
    let (w, h) = (dark.width, dark.height);
    // Adds `sign` times the pose's coverage, and brings the free darkness along.
    let mut add = |pose: Pose, sign: f32, free_bordered: &mut Bordered| {
        model.each_covered(pose, w, h, all, |c, r, cov| {
            let i = r * w + c;
            cover.data[i] += sign * cov;
            free.data[i] = dark.data[i] * (1.0 - cover.data[i].clamp(0.0, 1.0));
            free_bordered.set(c, r, free.data[i]);
        });
    };
    let mut moved = Vec::new();
    for &g in members {
        let p = found[g].pose;
        let old = Pose {
            x: p.x - origin.0,
            y: p.y - origin.1,
            phi: p.phi,
        };
        add(old, -1.0, &mut free_bordered);
        let before = model.score(old, &dark_bordered, &free_bordered);
        let levels = Levels {
            fine: &dark_bordered,
            fine_free: &free_bordered,
            ..cx.levels
        };
        let again = fit::refine(&levels, old);
        let s = again.score;
        let pose = if s.total > before.total
            && f64::from(s.agreement) >= cx.min_confidence
            && f64::from(s.visible) >= cx.min_visible
        {
            let pose = Pose {
                x: again.pose.x + origin.0,
                y: again.pose.y + origin.1,
                phi: again.pose.phi,
            };
            moved.push((g, Found::at(pose, f64::from(s.agreement), model)));
            again.pose
        } else {
            old
        };
        add(pose, 1.0, &mut free_bordered);
    }
    let inner = Span {
        c0: written.c0 - window.c0,
        c1: written.c1 - window.c0,
        r0: written.r0 - window.r0,
        r1: written.r1 - window.r0,
    };
    Settled {
        moved,
        cover: Patch {
            span: written,
            values: inner.crop(&cover),
        },
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::GrainShape;
    use crate::detect::model::Model;
    use crate::detect::testing::Lcg;

    const FACTOR: f64 = 3.0;

    /// Rods (rod53 at 10 px/mm: 49 x 30 px) lying face to face and end to end in rows, each
    /// row shifted by part of a length, over several tiles of the settling.
    fn brick_rows() -> (Vec<Pose>, usize, usize) {
        let mut rods = Vec::new();
        for row in 0..6 {
            let shift = 7.0 + 13.0 * (row % 3) as f64;
            for k in 0..6 {
                rods.push(Pose {
                    x: shift + 24.5 + 49.0 * k as f64,
                    y: 10.0 + 15.0 + 30.0 * row as f64,
                    phi: 0.0,
                });
            }
        }
        (rods, 330, 200)
    }

    /// The rods `truth` fitted off their places by up to 1.5 px and 2 degrees, accepted one
    /// after another (each painted over the ones before), settled `sweeps` times on
    /// `threads` threads: the poses, to the bit.
    fn settled(truth: &[Pose], size: (usize, usize), sweeps: usize, threads: usize) -> Vec<Pose> {
        let shape = GrainShape::Rod {
            length: 4.9e-3,
            width: 3e-3,
        };
        let model = Model::new(shape, 1e4);
        let coarse_model = Model::with_softness(shape, 1e4 / FACTOR, 2.0);
        let mut dark = Plane::new(size.0, size.1, 0.0);
        let mut ones = Plane::new(size.0, size.1, 1.0);
        let mut scratch = Bordered::new(&ones);
        for &p in truth {
            model.paint(p, &ones.clone(), &mut dark, &mut ones, &mut scratch);
        }
        let mut rng = Lcg(7);
        let mut found: Vec<Found> = truth
            .iter()
            .map(|p| {
                let mut off = || 2.0 * rng.unit_f64() - 1.0;
                let pose = Pose {
                    x: p.x + 1.5 * off(),
                    y: p.y + 1.5 * off(),
                    phi: p.phi + 2f64.to_radians() * off(),
                };
                Found::at(pose, 0.9, &model)
            })
            .collect();
        let mut maps = Maps {
            explained: Plane::new(size.0, size.1, 0.0),
            free: dark.clone(),
            free_bordered: Bordered::new(&dark),
        };
        for f in &found {
            model.paint(
                f.pose,
                &dark,
                &mut maps.explained,
                &mut maps.free,
                &mut maps.free_bordered,
            );
        }
        let fine = Bordered::new(&dark);
        let coarse = Bordered::new(&dark.downsample(FACTOR as usize));
        let cx = Settling {
            dark: &dark,
            levels: Levels {
                fine: &fine,
                fine_free: &fine,
                coarse: &coarse,
                coarse_free: &coarse,
                fine_model: &model,
                coarse_model: &coarse_model,
                factor: FACTOR,
                period: std::f64::consts::PI,
                finalist_margin: f64::INFINITY,
                finalists: fit::FINALISTS,
            },
            min_confidence: 0.5,
            min_visible: 0.25,
        };
        rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .expect("a thread pool")
            .install(|| settle(&mut found, &mut maps, &cx, sweeps));
        found.iter().map(|f| f.pose).collect()
    }

    /// RMS distance (px) and turn (degrees) of `poses` from `truth`.
    fn rms(poses: &[Pose], truth: &[Pose]) -> (f64, f64) {
        let n = poses.len() as f64;
        let (d2, a2) = poses.iter().zip(truth).fold((0.0, 0.0), |(d, a), (p, t)| {
            (
                d + (p.x - t.x).powi(2) + (p.y - t.y).powi(2),
                a + (p.phi - t.phi).to_degrees().powi(2),
            )
        });
        ((d2 / n).sqrt(), (a2 / n).sqrt())
    }

    /// Rods fitted off their places, each against the ones accepted before it, settle back
    /// on a photograph that is their own paint: from 1.2 px and 1.2 degrees RMS off to
    /// within a third of a pixel and a quarter of a degree. (Closer than a quarter pixel the
    /// score of a rod's outline on a pixel grid is nearly flat; more sweeps take the angle
    /// on to 0.06 degrees, the distance stays at 0.3 px.)
    #[test]
    fn rods_fitted_off_their_places_settle_back() {
        let (truth, w, h) = brick_rows();
        let (d0, a0) = rms(&settled(&truth, (w, h), 0, 1), &truth);
        assert!(
            d0 > 1.0 && a0 > 1.0,
            "the rods start {d0:.2} px, {a0:.2} degrees off"
        );
        let (d, a) = rms(&settled(&truth, (w, h), SWEEPS, 1), &truth);
        assert!(d < 0.35 && a < 0.25, "RMS {d:.3} px, {a:.3} degrees");
    }

    /// The tiles of one colour are settled at once: one, two and three threads give the same
    /// poses, to the bit.
    #[test]
    fn settling_does_not_depend_on_the_thread_count() {
        let (truth, w, h) = brick_rows();
        let one = settled(&truth, (w, h), SWEEPS, 1);
        for threads in [2, 3] {
            assert!(settled(&truth, (w, h), SWEEPS, threads) == one);
        }
    }
}
