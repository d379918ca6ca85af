use serde::{Deserialize, Serialize};

use crate::math::Vec2;

/// A flat wall: the line through `point` with unit `normal` pointing into the region the
/// grains may occupy. One-sided, so a grain pushed through it is still pushed back.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct Wall {
    pub point: Vec2,
    pub normal: Vec2,
}

impl Wall {
    /// A wall through `point`; `normal` need not be unit length.
    pub fn new(point: Vec2, normal: Vec2) -> Self {
        Self {
            point,
            normal: normal.normalize(),
        }
    }

    /// Signed distance of a point from the wall (positive inside).
    pub fn distance(&self, p: Vec2) -> f64 {
        (p - self.point).dot(&self.normal)
    }
}
