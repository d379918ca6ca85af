/// Energies of a world (J; per unit thickness is not implied: masses are per grain).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Energies {
    /// Translational plus rotational kinetic energy of the mobile grains.
    pub kinetic: f64,
    /// Gravitational potential energy, zero at the origin.
    pub potential: f64,
    /// Elastic energy stored in the normal and tangential springs of the sub-contacts.
    pub elastic: f64,
    /// Elastic energy that entered the account when sub-contacts appeared, less what left it
    /// when they vanished, evaluated at the configuration of the switch. A contact that opens
    /// and closes at zero overlap contributes nothing. The sub-contact model of docs/model.md §2 switches
    /// at finite overlap when the shared stretch of a face-on-face contact shrinks to a
    /// corner-on-corner contact (two sub-contacts become one), so `total - switching` is what
    /// the integrator conserves in an undamped, frictionless system.
    pub switching: f64,
}

impl Energies {
    pub fn total(&self) -> f64 {
        self.kinetic + self.potential + self.elastic
    }
}
