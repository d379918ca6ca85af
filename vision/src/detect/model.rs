//! The rendered grain model a candidate pose is scored with: an anti-aliased rounded
//! rectangle (spheropolygon, rounding 0.05 D), the bright hole of a nut, the faint highlight
//! along a rod's axis, and a thin ring of field around the outline.
//!
//! The model is tabulated once as taps (points in the grain's frame with weights) and a pose
//! is scored by sampling the darkness bilinearly at the rotated taps. Rasterising the outline
//! per pose cost a square root (two for nuts, an exponential for rods) per pixel; the taps
//! cost one rotation and one bilinear read, and deep inside the outline, where a small move
//! of the pose changes nothing, one tap stands for a 2 x 2 block.

use crate::GrainShape;

use super::plane::{Bordered, Plane};
use super::taps::{LANES, Placement, Taps};

/// Rounding radius of the grains' corners, as a fraction of the width D.
const ROUNDING: f64 = 0.05;
/// Relative weights of the cues; the interior term has weight 1.
const RING_WEIGHT: f32 = 0.5;
const HOLE_WEIGHT: f32 = 1.0;
/// The highlight is a contrast of a few percent (floored, see `Model::highlight_floor`) on a
/// narrow line: it needs a large weight to count against the interior in dense clusters,
/// where it is the only cue that tells one rod from two.
const HIGHLIGHT_WEIGHT: f32 = 8.0;

/// Blocks each cue is summed in when a pose may be given up on partway.
const BLOCKS: usize = 8;

/// The order `score_unless_below` sums the cues in (indices into `Model::cues`): ring,
/// interior, highlight, flanks, hole gave up on hopeless poses soonest (six lab photographs
/// at 10 px/mm, 3.5 G coarse taps: 0.83 G spared, against 0.77 G interior first and 0.57 G
/// highlight first).
const SUMMING_ORDER: [usize; 5] = [2, 0, 3, 4, 1];

/// Where a pose puts the model's taps.
fn placement(pose: Pose) -> Placement {
    Placement {
        x: pose.x as f32,
        y: pose.y as f32,
        sin: pose.phi.sin() as f32,
        cos: pose.phi.cos() as f32,
    }
}

/// A pose in continuous pixel coordinates (column, row; row 0 at the top). `phi` is the
/// frame angle (counter-clockwise with y up): the long axis points along (cos phi, -sin phi).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Pose {
    pub x: f64,
    pub y: f64,
    pub phi: f64,
}

/// Grain geometry in pixels at one resolution level.
#[derive(Clone, Copy, Debug)]
struct Geometry {
    half_length: f32,
    half_width: f32,
    round: f32,
    hole_radius: f32,
    highlight_sigma: f32,
    highlight_half_length: f32,
    /// Offset of the flanking lines the highlight is compared with (pixels).
    highlight_flank: f32,
    /// Width of the anti-aliasing ramp of the outline (pixels).
    soft: f32,
    /// Width of the ring of field scored outside the outline (pixels).
    ring: f32,
}

/// The grain model at one resolution level.
#[derive(Clone, Debug)]
pub struct Model {
    geometry: Geometry,
    /// Grain interior (outside the hole), scored on the darkness not yet explained.
    interior: Taps,
    /// The nut's hole: should be bright.
    hole: Taps,
    /// The field just outside the outline (and the outer half of its ramp): should be bright.
    ring: Taps,
    /// The faint highlight along a rod's axis: should be a little less dark (positive
    /// weights) than the lines flanking it (`flank`, negative weights).
    highlight: Taps,
    flank: Taps,
    /// Darkness below which the axis counts no lighter: a rod's own highlight is this light,
    /// a gap of bright field between two grains much lighter, and without the floor an
    /// outline laid along a gap would outscore the grains on either side of it.
    highlight_floor: f32,
    /// Covered area of the whole outline (interior and hole), the denominator of `visible`.
    area: f32,
    /// Per cue (in the order of `cues`), the ends of its blocks for `score_unless_below`
    /// (whole lanes) and the weight of its taps from each block's start on.
    blocks: [Vec<(usize, f32)>; 5],
    /// Bound on the f32 rounding of a total (a ten-thousandth of its largest magnitude).
    rounding_margin: f64,
}

/// Score of one pose.
#[derive(Clone, Copy, Debug, Default)]
pub struct Score {
    /// Objective maximised by the fit (all cues).
    pub total: f32,
    /// Agreement of interior and hole with the photograph, in [-1, 1]: the confidence.
    pub agreement: f32,
    /// Fraction of the outline's area that lies inside the photograph.
    pub visible: f32,
}

impl Geometry {
    /// Signed distance (pixels) from the outline, negative inside, in grain coordinates.
    #[inline]
    fn signed_distance(&self, u: f32, v: f32) -> f32 {
        let qx = u.abs() - (self.half_length - self.round);
        let qy = v.abs() - (self.half_width - self.round);
        let outside = (qx.max(0.0).powi(2) + qy.max(0.0).powi(2)).sqrt();
        outside + qx.max(qy).min(0.0) - self.round
    }

    /// Coverage in [0, 1] of a pixel centred at (u, v) in grain coordinates.
    #[inline]
    fn coverage(&self, u: f32, v: f32) -> f32 {
        (0.5 - self.signed_distance(u, v) / self.soft).clamp(0.0, 1.0)
    }

    fn hole_coverage(&self, u: f32, v: f32) -> f32 {
        if self.hole_radius <= 0.0 {
            return 0.0;
        }
        (0.5 + (self.hole_radius - u.hypot(v)) / self.soft).clamp(0.0, 1.0)
    }

