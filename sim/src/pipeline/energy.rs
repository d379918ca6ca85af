/// Energies of a world (J; per unit thickness is not implied: masses are per grain).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Energies {
    /// Translational plus rotational kinetic energy of the mobile grains.
    pub kinetic: f64,
    /// Gravitational potential energy, zero at the origin.
    pub potential: f64,
    /// Elastic energy stored in the normal and tangential springs of the sub-contacts.
    pub elastic: f64,
}

impl Energies {
    pub fn total(&self) -> f64 {
        self.kinetic + self.potential + self.elastic
    }
}
