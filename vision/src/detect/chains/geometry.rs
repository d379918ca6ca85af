//! Where poses lie: against a rod's axis (offsets along and across it, turns between axes,
//! shifts along it) and against the photograph's edges.

use crate::detect::model::Pose;
use crate::detect::plane::Plane;

/// Offsets of (x, y) from an axis through (ax, ay) at angle `phi`: along it and across it.
pub(super) fn offsets(ax: f64, ay: f64, phi: f64, x: f64, y: f64) -> (f64, f64) {
    let (s, c) = phi.sin_cos();
    let (dx, dy) = (x - ax, y - ay);
    // The axis points along (cos phi, -sin phi), as in `Pose`.
    (dx * c - dy * s, dx * s + dy * c)
}

/// The edge of the photograph nearest a centre: its direction (a rod's angle lying along
/// it), the unit normal pointing into the photograph, and the centre's distance from it
/// (negative outside).
#[derive(Clone, Copy)]
pub(super) struct Edge {
    pub(super) phi: f64,
    pub(super) inward: (f64, f64),
    pub(super) depth: f64,
}

pub(super) fn nearest_edge(p: Pose, plane: &Plane) -> Edge {
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
pub(super) fn centred_inside(p: Pose, plane: &Plane) -> bool {
    p.x >= 0.0 && p.y >= 0.0 && p.x < plane.width as f64 && p.y < plane.height as f64
}

/// Angle between two axes, modulo half a turn.
pub(super) fn turn(a: f64, b: f64) -> f64 {
    let d = (a - b).rem_euclid(std::f64::consts::PI);
    d.min(std::f64::consts::PI - d)
}

/// Shifts `pose` by `d` pixels along its axis.
pub(super) fn along(pose: Pose, d: f64) -> Pose {
    let (s, c) = pose.phi.sin_cos();
    Pose {
        x: pose.x + d * c,
        y: pose.y - d * s,
        phi: pose.phi,
    }
}