    /// The taps of a point: interior, hole, ring and highlight weights per unit area.
    fn profile(&self, u: f32, v: f32) -> [f32; 4] {
        let sd = self.signed_distance(u, v);
        if sd > self.ring {
            return [0.0; 4];
        }
        let cov = (0.5 - sd / self.soft).clamp(0.0, 1.0);
        let ring = if cov < 1.0 { 1.0 - cov } else { 0.0 };
        if cov <= 0.0 {
            return [0.0, 0.0, ring, 0.0];
        }
        let hc = self.hole_coverage(u, v);
        let highlight = if self.highlight_sigma > 0.0 && u.abs() < self.highlight_half_length {
            // The axis line less the two flanking lines: a contrast, blind to how dark the
            // grain is as a whole, that only a rod's own highlight gives. An outline laid
            // across two rods, or along their seam, finds none.
            let s = self.highlight_sigma;
            let f = self.highlight_flank;
            let g = |d: f32| (-d * d / (2.0 * s * s)).exp();
            cov * (g(v) - 0.5 * (g(v - f) + g(v + f)))
        } else {
            0.0
        };
        [cov * (1.0 - hc), hc, ring, highlight]
    }

    /// Far enough inside the outline and from the hole's edge that a 2 x 2 block of taps
    /// around (u, v) (spacing 1) all have the same plain interior profile.
    fn deep(&self, u: f32, v: f32) -> bool {
        let margin = 0.5 * self.soft + 1.5;
        self.signed_distance(u, v) < -margin
            && (self.hole_radius <= 0.0 || u.hypot(v) > self.hole_radius + margin)
    }
}

impl Model {
    /// `px_per_m` at this level (full scale divided by the level's downsampling factor).
    pub fn new(shape: GrainShape, px_per_m: f64) -> Self {
        Self::with_softness(shape, px_per_m, 1.0)
    }

    /// `soft`: width of the outline's ramp (pixels); a softer model gives the coarse search a
    /// smoother objective, so grid poses near the truth score near its maximum.
    pub fn with_softness(shape: GrainShape, px_per_m: f64, soft: f64) -> Self {
        let length = shape.length() * px_per_m;
        let width = shape.width() * px_per_m;
        let (hole_radius, highlight_sigma, highlight_half_length) = match shape {
            GrainShape::Square { hole_diameter, .. } => (0.5 * hole_diameter * px_per_m, 0.0, 0.0),
            // The highlight runs the rod's whole length; its rounded corners take 0.05 D.
            GrainShape::Rod { .. } => (0.0, (0.1 * width).max(0.5), 0.5 * length - 0.1 * width),
        };
        let geometry = Geometry {
            half_length: (0.5 * length) as f32,
            half_width: (0.5 * width) as f32,
            round: (ROUNDING * width) as f32,
            hole_radius: hole_radius as f32,
            highlight_sigma: highlight_sigma as f32,
            highlight_half_length: highlight_half_length.max(0.0) as f32,
            highlight_flank: (0.3 * width) as f32,
            soft: soft as f32,
            ring: (0.08 * width).clamp(soft, 2.5 * soft) as f32,
        };
        Self::tabulate(geometry)
    }

    /// Taps on a unit grid centred on the grain, merged into 2 x 2 blocks deep inside.
    fn tabulate(g: Geometry) -> Model {
        let reach_u = g.half_length + g.ring + g.soft + 1.0;
        let reach_v = g.half_width + g.ring + g.soft + 1.0;
        // Blocks of 2 x 2 unit cells, symmetric about the centre.
        let blocks_u = (reach_u / 2.0).ceil() as i32;
        let blocks_v = (reach_v / 2.0).ceil() as i32;
        let mut model = Model {
            geometry: g,
            interior: Taps::default(),
            hole: Taps::default(),
            ring: Taps::default(),
            highlight: Taps::default(),
            flank: Taps::default(),
            highlight_floor: 0.0,
            area: 0.0,
            blocks: Default::default(),
            rounding_margin: 0.0,
        };
        for bv in -blocks_v..blocks_v {
            for bu in -blocks_u..blocks_u {
                let (cu, cv) = (2.0 * bu as f32 + 1.0, 2.0 * bv as f32 + 1.0);
                let cells = [(-0.5, -0.5), (0.5, -0.5), (-0.5, 0.5), (0.5, 0.5)]
                    .map(|(du, dv)| (cu + du, cv + dv));
                let merge = cells.iter().all(|&(u, v)| g.deep(u, v));
                if merge {
                    model.interior.push(cu, cv, 4.0);
                    model.area += 4.0;
                }
                // Near the outline and the hole's edge of the sharp (full-resolution) model,
                // taps every half pixel: the refinement's sub-pixel, sub-degree shifts move the
                // outline by less than a pixel. The soft coarse model needs no more than one.
                let subcells: Vec<(f32, f32, f32)> = if merge || g.soft > 1.0 {
                    cells.iter().map(|&(u, v)| (u, v, 1.0)).collect()
                } else {
                    (0..16)
                        .map(|k| {
                            let (i, j) = ((k % 4) as f32, (k / 4) as f32);
                            (cu - 0.75 + 0.5 * i, cv - 0.75 + 0.5 * j, 0.25)
                        })
                        .collect()
                };
                for (u, v, a) in subcells {
                    let [interior, hole, ring, highlight] = g.profile(u, v).map(|w| w * a);
                    if !merge {
                        model.area += interior + hole;
                    }
                    // The highlight's positive part is the axis line, the negative its flanks.
                    let highlight_list = if highlight > 0.0 {
                        &mut model.highlight
                    } else {
                        &mut model.flank
                    };
                    for (list, w, min) in [
                        (
                            &mut model.interior,
                            interior,
                            if merge { f32::INFINITY } else { 1e-5 },
                        ),
                        (&mut model.hole, hole, 1e-5),
                        (&mut model.ring, ring, 1e-5),
                        // The highlight's tails beyond three sigma carry nothing measurable.
                        (highlight_list, highlight, 0.011 * a),
                    ] {
                        if w.abs() > min {
                            list.push(u, v, w);
                        }
                    }
                }
            }
        }
        for taps in [
            &mut model.interior,
            &mut model.hole,
            &mut model.ring,
            &mut model.highlight,
            &mut model.flank,
        ] {
            taps.seal();
        }
        let blocks = [
            &model.interior,
            &model.hole,
            &model.ring,
            &model.highlight,
            &model.flank,
        ]
        .map(|taps| {
            let n = taps.padded_len();
            let block = (n / LANES).div_ceil(BLOCKS).max(1) * LANES;
            (0..n)
                .step_by(block)
                .map(|start| ((start + block).min(n), taps.weight_of(start..n)))
                .collect()
        });
        model.blocks = blocks;
        model.rounding_margin = 1e-4
            * (2.0 * f64::from(model.interior.weight())
                + 2.0 * f64::from(HOLE_WEIGHT * model.hole.weight())
                + 2.0 * f64::from(RING_WEIGHT * model.ring.weight())
                + f64::from(HIGHLIGHT_WEIGHT)
                    * f64::from(model.highlight.weight().abs() + model.flank.weight().abs())
                + 1.0);
        model
    }

