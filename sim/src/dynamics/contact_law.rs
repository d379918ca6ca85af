use serde::{Deserialize, Serialize};

use crate::error::SimError;

/// The per-sub-contact force law of docs/model.md §2: a linear spring-dashpot along the normal, never
/// attractive, and a tangential spring on the accumulated displacement with damping, capped
/// by Coulomb friction.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct ContactLaw {
    /// k_N (N/m).
    pub normal_stiffness: f64,
    /// k_T (N/m).
    pub tangential_stiffness: f64,
    /// gamma_N (1/s); the damping force is gamma_N times the reduced mass times v_n.
    pub normal_damping: f64,
    /// gamma_T (1/s).
    pub tangential_damping: f64,
    /// Coulomb friction coefficient mu.
    pub friction: f64,
}

impl Default for ContactLaw {
    /// The paper's parameters: k_N = 1e4 N/m, k_T = 0.1 k_N, gamma_T = 100 1/s,
    /// gamma_N = 3 gamma_T, mu = 0.4.
    fn default() -> Self {
        Self {
            normal_stiffness: 1e4,
            tangential_stiffness: 1e3,
            normal_damping: 300.0,
            tangential_damping: 100.0,
            friction: 0.4,
        }
    }
}

/// The result of the law for one sub-contact at one step.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SubContactForce {
    /// Normal force on the first body, along the normal (>= 0).
    pub normal: f64,
    /// Tangential force on the first body, along perp(normal).
    pub tangential: f64,
    /// Accumulated tangential displacement xi after this step.
    pub displacement: f64,
    /// True when the Coulomb cap holds the tangential force.
    pub sliding: bool,
}

impl ContactLaw {
    pub fn validate(&self) -> Result<(), SimError> {
        let fields = [
            ("normal_stiffness", self.normal_stiffness, true),
            ("tangential_stiffness", self.tangential_stiffness, false),
            ("normal_damping", self.normal_damping, false),
            ("tangential_damping", self.tangential_damping, false),
            ("friction", self.friction, false),
        ];
        for (field, value, strictly_positive) in fields {
            let ok = value.is_finite()
                && if strictly_positive {
                    value > 0.0
                } else {
                    value >= 0.0
                };
            if !ok {
                return Err(SimError::BadParameter {
                    field,
                    value,
                    expected: if strictly_positive {
                        "expected a finite positive number"
                    } else {
                        "expected a finite number >= 0"
                    },
                });
            }
        }
        Ok(())
    }

    /// Force of one sub-contact.
    ///
    /// `normal_velocity` and `tangential_velocity` are the velocity of the first body's contact
    /// point relative to the second's, along the normal (positive when separating) and along
    /// perp(normal). `displacement` is xi before this step.
    #[inline]
    pub fn force(
        &self,
        overlap: f64,
        normal_velocity: f64,
        tangential_velocity: f64,
        reduced_mass: f64,
        displacement: f64,
        dt: f64,
    ) -> SubContactForce {
        let normal = (self.normal_stiffness * overlap
            - self.normal_damping * reduced_mass * normal_velocity)
            .max(0.0);
        let xi = displacement + tangential_velocity * dt;
        let damping = self.tangential_damping * reduced_mass * tangential_velocity;
        let trial = -self.tangential_stiffness * xi - damping;
        let cap = self.friction * normal;
        if trial.abs() <= cap {
            SubContactForce {
                normal,
                tangential: trial,
                displacement: xi,
                sliding: false,
            }
        } else {
            // Sliding: the force sits on the cap, and the spring is reset so that spring and
            // damper together give exactly the cap; the force stays continuous when sliding stops.
            let tangential = cap.copysign(trial);
            let xi = if self.tangential_stiffness > 0.0 {
                -(tangential + damping) / self.tangential_stiffness
            } else {
                0.0
            };
            SubContactForce {
                normal,
                tangential,
                displacement: xi,
                sliding: true,
            }
        }
    }

    /// Elastic energy stored in one sub-contact.
    pub fn elastic_energy(&self, overlap: f64, displacement: f64) -> f64 {
        0.5 * self.normal_stiffness * overlap.max(0.0).powi(2)
            + 0.5 * self.tangential_stiffness * displacement * displacement
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn never_attractive_and_capped() {
        let law = ContactLaw::default();
        let f = law.force(1e-6, 10.0, 0.0, 1e-3, 0.0, 1e-6);
        assert_eq!(f.normal, 0.0);
        let f = law.force(1e-3, 0.0, 10.0, 1e-3, 0.0, 1e-3);
        assert!(f.sliding);
        assert!((f.tangential.abs() - 0.4 * 10.0).abs() < 1e-12);
        assert!(f.tangential < 0.0, "friction opposes sliding");
        let f = law.force(1e-3, 0.0, 0.0, 1e-3, 1e-4, 1e-6);
        assert!(!f.sliding && (f.tangential + 0.1).abs() < 1e-12);
    }

    #[test]
    fn bad_parameters_name_the_field() {
        let law = ContactLaw {
            friction: -0.1,
            ..ContactLaw::default()
        };
        assert!(
            law.validate()
                .unwrap_err()
                .to_string()
                .contains("`friction`")
        );
        let law = ContactLaw {
            normal_stiffness: f64::NAN,
            ..ContactLaw::default()
        };
        assert!(
            law.validate()
                .unwrap_err()
                .to_string()
                .contains("`normal_stiffness`")
        );
    }
}
