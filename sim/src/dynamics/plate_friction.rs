use serde::{Deserialize, Serialize};

use super::ContactLaw;
use crate::error::SimError;
use crate::math::Vec2;

/// Friction of the glass plates in front of and behind a quasi-two-dimensional cell on a grain
/// sliding between them.
///
/// The experiment's grains are a little thinner than the gap between its plates: a grain
/// tilted or pressed out of plane by its neighbours rubs on them. A two-dimensional model has
/// no out-of-plane force to set that rubbing's normal load, so the load is a parameter. The
/// plates act on the grain's translation only; the torque of the rubbing is left out.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub enum PlateFriction {
    /// Dry friction: the contact law's tangential spring and damper against a plate at rest,
    /// anchored where the grain last stuck, capped at `coefficient` times a normal load of
    /// `load_fraction` of the grain's weight. It holds a grain at rest as dry plates do.
    Coulomb {
        coefficient: f64,
        load_fraction: f64,
    },
    /// A force `-rate m v` (1/s): plates wetted or a cell filled with a fluid.
    Viscous { rate: f64 },
}

impl PlateFriction {
    pub fn validate(&self) -> Result<(), SimError> {
        let fields: &[(&'static str, f64)] = match self {
            Self::Coulomb {
                coefficient,
                load_fraction,
            } => &[
                ("plate_friction.coefficient", *coefficient),
                ("plate_friction.load_fraction", *load_fraction),
            ],
            Self::Viscous { rate } => &[("plate_friction.rate", *rate)],
        };
        for &(field, value) in fields {
            if !(value.is_finite() && value >= 0.0) {
                return Err(SimError::BadParameter {
                    field,
                    value,
                    expected: "expected a finite number >= 0",
                });
            }
        }
        Ok(())
    }

    /// The plates' force on a grain of `mass` moving at `velocity`, and the grain's slip
    /// against the plates after a step of `dt` (the spring's stretch; 0 for the viscous law).
    #[inline]
    pub fn force(
        &self,
        law: &ContactLaw,
        mass: f64,
        gravity: f64,
        velocity: Vec2,
        slip: Vec2,
        dt: f64,
    ) -> (Vec2, Vec2) {
        match *self {
            Self::Viscous { rate } => (velocity * (-rate * mass), Vec2::zeros()),
            Self::Coulomb {
                coefficient,
                load_fraction,
            } => {
                let stretch = slip + velocity * dt;
                let damping = velocity * (law.tangential_damping * mass);
                let trial = -stretch * law.tangential_stiffness - damping;
                let cap = coefficient * load_fraction * mass * gravity;
                let size = trial.norm();
                if size <= cap {
                    (trial, stretch)
                } else {
                    // Sliding: on the cap, the spring set so that spring and damper give it
                    // exactly, as the contact law does.
                    let force = trial * (cap / size);
                    let stretch = if law.tangential_stiffness > 0.0 {
                        -(force + damping) / law.tangential_stiffness
                    } else {
                        Vec2::zeros()
                    };
                    (force, stretch)
                }
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn coulomb_holds_below_the_cap_and_slides_on_it() {
        let law = ContactLaw::default();
        let plates = PlateFriction::Coulomb {
            coefficient: 0.5,
            load_fraction: 1.0,
        };
        let (m, g) = (1e-3, 10.0);
        // At rest with a small stretch: the spring pulls back.
        let (f, s) = plates.force(&law, m, g, Vec2::zeros(), Vec2::new(1e-6, 0.0), 1e-5);
        assert_eq!(s, Vec2::new(1e-6, 0.0));
        assert!((f.x + law.tangential_stiffness * 1e-6).abs() < 1e-15);
        // Fast: the force sits on the cap, against the motion.
        let v = Vec2::new(0.0, -2.0);
        let (f, s) = plates.force(&law, m, g, v, Vec2::zeros(), 1e-5);
        assert!((f.norm() - 0.5 * m * g).abs() < 1e-15);
        assert!(f.y > 0.0 && f.x == 0.0);
        // The stretch left is the one that gives the cap with the damper.
        let back = -s * law.tangential_stiffness - v * (law.tangential_damping * m);
        assert!((back - f).norm() < 1e-15);
    }

    #[test]
    fn bad_values_name_the_field() {
        let plates = PlateFriction::Coulomb {
            coefficient: f64::NAN,
            load_fraction: 0.1,
        };
        let e = plates.validate().unwrap_err().to_string();
        assert!(e.contains("plate_friction.coefficient"), "{e}");
        let e = PlateFriction::Viscous { rate: -1.0 }
            .validate()
            .unwrap_err()
            .to_string();
        assert!(e.contains("plate_friction.rate"), "{e}");
    }
}