    /// The model with the axis' darkness floored at `floor` (see `highlight_floor`).
    pub fn with_highlight_floor(mut self, floor: f32) -> Self {
        self.highlight_floor = floor;
        self
    }

    pub fn half_width(&self) -> f32 {
        self.geometry.half_width
    }

    pub fn half_length(&self) -> f32 {
        self.geometry.half_length
    }

    /// Farthest any tap of a pose lies from its centre, whatever its angle (pixels of this
    /// level).
    pub fn reach(&self) -> f32 {
        [
            &self.interior,
            &self.hole,
            &self.ring,
            &self.highlight,
            &self.flank,
        ]
        .iter()
        .map(|t| t.reach())
        .fold(0.0, f32::max)
    }

    /// Whether the point (pixels of this level) lies inside the pose's outline.
    pub fn covers(&self, pose: Pose, point: (f64, f64)) -> bool {
        let (s, c) = pose.phi.sin_cos();
        let (dx, dy) = (point.0 - pose.x, point.1 - pose.y);
        let (u, v) = (dx * c - dy * s, dx * s + dy * c);
        self.geometry.signed_distance(u as f32, v as f32) < 0.0
    }

    /// Whether two poses claim one grain's place: of the nine points of either outline a
    /// quarter of its length and width apart (its centre among them), three or more lie
    /// inside the other's outline by a tenth of its width, a third of a grain's area of
    /// overlap. Grains touching face to face, end to end or at a corner share none.
    pub fn same_place(&self, a: Pose, b: Pose) -> bool {
        let g = &self.geometry;
        let depth = 0.2 * g.half_width;
        let (qu, qv) = (
            0.5 * f64::from(g.half_length),
            0.5 * f64::from(g.half_width),
        );
        let inside = |p: Pose, q: Pose| {
            let (s, c) = p.phi.sin_cos();
            let (qs, qc) = q.phi.sin_cos();
            let mut n = 0;
            for u in [-qu, 0.0, qu] {
                for v in [-qv, 0.0, qv] {
                    let (dx, dy) = (p.x + u * c + v * s - q.x, p.y - u * s + v * c - q.y);
                    let (uq, vq) = (dx * qc - dy * qs, dx * qs + dy * qc);
                    n += usize::from(g.signed_distance(uq as f32, vq as f32) < -depth);
                }
            }
            n
        };
        inside(a, b) >= 3 || inside(b, a) >= 3
    }

    /// Half extents (columns, rows) of the axis-aligned box that holds the pose and its ring.
    pub fn extent(&self, phi: f64) -> (f32, f32) {
        let g = &self.geometry;
        let (s, c) = (phi.sin().abs() as f32, phi.cos().abs() as f32);
        let pad = g.ring + g.soft + 1.0;
        (
            c * g.half_length + s * g.half_width + pad,
            s * g.half_length + c * g.half_width + pad,
        )
    }

    /// Scores a pose against the darkness `dark`; the interior is scored on `free`, the
    /// darkness not yet explained by accepted grains, so grains do not overlap.
    pub fn score(&self, pose: Pose, dark: &Bordered, free: &Bordered) -> Score {
        let at = placement(pose);
        self.finish(
            self.interior.sum(at, free, 0.0),
            self.hole.sum(at, dark, 0.0),
            self.ring.sum(at, dark, 0.0),
            self.highlight.sum(at, dark, self.highlight_floor),
            self.flank.sum(at, dark, 0.0),
        )
    }

