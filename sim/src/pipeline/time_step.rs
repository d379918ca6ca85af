use std::f64::consts::PI;

use crate::dynamics::ContactLaw;

/// Stability bound of the velocity-Verlet step for the stiffest contact on the lightest grain.
///
/// The stiffest contact is face on face: two sub-contacts in parallel. Each presses on an
/// effective mass 1 / (1/m + rho^2/I) per grain, rho the grain's reach (a sub-contact at the
/// tip of the outline also turns the grain), and both grains move. For a damped oscillator of
/// angular frequency omega and damping ratio zeta the explicit central-difference scheme is
/// stable for dt < 2 (sqrt(1 + zeta^2) - zeta) / omega.
pub fn critical_time_step(law: &ContactLaw, mass: f64, inertia: f64, reach: f64) -> f64 {
    let inverse_mass = 2.0 * (1.0 / mass + reach * reach / inertia);
    let omega = (2.0 * law.normal_stiffness * inverse_mass).sqrt();
    let zeta = law.normal_damping / omega;
    2.0 * ((1.0 + zeta * zeta).sqrt() - zeta) / omega
}

/// Duration of a binary collision through one sub-contact (linear spring-dashpot).
pub fn collision_time(law: &ContactLaw, reduced_mass: f64) -> f64 {
    let omega0_sq = law.normal_stiffness / reduced_mass;
    let beta = law.normal_damping / 2.0;
    PI / (omega0_sq - beta * beta).max(f64::MIN_POSITIVE).sqrt()
}

/// The default step: 1/400 of the collision of two of the lightest grains (1.7 us for the
/// nuts, 0.9 us for the short rods, near the paper's 1 us). The force has a kink where a
/// contact opens or closes, so the energy error per collision falls only as dt^2: at t_c/50 a
/// box of bouncing grains drifts by ~1e-3 over 100 collisions, at t_c/400 by < 1e-4 (see
/// `tests/physics/energy.rs`). Coarser steps are a measured speed-up, not the default.
pub fn default_time_step(law: &ContactLaw, lightest_mass: f64) -> f64 {
    collision_time(law, lightest_mass / 2.0) / STEPS_PER_COLLISION
}

/// Steps per binary collision of the default time step.
pub const STEPS_PER_COLLISION: f64 = 400.0;
