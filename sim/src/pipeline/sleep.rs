//! Sleeping grains: a grain at rest stops being integrated, and the contacts between two
//! sleeping (or fixed) grains keep the forces they had. A sleeping grain wakes as soon as the
//! contacts it has with awake grains change its net force.
//!
//! A scene models only what it needs: the deep part of a deposit that no longer moves costs
//! nothing per step but a flag test, while the grains that land and the ones they disturb are
//! integrated as usual. The price: a grain falls asleep with whatever net force it had (a
//! deposit hit by a rain of grains rings, and its grains are rarely in balance), and keeps it
//! until a neighbour changes it by `wake_fraction` of its weight; wake everything and relax
//! to remove it ([`World::wake_all`]).

use serde::{Deserialize, Serialize};

use super::world::World;
use crate::error::SimError;
use crate::math::Vec2;

/// When a grain falls asleep and when it wakes.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct SleepSettings {
    /// A grain may fall asleep when its centre and its farthest vertex move slower than this
    /// (m/s) ...
    pub speed: f64,
    /// ... and its net force is below this fraction of its weight (its net torque below this
    /// fraction of weight times arm; 1 excludes only grains in free flight) ...
    pub force_fraction: f64,
    /// ... and neither its centre nor its farthest vertex strays farther than this (m) from
    /// where they stood when the quiet stretch began ...
    pub drift: f64,
    /// ... without interruption for this long (s). Any criterion set to infinity is off: a
    /// deposit under a rain of grains trembles (cm/s, forces of several weights) while its
    /// grains stay within microns of their places, which only the drift criterion sees.
    pub quiet_time: f64,
    /// A sleeping grain touching an awake one wakes when its net force has changed since it
    /// fell asleep by more than this fraction of its weight (or its torque by this fraction of
    /// weight times arm).
    pub wake_fraction: f64,
    /// Sleep is decided every this many seconds (a Verlet rebuild decides it too).
    pub check_interval: f64,
}

impl Default for SleepSettings {
    fn default() -> Self {
        Self {
            speed: 2e-3,
            force_fraction: 1.0,
            drift: f64::INFINITY,
            quiet_time: 5e-3,
            wake_fraction: 0.2,
            check_interval: 1e-3,
        }
    }
}

impl SleepSettings {
    /// Whether a sleeper's net force (and torque), gathered now, has moved far enough from
    /// what it held when it fell asleep to wake it.
    pub(crate) fn disturbed(
        &self,
        force: Vec2,
        torque: f64,
        (asleep_force, asleep_torque): (Vec2, f64),
        weight: f64,
        arm: f64,
    ) -> bool {
        above((force - asleep_force).norm(), self.wake_fraction, weight)
            || above(
                (torque - asleep_torque).abs(),
                self.wake_fraction,
                weight * arm,
            )
    }

    /// Whether an awake grain meets every sleep criterion this step (`anchor`: where its quiet
    /// stretch began).
    #[allow(clippy::too_many_arguments)]
    pub(crate) fn quiet(
        &self,
        velocity: Vec2,
        angular_velocity: f64,
        force: Vec2,
        torque: f64,
        weight: f64,
        arm: f64,
        (x, theta): (Vec2, f64),
        anchor: (Vec2, f64),
    ) -> bool {
        velocity.norm() + arm * angular_velocity.abs() < self.speed
            && !above(force.norm(), self.force_fraction, weight)
            && !above(torque.abs(), self.force_fraction, weight * arm)
            && (x - anchor.0).norm() + arm * (theta - anchor.1).abs() < self.drift
    }

    pub fn validate(&self) -> Result<(), SimError> {
        // The criteria may be off (infinite).
        let criteria: [(&'static str, f64, &'static str); 4] = [
            ("sleep.speed", self.speed, "expected a speed >= 0 in m/s"),
            (
                "sleep.force_fraction",
                self.force_fraction,
                "expected a fraction of the weight >= 0",
            ),
            ("sleep.drift", self.drift, "expected a distance >= 0 in m"),
            (
                "sleep.wake_fraction",
                self.wake_fraction,
                "expected a fraction of the weight >= 0",
            ),
        ];
        for (field, value, expected) in criteria {
            if value.is_nan() || value < 0.0 {
                return Err(SimError::BadParameter {
                    field,
                    value,
                    expected,
                });
            }
        }
        let checks: [(&'static str, f64, &'static str); 2] = [
            (
                "sleep.quiet_time",
                self.quiet_time,
                "expected a time >= 0 in s",
            ),
            (
                "sleep.check_interval",
                self.check_interval,
                "expected a time >= 0 in s",
            ),
        ];
        for (field, value, expected) in checks {
            if !(value.is_finite() && value >= 0.0) {
                return Err(SimError::BadParameter {
                    field,
                    value,
                    expected,
                });
            }
        }
        Ok(())
    }
}