    /// [`Model::score`] and the derivatives of its total along x, y and the angle, from one
    /// pass over the taps (the refinement's gradient).
    pub fn score_with_slopes(
        &self,
        pose: Pose,
        dark: &Bordered,
        free: &Bordered,
    ) -> (Score, [f64; 3]) {
        let at = placement(pose);
        let cues = self.cues();
        let slopes = cues.map(|(taps, on_free, floor, _)| {
            taps.sum_with_slopes(at, if on_free { free } else { dark }, floor)
        });
        let [interior, hole, ring, axis, flank] = &slopes;
        let score = self.finish(
            (interior.sum, interior.weight),
            (hole.sum, hole.weight),
            (ring.sum, ring.weight),
            (axis.sum, axis.weight),
            (flank.sum, flank.weight),
        );
        // The total is linear in each cue's sum, with the coefficients of `cues` (the ring's
        // and the highlight's scaled to what of them is seen, a constant but where a tap
        // crosses the edge).
        let (axis_part, flank_part) = self.highlight_seen(axis.weight, flank.weight);
        let parts = [
            1.0,
            1.0,
            f64::from(self.ring_seen(ring.weight, self.visible(interior.weight, hole.weight))),
            f64::from(axis_part),
            f64::from(flank_part),
        ];
        let mut gradient = [0.0f64; 3];
        for ((s, (_, _, _, coefficient)), part) in slopes.iter().zip(cues).zip(parts) {
            let coefficient = coefficient * part;
            gradient[0] += coefficient * f64::from(s.dx);
            gradient[1] += coefficient * f64::from(s.dy);
            gradient[2] += coefficient * f64::from(s.dphi);
        }
        (score, gradient)
    }

    /// [`Model::score`], or `None` when the pose certainly scores below `threshold`: each
    /// cue is summed a block of taps at a time, and the pose given up on as soon as even the
    /// most favourable darkness (in [0, 1]) under the taps not yet summed could not lift the
    /// total to the threshold. Poses near the plane's edge are always scored in full.
    pub fn score_unless_below(
        &self,
        pose: Pose,
        dark: &Bordered,
        free: &Bordered,
        threshold: f32,
    ) -> Option<Score> {
        let at = placement(pose);
        let cues = self.cues();
        let planes = cues.map(|(_, on_free, _, _)| if on_free { free } else { dark });
        if !cues.iter().zip(&planes).all(|(c, p)| c.0.inside(at, p)) {
            return Some(self.score(pose, dark, free));
        }
        // What the total is made of: a constant, and per cue a coefficient times its sum.
        let mut known = f64::from(HOLE_WEIGHT * self.hole.weight())
            + f64::from(RING_WEIGHT * self.ring.weight())
            - f64::from(self.interior.weight());
        // The most the taps from a block's start on can add: all dark where that raises the
        // total, else as light as their floor allows.
        let most = |cue: usize, rest: f32| {
            let (_, _, floor, coefficient) = cues[cue];
            let m = coefficient * f64::from(rest);
            if m > 0.0 { m } else { m * f64::from(floor) }
        };
        let mut others: f64 = (0..cues.len())
            .map(|k| self.blocks[k].first().map_or(0.0, |b| most(k, b.1)))
            .sum();
        let cut = threshold as f64 - self.rounding_margin;
        let mut sums = [0.0f32; 5];
        for k in SUMMING_ORDER {
            let (taps, _, floor, coefficient) = cues[k];
            others -= self.blocks[k].first().map_or(0.0, |b| most(k, b.1));
            let mut lanes = [0.0f32; LANES];
            let mut start = 0;
            for &(end, rest) in &self.blocks[k] {
                let partial = coefficient * Taps::lanes_total(lanes) as f64;
                if known + partial + most(k, rest) + others < cut {
                    return None;
                }
                taps.accumulate_inside(at, planes[k], floor, &mut lanes, start..end);
                start = end;
            }
            sums[k] = Taps::lanes_total(lanes);
            known += coefficient * sums[k] as f64;
        }
        Some(self.finish(
            (sums[0], self.interior.weight()),
            (sums[1], self.hole.weight()),
            (sums[2], self.ring.weight()),
            (sums[3], self.highlight.weight()),
            (sums[4], self.flank.weight()),
        ))
    }

    /// The cues as `score_unless_below` sums them: taps, whether on the free darkness, floor,
    /// and the coefficient of their sum in the total.
    fn cues(&self) -> [(&Taps, bool, f32, f64); 5] {
        [
            (&self.interior, true, 0.0, 2.0),
            (&self.hole, false, 0.0, -2.0 * f64::from(HOLE_WEIGHT)),
            (&self.ring, false, 0.0, -2.0 * f64::from(RING_WEIGHT)),
            (
                &self.highlight,
                false,
                self.highlight_floor,
                -f64::from(HIGHLIGHT_WEIGHT),
            ),
            (&self.flank, false, 0.0, -f64::from(HIGHLIGHT_WEIGHT)),
        ]
    }

    /// What the axis and flank sums count for given the weights of their taps seen (inside
    /// the photograph): both scaled to the smaller part seen, so the highlight stays a
    /// contrast, blind to how dark the grain is. Unscaled, a rod a third inside the frame,
    /// its axis beyond the edge and a flank on a dark neighbour, outscored the whole rod next
    /// to it (lab rod53 at 6 px/mm: 511 against 461), and rods along the edge were pushed out
    /// over it. Both 1 when every tap is seen.
    fn highlight_seen(&self, axis_w: f32, flank_w: f32) -> (f32, f32) {
        let (full_axis, full_flank) = (self.highlight.weight(), self.flank.weight());
        if axis_w == full_axis && flank_w == full_flank {
            return (1.0, 1.0);
        }
        let axis_seen = if full_axis != 0.0 {
            axis_w / full_axis
        } else {
            0.0
        };
        let flank_seen = if full_flank != 0.0 {
            flank_w / full_flank
        } else {
            0.0
        };
        let seen = axis_seen.min(flank_seen);
        if seen <= 0.0 {
            return (0.0, 0.0);
        }
        (seen / axis_seen, seen / flank_seen)
    }

