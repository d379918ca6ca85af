//! Small 2D helpers on top of nalgebra's vectors.

pub type Vec2 = nalgebra::Vector2<f64>;

/// z-component of the cross product of two plane vectors.
#[inline]
pub fn cross(a: Vec2, b: Vec2) -> f64 {
    a.x * b.y - a.y * b.x
}

/// Cross product of a scalar angular velocity (along z) with a plane vector: w x r.
#[inline]
pub fn cross_scalar(w: f64, r: Vec2) -> Vec2 {
    Vec2::new(-w * r.y, w * r.x)
}

/// The vector turned by +90 degrees.
#[inline]
pub fn perp(a: Vec2) -> Vec2 {
    Vec2::new(-a.y, a.x)
}

/// Rotation by an angle given by its cosine and sine.
#[inline]
pub fn rotate(v: Vec2, cos: f64, sin: f64) -> Vec2 {
    Vec2::new(cos * v.x - sin * v.y, sin * v.x + cos * v.y)
}
