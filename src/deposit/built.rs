//! A static deposit built by hand, with contact forces in exact balance: the reference the
//! stress analysis is tested on before simulated deposits exist, and the sample in
//! data-samples/deposits/.
//!
//! Square grains of side D stacked in `columns` x `rows` that fill a silo of width columns * D.
//! Each row is squeezed horizontally by the walls with a normal force that grows with depth and
//! saturates (a Janssen-like lateral load, K * m g * min(depth in rows, saturation)); the walls
//! carry part of the edge grains' weight by friction (mu_w times that normal force, below
//! Coulomb's mu = 0.4); every column carries the rest down to the floor. Every grain's forces
//! sum to zero with its weight.

use super::{Contact, Deposit, DepositMeta, FrameMm, Grain, Partner, Source, Wall};

/// Parameters of a stack of squares, built by [`SquareStack::build`].
#[derive(Clone, Copy, Debug)]
pub struct SquareStack {
    pub columns: usize,
    pub rows: usize,
    /// Side D (m).
    pub side: f64,
    /// Areal density (kg/m^2).
    pub areal_density: f64,
    pub gravity: f64,
    /// Lateral load coefficient K.
    pub lateral: f64,
    /// Depth (in rows) below which the lateral load stops growing.
    pub saturation_rows: f64,
    /// Wall friction coefficient in use (the fraction of the normal force carried as friction).
    pub wall_friction: f64,
}

impl Default for SquareStack {
    fn default() -> Self {
        SquareStack {
            columns: 24,
            rows: 40,
            side: 6.9e-3,
            areal_density: 20.3,
            gravity: 10.0,
            lateral: 0.5,
            saturation_rows: 8.0,
            wall_friction: 0.2,
        }
    }
}

impl SquareStack {
    pub fn grain_mass(&self) -> f64 {
        self.areal_density * self.side * self.side
    }

    pub fn silo_width(&self) -> f64 {
        self.columns as f64 * self.side
    }

    /// Wall normal force on the edge grains of row r (0 at the floor).
    pub fn wall_normal(&self, r: usize) -> f64 {
        let depth = (self.rows - r) as f64;
        self.lateral * self.grain_mass() * self.gravity * depth.min(self.saturation_rows)
    }

    /// The deposit, its contacts (grain index = row * columns + column) and its sidecar.
    pub fn build(&self, phi0: f64) -> (Deposit, Vec<Contact>, DepositMeta) {
        let d = self.side;
        let weight = self.grain_mass() * self.gravity;
        let index = |c: usize, r: usize| r * self.columns + c;
        let grains = (0..self.rows)
            .flat_map(|r| (0..self.columns).map(move |c| (c, r)))
            .map(|(c, r)| Grain::placed((c as f64 + 0.5) * d, (r as f64 + 0.5) * d, 0.0, d, d))
            .collect();
        let mut contacts = Vec::new();
        for r in 0..self.rows {
            let y = (r as f64 + 0.5) * d;
            let n = self.wall_normal(r);
            let friction = self.wall_friction * n;
            contacts.push(Contact {
                i: index(0, r),
                partner: Partner::Wall(Wall::Left),
                force: [n, friction],
                point: [0.0, y],
            });
            contacts.push(Contact {
                i: index(self.columns - 1, r),
                partner: Partner::Wall(Wall::Right),
                force: [-n, friction],
                point: [self.silo_width(), y],
            });
            // The row transmits the wall's squeeze from grain to grain.
            for c in 0..self.columns - 1 {
                contacts.push(Contact {
                    i: index(c, r),
                    partner: Partner::Grain(index(c + 1, r)),
                    force: [-n, 0.0],
                    point: [(c as f64 + 1.0) * d, y],
                });
            }
        }
        for c in 0..self.columns {
            let edge = c == 0 || c == self.columns - 1;
            // Load on the contact below row r: weight of the grains above it, less the wall
            // friction they receive.
            let carried = |r: usize| -> f64 {
                (r..self.rows)
                    .map(|k| {
                        weight
                            - if edge {
                                self.wall_friction * self.wall_normal(k)
                            } else {
                                0.0
                            }
                    })
                    .sum()
            };
            for r in 1..self.rows {
                contacts.push(Contact {
                    i: index(c, r),
                    partner: Partner::Grain(index(c, r - 1)),
                    force: [0.0, carried(r)],
                    point: [(c as f64 + 0.5) * d, r as f64 * d],
                });
            }
            contacts.push(Contact {
                i: index(c, 0),
                partner: Partner::Wall(Wall::Floor),
                force: [0.0, carried(0)],
                point: [(c as f64 + 0.5) * d, 0.0],
            });
        }
        let meta = DepositMeta {
            silo_width_mm: self.silo_width() * 1e3,
            phi0,
            frame_mm: Some(FrameMm {
                x_min: 0.0,
                x_max: self.silo_width() * 1e3,
                y_min: 0.0,
                y_max: self.rows as f64 * d * 1e3,
            }),
            areal_density_kg_m2: Some(self.areal_density),
            gravity_m_s2: Some(self.gravity),
            source: Source::Simulation,
        };
        (Deposit { grains }, contacts, meta)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_grain_is_in_force_balance_and_no_contact_pulls() {
        let stack = SquareStack::default();
        let (deposit, contacts, _) = stack.build(0.1);
        let weight = stack.grain_mass() * stack.gravity;
        let mut net = vec![[0.0, -weight]; deposit.grains.len()];
        for c in &contacts {
            net[c.i][0] += c.force[0];
            net[c.i][1] += c.force[1];
            if let Partner::Grain(j) = c.partner {
                net[j][0] -= c.force[0];
                net[j][1] -= c.force[1];
                // Compressive: the force on i points from j to i.
                let gi = deposit.grains[c.i];
                let gj = deposit.grains[j];
                let dot = c.force[0] * (gi.x - gj.x) + c.force[1] * (gi.y - gj.y);
                assert!(dot > 0.0);
            }
        }
        for f in net {
            assert!(
                f[0].abs() < 1e-12 && f[1].abs() < 1e-12 * weight.max(1.0),
                "{f:?}"
            );
        }
    }
}