    /// Fraction of the outline's area seen, from the weights of the interior and hole taps
    /// seen.
    fn visible(&self, int_w: f32, hole_w: f32) -> f32 {
        if self.area > 0.0 {
            (int_w + hole_w) / self.area
        } else {
            0.0
        }
    }

    /// What the ring's sum counts for given the weight of its taps seen and the part of the
    /// outline seen (`visible`): for a pose mostly inside the frame, scaled up to the whole
    /// ring, the part beyond the edge read as the part seen reads; else, and when all of it
    /// is seen, 1.
    ///
    /// Summed as seen, a pose pushed over the edge shed the ring's penalty for the dark
    /// neighbours beyond, which in a dense deposit lie all along the edge: a rod lying whole
    /// along the edge, with the rod the edge cuts beyond it, was fitted standing across both,
    /// cut by the edge (lab rod53 at 6 px/mm, seed 58 ordered, at (153.5, 3.6) mm), and the
    /// rod refitted along the edge slid down onto the cut one. Of the rods turned on lab
    /// rod53 at 6 px/mm, seeds 50-59, 17 of 22 were such rods, whole within 4 mm of the edge
    /// and found cut. A pose mostly beyond the edge is the strip the edge leaves of a rod
    /// (the edge repair's stubs): scaled up from that sliver, its ring would be charged as a
    /// whole rod's, and the strip would go unexplained.
    fn ring_seen(&self, ring_w: f32, visible: f32) -> f32 {
        let full = self.ring.weight();
        if ring_w == full || ring_w <= 0.0 || visible < 0.5 {
            return 1.0;
        }
        full / ring_w
    }

    /// The score from the groups' sums (darkness, weight): one formula for every way of
    /// summing them, so they agree to the bit.
    fn finish(
        &self,
        (int_d, int_w): (f32, f32),
        (hole_d, hole_w): (f32, f32),
        (ring_d, ring_w): (f32, f32),
        (axis_d, axis_w): (f32, f32),
        (flank_d, flank_w): (f32, f32),
    ) -> Score {
        let (axis_part, flank_part) = self.highlight_seen(axis_w, flank_w);
        let hl_d = axis_part * axis_d + flank_part * flank_d;
        let inside = 2.0 * int_d - int_w;
        let hole = hole_w - 2.0 * hole_d;
        let visible = self.visible(int_w, hole_w);
        let ring = self.ring_seen(ring_w, visible) * (ring_w - 2.0 * ring_d);
        let agreement = if int_w + hole_w > 0.0 {
            (inside + hole) / (int_w + hole_w)
        } else {
            -1.0
        };
        Score {
            total: inside + HOLE_WEIGHT * hole + RING_WEIGHT * ring - HIGHLIGHT_WEIGHT * hl_d,
            agreement,
            visible: visible.min(1.0),
        }
    }

    /// Adds this pose's opacity to the explained map (clamped to 1) and lowers the free
    /// darkness (`dark` times what is not explained) to match, in both its forms.
    pub fn paint(
        &self,
        pose: Pose,
        dark: &Plane,
        explained: &mut Plane,
        free: &mut Plane,
        free_bordered: &mut Bordered,
    ) {
        let all = (
            0,
            explained.width as isize - 1,
            0,
            explained.height as isize - 1,
        );
        self.paint_within(pose, dark, explained, free, free_bordered, all);
    }

    /// The pixels [`Model::paint`] may change on a `width` x `height` plane: columns
    /// `c0..=c1`, rows `r0..=r1` (empty when c0 > c1 or r0 > r1).
    pub fn painted_box(
        &self,
        pose: Pose,
        width: usize,
        height: usize,
    ) -> (isize, isize, isize, isize) {
        let (ex, ey) = self.extent(pose.phi);
        let (px, py) = (pose.x as f32, pose.y as f32);
        (
            ((px - ex).floor() as isize).max(0),
            ((px + ex).ceil() as isize).min(width as isize - 1),
            ((py - ey).floor() as isize).max(0),
            ((py + ey).ceil() as isize).min(height as isize - 1),
        )
    }

    /// [`Model::paint`] on the pixels of columns `clip.0..=clip.1` and rows
    /// `clip.2..=clip.3` only.
    pub fn paint_within(
        &self,
        pose: Pose,
        dark: &Plane,
        explained: &mut Plane,
        free: &mut Plane,
        free_bordered: &mut Bordered,
        clip: (isize, isize, isize, isize),
    ) {
        let width = explained.width;
        self.each_covered(pose, width, explained.height, clip, |c, r, cov| {
            let i = r * width + c;
            let e = &mut explained.data[i];
            *e = (*e + cov).min(1.0);
            free.data[i] = dark.data[i] * (1.0 - *e);
            free_bordered.set(c, r, free.data[i]);
        });
    }

