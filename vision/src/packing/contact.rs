//! Overlap of two rectangles by separating axes: depth, normal and contact point.
//!
//! Packing only needs the rectangles: the rounded corners (r = 0.05 D) lie inside them, so a
//! packing free of rectangle overlaps is free of spheropolygon overlaps too.

/// A rectangle being packed: centre, angle, half-extents (metres).
#[derive(Clone, Copy, Debug)]
pub struct Body {
    pub x: f64,
    pub y: f64,
    pub theta: f64,
    pub half_length: f64,
    pub half_width: f64,
}

/// How two overlapping rectangles interpenetrate.
#[derive(Clone, Copy, Debug)]
pub struct Contact {
    /// Penetration depth along `normal` (metres, positive).
    pub depth: f64,
    /// Unit normal from the first body towards the second.
    pub normal: [f64; 2],
    /// Where the bodies press on each other, relative to the first body's centre.
    pub point: [f64; 2],
}

impl Body {
    fn axes(&self) -> ([f64; 2], [f64; 2]) {
        let (s, c) = self.theta.sin_cos();
        ([c, s], [-s, c])
    }

    /// Half the extent of the rectangle projected on a unit axis.
    fn radius_along(&self, axis: [f64; 2]) -> f64 {
        let (u, v) = self.axes();
        self.half_length * dot(u, axis).abs() + self.half_width * dot(v, axis).abs()
    }

    /// Corners relative to the centre.
    fn corners(&self) -> [[f64; 2]; 4] {
        let (u, v) = self.axes();
        let (a, b) = (self.half_length, self.half_width);
        [(1.0, 1.0), (-1.0, 1.0), (-1.0, -1.0), (1.0, -1.0)]
            .map(|(s, t)| [s * a * u[0] + t * b * v[0], s * a * u[1] + t * b * v[1]])
    }
}

fn dot(a: [f64; 2], b: [f64; 2]) -> f64 {
    a[0] * b[0] + a[1] * b[1]
}

/// Overlap of `a` and `b`, where `b`'s centre sits at offset `d` from `a`'s (the caller applies
/// the periodic minimum image). `None` when they do not overlap.
pub fn contact(a: &Body, b: &Body, d: [f64; 2]) -> Option<Contact> {
    let (ua, va) = a.axes();
    let (ub, vb) = b.axes();
    let mut best: Option<(f64, [f64; 2], bool)> = None;
    for (axis, of_a) in [(ua, true), (va, true), (ub, false), (vb, false)] {
        let separation = dot(d, axis);
        let depth = a.radius_along(axis) + b.radius_along(axis) - separation.abs();
        if depth <= 0.0 {
            return None;
        }
        if best.is_none_or(|(best_depth, _, _)| depth < best_depth) {
            let n = if separation >= 0.0 {
                axis
            } else {
                [-axis[0], -axis[1]]
            };
            best = Some((depth, n, of_a));
        }
    }
    let (depth, n, face_of_a) = best?;
    // The incident body's corners that reach deepest through the reference face; corners about
    // as deep as the deepest are averaged so that face-to-face contacts press at their middle.
    let (point, reference_centre, tangent_half) = if face_of_a {
        let corners = b.corners().map(|c| [c[0] + d[0], c[1] + d[1]]);
        let p = deepest(&corners, [-n[0], -n[1]], depth);
        let t = [-n[1], n[0]];
        (p, [0.0, 0.0], a.radius_along(t))
    } else {
        let p = deepest(&a.corners(), n, depth);
        let t = [-n[1], n[0]];
        (p, d, b.radius_along(t))
    };
    // Keep the pressing point on the reference face: an incident corner beyond the face's end
    // (a long rod across a short face) would give a lever arm the contact does not have.
    let t = [-n[1], n[0]];
    let along = dot(
        [
            point[0] - reference_centre[0],
            point[1] - reference_centre[1],
        ],
        t,
    );
    let clamped = along.clamp(-tangent_half, tangent_half);
    let shift = clamped - along;
    Some(Contact {
        depth,
        normal: n,
        point: [point[0] + shift * t[0], point[1] + shift * t[1]],
    })
}

/// Mean of the corners furthest along `direction` (within a fraction of the depth of the best).
fn deepest(corners: &[[f64; 2]; 4], direction: [f64; 2], depth: f64) -> [f64; 2] {
    let reach = corners.map(|c| dot(c, direction));
    let max = reach.iter().copied().fold(f64::NEG_INFINITY, f64::max);
    let (mut sum, mut count) = ([0.0, 0.0], 0.0);
    for (c, r) in corners.iter().zip(reach) {
        if r >= max - 0.5 * depth {
            sum[0] += c[0];
            sum[1] += c[1];
            count += 1.0;
        }
    }
    [sum[0] / count, sum[1] / count]
}

#[cfg(test)]
mod tests {
    use super::*;

    fn square(theta: f64) -> Body {
        Body {
            x: 0.0,
            y: 0.0,
            theta,
            half_length: 1.0,
            half_width: 1.0,
        }
    }

    #[test]
    fn aligned_squares_overlap_by_their_interpenetration() {
        let c = contact(&square(0.0), &square(0.0), [1.9, 0.2]).unwrap();
        assert!((c.depth - 0.1).abs() < 1e-12);
        assert!((c.normal[0] - 1.0).abs() < 1e-12 && c.normal[1].abs() < 1e-12);
        // Face to face: the pressing point lies on the shared face, between the faces' ends.
        assert!(
            (c.point[0] - 0.9).abs() < 0.06 && c.point[1].abs() < 1.0,
            "{:?}",
            c.point
        );
        assert!(contact(&square(0.0), &square(0.0), [2.01, 0.0]).is_none());
    }

    #[test]
    fn corner_into_face() {
        // A square turned 45 degrees pokes one corner (at x = 2.5 - sqrt 2) into the first.
        let c = contact(
            &square(0.0),
            &square(std::f64::consts::FRAC_PI_4),
            [2.3, 0.0],
        )
        .unwrap();
        let expected = 1.0 - (2.3 - 2f64.sqrt());
        assert!((c.depth - expected).abs() < 1e-12, "{}", c.depth);
        assert!((c.point[0] - (2.3 - 2f64.sqrt())).abs() < 1e-9 && c.point[1].abs() < 1e-9);
    }
}
