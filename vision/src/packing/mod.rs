//! Dense packings of touching grains that stand in for deposits until the simulator makes them.
//!
//! Grains are scattered in a periodic box, overlaps are removed, then the box is shrunk step by
//! step, each step followed by overlap removal; when a step can no longer be relaxed the grains
//! are jammed and the last relaxed state is kept. Shrinking stops at steps of 0.1 % of the box,
//! so neighbours end within ~0.1 % of D of touching and overlap by less than
//! [`OVERLAP_TOLERANCE`] D. The frame is cut out of the periodic packing (periodic images
//! included), so grains crossing its edges are there, cut, as in a photograph.

mod contact;
mod relax;

use std::f64::consts::PI;

use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

use crate::{Frame, GrainOutline, GrainShape};
use contact::Body;
use relax::{Box2, Relax, deepest_overlap, relax};

/// Relaxation stops once the deepest overlap is below this fraction of the grain width D.
pub const OVERLAP_TOLERANCE: f64 = 0.003;
/// While squeezing, a step counts as relaxed at this looser overlap (fraction of D): waiting
/// for the strict tolerance at every step jams the packing early in chains of contacts that
/// Gauss-Seidel sweeps straighten only slowly. The final relaxation meets the strict one.
const SQUEEZE_TOLERANCE: f64 = 0.04;
/// Random shift (fraction of D, full range) given to every grain at each squeeze step.
const JITTER: f64 = 0.1;

/// How the grains were laid down.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Packing {
    /// Slow filling: grains mostly lie flat (squares on a face, rods horizontal), with some
    /// grains at random angles as defects.
    Ordered,
    /// Fast filling: random orientations.
    Disordered,
}

impl std::str::FromStr for Packing {
    type Err = String;
    fn from_str(s: &str) -> Result<Self, String> {
        match s {
            "ordered" => Ok(Packing::Ordered),
            "disordered" => Ok(Packing::Disordered),
            other => Err(format!(
                "unknown packing `{other}`: expected ordered or disordered"
            )),
        }
    }
}

/// A generated packing, cut to a frame.
#[derive(Clone, Debug)]
pub struct PackedFrame {
    /// Grains that show in the frame (frame coordinates; centres of cut grains may lie outside).
    pub grains: Vec<GrainOutline>,
    /// Area fraction covered by grain outlines (holes not removed) in the periodic box.
    pub packing_fraction: f64,
    /// Deepest overlap between two grains, as a fraction of D.
    pub max_overlap: f64,
}

/// Fraction of grains in an ordered packing that fall at a random angle.
const ORDERED_DEFECTS: f64 = 0.12;
/// Spread of the aligned grains' angles around flat (radians).
const ORDERED_SPREAD: f64 = 4.0 * PI / 180.0;

/// Makes a dense packing of one grain shape that covers `frame` (its width and height; the scale
/// is not used), deterministic for a seed.
pub fn generate(shape: GrainShape, packing: Packing, frame: &Frame, seed: u64) -> PackedFrame {
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    let (length, width) = (shape.length(), shape.width());
    // The box must stay larger than the frame after compression: size it for a packing fraction
    // above what these grains reach (0.80 at most in trials), plus a margin of half a grain length
    // on each side.
    let margin = length;
    let target_area = (frame.width + margin) * (frame.height + margin);
    let grain_area = length * width;
    let count = (target_area * 0.9 / grain_area).ceil() as usize;
    let start_fraction = 0.5;
    let stretch = (count as f64 * grain_area / start_fraction / target_area).sqrt();
    let mut domain = Box2 {
        width: (frame.width + margin) * stretch,
        height: (frame.height + margin) * stretch,
    };
    let mut bodies: Vec<Body> = (0..count)
        .map(|_| Body {
            x: rng.random::<f64>() * domain.width,
            y: rng.random::<f64>() * domain.height,
            theta: initial_angle(shape, packing, &mut rng),
            half_length: 0.5 * length,
            half_width: 0.5 * width,
        })
        .collect();
    let rotation_mobility = match packing {
        Packing::Ordered => 0.15,
        Packing::Disordered => 1.0,
    };
    let settle = Relax {
        tolerance: OVERLAP_TOLERANCE * width,
        max_sweeps: 400,
        rotation_mobility,
    };
    relax(&mut bodies, &domain, &settle);
    let squeeze = Relax {
        max_sweeps: 20,
        tolerance: SQUEEZE_TOLERANCE * width,
        rotation_mobility,
    };
    let mut step: f64 = 0.02;
    let mut last = bodies.clone();
    let mut last_domain = Box2 {
        width: domain.width,
        height: domain.height,
    };
    while step > 1e-3 {
        let factor = 1.0 - step;
        for b in bodies.iter_mut() {
            b.x *= factor;
            b.y *= factor;
            // A shake: chains of contacts buckle and grains find the voids.
            b.x += JITTER * width * (rng.random::<f64>() - 0.5);
            b.y += JITTER * width * (rng.random::<f64>() - 0.5);
        }
        domain.width *= factor;
        domain.height *= factor;
        let too_small = domain.width < frame.width || domain.height < frame.height;
        if !too_small && relax(&mut bodies, &domain, &squeeze).1 {
            last.clone_from(&bodies);
            last_domain = Box2 {
                width: domain.width,
                height: domain.height,
            };
            step = (step * 1.5).min(0.02);
        } else {
            bodies.clone_from(&last);
            domain = Box2 {
                width: last_domain.width,
                height: last_domain.height,
            };
            step *= 0.5;
        }
    }
    // The loose squeeze can leave overlaps the strict relaxation cannot undo in place: let the
    // box out a little until it can.
    while !relax(&mut bodies, &domain, &settle).1 {
        let factor = 1.002;
        for b in bodies.iter_mut() {
            b.x *= factor;
            b.y *= factor;
        }
        domain.width *= factor;
        domain.height *= factor;
    }
    let max_overlap = deepest_overlap(&bodies, &domain) / width;
    let packing_fraction = count as f64 * grain_area / (domain.width * domain.height);
    PackedFrame {
        grains: cut_to_frame(&bodies, &domain, shape, frame),
        packing_fraction,
        max_overlap,
    }
}

fn initial_angle(shape: GrainShape, packing: Packing, rng: &mut ChaCha8Rng) -> f64 {
    let period = shape.symmetry_period();
    match packing {
        Packing::Disordered => rng.random::<f64>() * period,
        Packing::Ordered => {
            if rng.random::<f64>() < ORDERED_DEFECTS {
                rng.random::<f64>() * period
            } else {
                // Box-Muller: a normal spread around flat.
                let u1: f64 = 1.0 - rng.random::<f64>();
                let u2: f64 = rng.random::<f64>();
                ORDERED_SPREAD * (-2.0 * u1.ln()).sqrt() * (2.0 * PI * u2).cos()
            }
        }
    }
}

/// The grains (and periodic images) that show in the frame placed at the box's origin.
fn cut_to_frame(
    bodies: &[Body],
    domain: &Box2,
    shape: GrainShape,
    frame: &Frame,
) -> Vec<GrainOutline> {
    let mut out = Vec::new();
    for b in bodies {
        for ix in -1..=1 {
            for iy in -1..=1 {
                let outline = GrainOutline {
                    x: b.x + ix as f64 * domain.width,
                    y: b.y + iy as f64 * domain.height,
                    theta: b.theta.rem_euclid(shape.symmetry_period()),
                    shape,
                };
                if outline.overlaps_frame(frame) {
                    out.push(outline);
                }
            }
        }
    }
    out
}
