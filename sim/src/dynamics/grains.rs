use serde::{Deserialize, Serialize};

use crate::math::Vec2;

/// The state of every grain, one array per quantity (so each pass reads only what it needs).
/// Fixed grains have zero inverse mass and inertia and are never moved.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct Grains {
    pub shape: Vec<u32>,
    pub position: Vec<Vec2>,
    pub angle: Vec<f64>,
    /// (cos, sin) of the angle, advanced with the angle by small rotations so the step needs
    /// no trigonometric call; it differs from the angle by rounding only (~1e-16 per step).
    pub rotation: Vec<(f64, f64)>,
    pub velocity: Vec<Vec2>,
    pub angular_velocity: Vec<f64>,
    pub force: Vec<Vec2>,
    pub torque: Vec<f64>,
    pub mass: Vec<f64>,
    pub inertia: Vec<f64>,
    pub inverse_mass: Vec<f64>,
    pub inverse_inertia: Vec<f64>,
}

impl Grains {
    pub fn len(&self) -> usize {
        self.position.len()
    }

    pub fn is_empty(&self) -> bool {
        self.position.is_empty()
    }

    pub fn is_fixed(&self, i: usize) -> bool {
        self.inverse_mass[i] == 0.0
    }
}