    /// Calls `at(col, row, coverage)` for each pixel of a `width` x `height` plane within
    /// `clip` (as [`Model::paint_within`]'s) that the pose's outline covers.
    pub fn each_covered(
        &self,
        pose: Pose,
        width: usize,
        height: usize,
        clip: (isize, isize, isize, isize),
        mut at: impl FnMut(usize, usize, f32),
    ) {
        let (sin, cos) = (pose.phi.sin() as f32, pose.phi.cos() as f32);
        let (px, py) = (pose.x as f32, pose.y as f32);
        let g = &self.geometry;
        // A hundredth of a pixel more, for the rounding of the distance.
        let (reach_u, reach_v) = (
            g.half_length + 0.5 * g.soft + 0.01,
            g.half_width + 0.5 * g.soft + 0.01,
        );
        let (c0, c1, r0, r1) = self.painted_box(pose, width, height);
        let (c0, c1) = (c0.max(clip.0), c1.min(clip.1));
        let (r0, r1) = (r0.max(clip.2), r1.min(clip.3));
        // Deeper inside than half the soft edge along both axes the coverage is 1.
        let (solid_u, solid_v) = (
            g.half_length - g.round.max(0.5 * g.soft) - 0.01,
            g.half_width - g.round.max(0.5 * g.soft) - 0.01,
        );
        for r in r0..=r1 {
            let dy = r as f32 + 0.5 - py;
            for c in c0..=c1 {
                let dx = c as f32 + 0.5 - px;
                let u = (dx * cos - dy * sin).abs();
                let v = (dx * sin + dy * cos).abs();
                // Farther out than half the soft edge along either axis the coverage is 0
                // (the signed distance is at least |u| - half length): no root to take.
                if u > reach_u || v > reach_v {
                    continue;
                }
                let cov = if u < solid_u && v < solid_v {
                    1.0
                } else {
                    self.geometry.coverage(u, v)
                };
                if cov > 0.0 {
                    at(c as usize, r as usize, cov);
                }
            }
        }
    }

    /// Coverage in [0, 1] of the pixel (`col`, `row`) by the pose's hole (none for rods):
    /// the part of the outline that is not dark.
    pub fn hole_at(&self, pose: Pose, col: usize, row: usize) -> f32 {
        let g = &self.geometry;
        if g.hole_radius <= 0.0 {
            return 0.0;
        }
        let (dx, dy) = (
            col as f32 + 0.5 - pose.x as f32,
            row as f32 + 0.5 - pose.y as f32,
        );
        let reach = g.hole_radius + g.soft;
        if dx.abs() > reach || dy.abs() > reach {
            return 0.0;
        }
        g.hole_coverage(dx, dy)
    }