/// Per-grain sleep state.
#[derive(Clone, Debug, Default, Serialize, Deserialize)]
pub(crate) struct Dormancy {
    pub settings: Option<SleepSettings>,
    /// Mobile and integrated this step (false for fixed and sleeping grains).
    pub awake: Vec<bool>,
    /// Consecutive steps the grain has met the sleep criterion.
    pub quiet_steps: Vec<u32>,
    /// Sleeping and sharing a listed pair with an awake grain: its net force is watched.
    pub watched: Vec<bool>,
    /// Net force and torque when the grain fell asleep.
    pub asleep_load: Vec<(Vec2, f64)>,
    /// Position and angle at the start of the grain's quiet stretch.
    pub anchor: Vec<(Vec2, f64)>,
    /// A grain woke since the last Verlet rebuild: pairs between it and other sleeping grains
    /// were not searched, so the list must be rebuilt.
    pub woken: bool,
}

impl Dormancy {
    pub fn push(&mut self, mobile: bool, position: Vec2, angle: f64) {
        self.awake.push(mobile);
        self.quiet_steps.push(0);
        self.watched.push(false);
        self.asleep_load.push((Vec2::zeros(), 0.0));
        self.anchor.push((position, angle));
    }
}

impl World {
    /// Lets grains at rest fall asleep (`Some`), or wakes every grain and keeps them awake
    /// (`None`, the default).
    pub fn set_sleep(&mut self, settings: Option<SleepSettings>) -> Result<(), SimError> {
        if let Some(s) = &settings {
            s.validate()?;
        } else {
            self.wake_all();
        }
        self.dormancy.settings = settings;
        Ok(())
    }

    pub fn sleep_settings(&self) -> Option<SleepSettings> {
        self.dormancy.settings
    }

    /// Wakes every sleeping grain (their velocities are zero; their forces are recomputed at
    /// the next step).
    pub fn wake_all(&mut self) {
        let d = &mut self.dormancy;
        for i in 0..self.mobile.len() {
            if self.mobile[i] && !d.awake[i] {
                d.awake[i] = true;
                d.woken = true;
            }
            d.quiet_steps[i] = 0;
            d.watched[i] = false;
            d.anchor[i] = (self.grains.position[i], self.grains.angle[i]);
        }
    }

    /// Number of sleeping grains.
    pub fn sleeping(&self) -> usize {
        (0..self.mobile.len())
            .filter(|&i| self.mobile[i] && !self.dormancy.awake[i])
            .count()
    }

    pub fn is_asleep(&self, i: usize) -> bool {
        self.mobile[i] && !self.dormancy.awake[i]
    }

    /// Steps of quiet a grain needs before it may fall asleep.
    fn quiet_steps_needed(&self, s: &SleepSettings) -> u32 {
        ((s.quiet_time / self.dt).ceil() as u32).max(1)
    }

    /// Whether this step should decide who falls asleep.
    pub(crate) fn sleep_check_due(&self) -> bool {
        self.dormancy.settings.is_some_and(|s| {
            let every = ((s.check_interval / self.dt).round() as u64).max(1);
            self.steps % every == 0
        })
    }

    /// Puts the grains that have been quiet long enough to sleep: at rest, exactly.
    pub(crate) fn fall_asleep(&mut self) {
        let Some(s) = self.dormancy.settings else {
            return;
        };
        let needed = self.quiet_steps_needed(&s);
        let d = &mut self.dormancy;
        let g = &mut self.grains;
        for i in 0..self.mobile.len() {
            if d.awake[i] && d.quiet_steps[i] >= needed {
                d.awake[i] = false;
                d.quiet_steps[i] = 0;
                g.velocity[i] = Vec2::zeros();
                g.angular_velocity[i] = 0.0;
                d.asleep_load[i] = (g.force[i], g.torque[i]);
            }
        }
    }

    /// Marks the sleeping grains that share a listed pair with an awake grain.
    pub(crate) fn find_watched(&mut self) {
        let d = &mut self.dormancy;
        // With sleep off nothing is ever watched (turning it off wakes and clears everyone).
        if d.settings.is_none() {
            return;
        }
        d.watched.iter_mut().for_each(|w| *w = false);
        for &[i, j] in &self.verlet.pairs {
            let (i, j) = (i as usize, j as usize);
            if d.awake[i] != d.awake[j] {
                let sleeper = if d.awake[i] { j } else { i };
                if self.mobile[sleeper] {
                    d.watched[sleeper] = true;
                }
            }
        }
    }
}

/// Whether `value` exceeds `fraction` of `scale`. An infinite fraction is never exceeded, even
/// when the scale is zero (a weight without gravity), where the product would be NaN.
fn above(value: f64, fraction: f64, scale: f64) -> bool {
    fraction != f64::INFINITY && value > fraction * scale
}
