//! The run's time step, resolved once: the scene's fixed step, or a fraction of the binary
//! collision of two of its grains. The engine receives it set, so its own default (for worlds
//! built without a scene) never comes into play for a silo.

use anyhow::Context;
use sim::Spheropolygon;

use super::{GrainSection, Scene};

impl GrainSection {
    /// The DEM outline: the L x D rectangle with corners rounded by the rounding fraction of D.
    pub fn outline(&self) -> anyhow::Result<Spheropolygon> {
        Spheropolygon::rounded_rectangle(
            self.length(),
            self.width(),
            self.rounding() * self.width(),
        )
        .context("in the scene's [grains] section")
    }
}

impl Scene {
    /// The time step (s): `[run] time_step_s` when set, else t_c / `[model]
    /// steps_per_collision`, t_c the binary collision of two grains of the scene through one
    /// sub-contact. Its stability is checked by the engine when the grain is registered.
    pub fn time_step(&self) -> anyhow::Result<f64> {
        if let Some(dt) = self.run.time_step_s {
            return Ok(dt);
        }
        let (mass, _) = self
            .grains
            .outline()?
            .mass_properties(self.grains.areal_density())
            .context("in the scene's [grains] section")?;
        let t_c = sim::collision_time(&self.contact.law(), mass / 2.0);
        Ok(t_c / self.model.steps_per_collision)
    }
}