    /// The coverage in [0, 1] of a pixel (`col`, `row`) by the pose's outline and by its
    /// hole, the pose's rotation worked out once for every pixel asked.
    pub fn coverage_of(&self, pose: Pose) -> impl Fn(usize, usize) -> (f32, f32) + '_ {
        let (sin, cos) = (pose.phi.sin() as f32, pose.phi.cos() as f32);
        let (px, py) = (pose.x as f32, pose.y as f32);
        let g = &self.geometry;
        let hole_reach = g.hole_radius + g.soft;
        move |col, row| {
            let dx = col as f32 + 0.5 - px;
            let dy = row as f32 + 0.5 - py;
            let (u, v) = (dx * cos - dy * sin, dx * sin + dy * cos);
            let hole = if g.hole_radius > 0.0 && dx.abs() <= hole_reach && dy.abs() <= hole_reach {
                g.hole_coverage(dx, dy)
            } else {
                0.0
            };
            (g.coverage(u, v), hole)
        }
    }

    /// Whether a pixel (`col`, `row`) lies within `reach` pixels of the pose's outline or
    /// its hole's edge: where moving the pose by less than `reach` less the anti-aliasing
    /// ramp can change a coverage.
    pub fn near_edge_of(&self, pose: Pose, reach: f32) -> impl Fn(usize, usize) -> bool + '_ {
        let (sin, cos) = (pose.phi.sin() as f32, pose.phi.cos() as f32);
        let (px, py) = (pose.x as f32, pose.y as f32);
        let g = &self.geometry;
        move |col, row| {
            let dx = col as f32 + 0.5 - px;
            let dy = row as f32 + 0.5 - py;
            let (u, v) = (dx * cos - dy * sin, dx * sin + dy * cos);
            g.signed_distance(u, v).abs() <= reach
                || (g.hole_radius > 0.0 && (u.hypot(v) - g.hole_radius).abs() <= reach)
        }
    }

    /// Width of the outline's anti-aliasing ramp (pixels).
    pub fn softness(&self) -> f32 {
        self.geometry.soft
    }

    /// Corners of the outline (pixels), for the cut test and overlays.
    pub fn corners(&self, pose: Pose) -> [(f64, f64); 4] {
        let (s, c) = pose.phi.sin_cos();
        let (a, b) = (
            self.geometry.half_length as f64,
            self.geometry.half_width as f64,
        );
        [(a, b), (-a, b), (-a, -b), (a, -b)].map(|(u, v)| {
            // Inverse of u = dx cos - dy sin, v = dx sin + dy cos.
            (pose.x + u * c + v * s, pose.y - u * s + v * c)
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::detect::testing::Lcg;

    /// A darkness with grain-sized dark patches and noise, in [0, 1] as the detector's are.
    fn patchy_plane(width: usize, height: usize) -> Plane {
        let mut rng = Lcg(0x2545_f491_4f6c_dd1d);
        let mut plane = Plane::new(width, height, 0.0);
        for r in 0..height {
            for c in 0..width {
                let noise = rng.unit_f32();
                let patch = ((c / 13 + r / 7) % 3 != 0) as u8 as f32;
                plane.data[r * width + c] = (0.8 * patch + 0.2 * noise).clamp(0.0, 1.0);
            }
        }
        plane
    }

    /// Painting skips only pixels the outline does not cover: the maps are those of
    /// painting every pixel of the box, to the bit, at every angle and at the edges.
    #[test]
    fn painting_skips_no_covered_pixel() {
        let dark = patchy_plane(90, 70);
        for shape in [
            GrainShape::nut(6.9e-3),
            GrainShape::Rod {
                length: 8.9e-3,
                width: 3e-3,
            },
        ] {
            let model = Model::new(shape, 3.3e3);
            let (mut explained, mut free, mut bordered) =
                (Plane::new(90, 70, 0.0), dark.clone(), Bordered::new(&dark));
            let (mut want_e, mut want_f, mut want_b) =
                (explained.clone(), free.clone(), bordered.clone());
            for k in 0..60 {
                let pose = Pose {
                    x: -5.0 + (k % 13) as f64 * 8.1,
                    y: -4.0 + (k % 7) as f64 * 11.3,
                    phi: k as f64 * 0.173,
                };
                model.paint(pose, &dark, &mut explained, &mut free, &mut bordered);
                let (s, c) = (pose.phi.sin() as f32, pose.phi.cos() as f32);
                for r in 0..70 {
                    for col in 0..90 {
                        let dx = col as f32 + 0.5 - pose.x as f32;
                        let dy = r as f32 + 0.5 - pose.y as f32;
                        let cov = model.geometry.coverage(dx * c - dy * s, dx * s + dy * c);
                        if cov > 0.0 {
                            let i = r * 90 + col;
                            want_e.data[i] = (want_e.data[i] + cov).min(1.0);
                            want_f.data[i] = dark.data[i] * (1.0 - want_e.data[i]);
                            want_b.set(col, r, want_f.data[i]);
                        }
                    }
                }
            }
            let bits = |v: &[f32]| v.iter().map(|x| x.to_bits()).collect::<Vec<_>>();
            assert_eq!(bits(&explained.data), bits(&want_e.data));
            assert_eq!(bits(&free.data), bits(&want_f.data));
            assert_eq!(bits(&bordered.data), bits(&want_b.data));
            assert!(explained.data.iter().any(|&e| e > 0.0 && e < 1.0));
        }
    }

    /// A point lies inside an outline when it is inside the turned rectangle.
    #[test]
    fn covers_the_points_inside_the_outline_only() {
        let model = Model::new(
            GrainShape::Rod {
                length: 9e-3,
                width: 3e-3,
            },
            1e3,
        );
        // The axis points along (cos phi, -sin phi): at 90 degrees, up the image.
        let pose = Pose {
            x: 20.0,
            y: 20.0,
            phi: std::f64::consts::FRAC_PI_2,
        };
        assert!(model.covers(pose, (20.0, 24.0)));
        assert!(model.covers(pose, (21.2, 16.0)));
        assert!(!model.covers(pose, (24.0, 20.0)));
        assert!(!model.covers(pose, (20.0, 25.0)));
    }

    /// Rods touching face to face, end to end or corner to corner (and a pixel apart, or a
    /// pixel into each other, as fits leave them) each hold their own place; a rod turned
    /// across another, or shifted along it by half a length or across it by half a width,
    /// claims its place. Nuts alike.
    #[test]
    fn same_place_is_overlap_not_contact() {
        let rod = Model::new(
            GrainShape::Rod {
                length: 4.9e-3,
                width: 3e-3,
            },
            1e4,
        );
        let (l, w) = (49.0, 30.0);
        let at = |x: f64, y: f64, deg: f64| Pose {
            x,
            y,
            phi: deg.to_radians(),
        };
        let a = at(100.0, 100.0, 0.0);
        for gap in [-1.0, 0.0, 1.0] {
            assert!(!rod.same_place(a, at(100.0, 100.0 + w + gap, 0.0)), "face");
            assert!(!rod.same_place(a, at(100.0 + l + gap, 100.0, 0.0)), "end");
            assert!(
                !rod.same_place(a, at(100.0 + l + gap, 100.0 + w, 0.0)),
                "corner"
            );
            // Standing across its end, touching it.
            let across = at(100.0 + 0.5 * l + 0.5 * w + gap, 100.0, 90.0);
            assert!(!rod.same_place(a, across), "across its end");
            assert!(!rod.same_place(across, a), "across its end, the other way");
        }
        // The case of the acceptance: standing over it, 8 px off its centre.
        assert!(rod.same_place(a, at(108.0, 100.0, 93.0)));
        assert!(
            rod.same_place(a, at(100.0 + 0.5 * l, 100.0, 0.0)),
            "half a length on"
        );
        assert!(
            rod.same_place(a, at(100.0, 100.0 + 0.5 * w, 0.0)),
            "half a width across"
        );
        let nut = Model::new(GrainShape::nut(6.9e-3), 1e4);
        let s = 69.0;
        let b = at(100.0, 100.0, 10.0);
        assert!(!nut.same_place(
            b,
            at(
                100.0 + s * 10f64.to_radians().cos(),
                100.0 - s * 10f64.to_radians().sin(),
                10.0
            )
        ));
        assert!(nut.same_place(b, at(110.0, 104.0, 35.0)));
    }
    /// A rod model at 6 px/mm and a darkness of 1 everywhere, 80 x 60 px: a dense deposit
    /// that goes on beyond the frame.
    fn rod_on_plain_darkness() -> (Model, Bordered) {
        let model = Model::new(
            GrainShape::Rod {
                length: 5e-3,
                width: 3e-3,
            },
            6e3,
        )
        .with_highlight_floor(0.6);
        (model, Bordered::new(&Plane::new(80, 60, 1.0)))
    }

    /// Forty poses of a rod lying along the top edge, from `y` (pixels) outward a quarter
    /// pixel at a time and turned by up to 0.04: those the edge cuts, with their scores.
    fn cut_along_top_edge(model: &Model, dark: &Bordered, y: f64) -> Vec<(Pose, Score)> {
        (0..40)
            .map(|k| Pose {
                x: 40.0,
                y: y - 0.25 * k as f64,
                phi: (k % 5) as f64 * 0.01,
            })
            .map(|pose| (pose, model.score(pose, dark, dark)))
            .filter(|(_, score)| score.visible < 1.0)
            .collect()
    }

    /// The highlight is a contrast wherever the frame's edge cuts the rod: on a darkness the
    /// same everywhere it adds no more than on a rod wholly inside, even with the axis beyond
    /// the edge and a flank inside (where, summed as seen, the flank alone paid a third of a
    /// rod's score).
    #[test]
    fn a_rod_cut_by_the_edge_gains_nothing_from_its_highlight_on_plain_darkness() {
        let (model, dark) = rod_on_plain_darkness();
        let mut plain = model.clone();
        plain.highlight = Taps::default();
        plain.flank = Taps::default();
        let highlight_part = |pose: Pose| {
            model.score(pose, &dark, &dark).total - plain.score(pose, &dark, &dark).total
        };
        let whole = highlight_part(Pose {
            x: 40.0,
            y: 30.0,
            phi: 0.0,
        })
        .abs();
        let flank = model.flank.weight().abs();
        // A tenth of the flank's weight: the imbalance of the whole rod's taps is smaller.
        assert!(whole < 0.1 * HIGHLIGHT_WEIGHT * flank, "{whole} whole");
        // Across the top edge, from a third of the width out to most of it.
        let cut = cut_along_top_edge(&model, &dark, 6.0);
        assert!(cut.len() > 30, "{} poses cut", cut.len());
        for (pose, score) in cut {
            let part = highlight_part(pose);
            assert!(
                part.abs() <= whole + 1e-4 * HIGHLIGHT_WEIGHT * flank,
                "highlight {part} at y {} (visible {}) against {whole} whole",
                pose.y,
                score.visible
            );
        }
    }

    /// On a darkness the same everywhere (a dense deposit, which goes on beyond the frame),
    /// nothing in the photograph prefers a pose pushed over the edge: for a pose mostly
    /// inside, the ring counts as much as for a pose wholly inside, and every such pose the
    /// edge cuts scores less than the rod wholly inside. Summed as seen, the ring beyond the
    /// edge read nothing, and a rod a pixel over the edge outscored the whole one.
    #[test]
    fn a_rod_pushed_over_the_edge_gains_nothing_from_its_ring_on_plain_darkness() {
        let (model, dark) = rod_on_plain_darkness();
        let mut ringless = model.clone();
        ringless.ring = Taps::default();
        let ring_part = |pose: Pose| {
            model.score(pose, &dark, &dark).total - ringless.score(pose, &dark, &dark).total
        };
        let inside = Pose {
            x: 40.0,
            y: 30.0,
            phi: 0.0,
        };
        let (whole, whole_ring) = (model.score(inside, &dark, &dark), ring_part(inside));
        // Along the top edge, from a pixel in from it to half the width beyond.
        let cut = cut_along_top_edge(&model, &dark, 10.0);
        assert!(cut.len() > 30, "{} poses cut", cut.len());
        for (pose, score) in cut {
            let ring = ring_part(pose);
            assert!(
                (ring - whole_ring).abs() <= 1e-3 * whole_ring.abs(),
                "ring {ring} at y {} (visible {}) against {whole_ring} whole",
                pose.y,
                score.visible
            );
            assert!(
                score.total < whole.total,
                "{} at y {} (visible {}) against {} whole",
                score.total,
                pose.y,
                score.visible,
                whole.total
            );
        }
    }

    /// A pose given up on scores below the threshold; a pose kept scores what `score` gives,
    /// to the bit, so the coarse search's finalists do not depend on what was given up.
    #[test]
    fn giving_up_is_exact() {
        let raw = patchy_plane(120, 90);
        let free = Bordered::new(&Plane {
            data: raw.data.iter().map(|d| d * 0.7).collect(),
            ..raw.clone()
        });
        let dark = Bordered::new(&raw);
        for (shape, floor) in [
            (GrainShape::nut(6.9e-3), 0.0),
            (
                GrainShape::Rod {
                    length: 8.9e-3,
                    width: 3e-3,
                },
                0.6,
            ),
        ] {
            let model = Model::with_softness(shape, 3.3e3, 2.0).with_highlight_floor(floor);
            let (mut dropped, mut kept) = (0, 0);
            for k in 0..200 {
                let pose = Pose {
                    x: 25.0 + (k % 17) as f64 * 4.3,
                    y: 20.0 + (k % 11) as f64 * 4.9,
                    phi: k as f64 * 0.31,
                };
                let full = model.score(pose, &dark, &free);
                for threshold in [-1e9, full.total - 5.0, full.total, full.total + 5.0, 1e9] {
                    match model.score_unless_below(pose, &dark, &free, threshold) {
                        None => {
                            assert!(full.total < threshold);
                            dropped += 1;
                        }
                        Some(s) => {
                            assert_eq!(s.total.to_bits(), full.total.to_bits());
                            assert_eq!(s.agreement.to_bits(), full.agreement.to_bits());
                            assert_eq!(s.visible.to_bits(), full.visible.to_bits());
                            kept += 1;
                        }
                    }
                }
            }
            // Both outcomes occur, so the test says something about each.
            assert!(
                dropped > 100 && kept > 400,
                "{dropped} dropped, {kept} kept"
            );
        }
    }
}
