//! The side walls' and the floor's shares of a deposit's weight, read from its contact table.
//!
//! A row of the table is the force on grain `i` from its partner (docs/model.md §4), so a boundary
//! carries the grains by the upward (y) components of the forces it exerts on them. The
//! shares are of the total upward force of the three boundaries: in a deposit at rest that is
//! its weight (a run stops when they agree within `[run] load_balance`), and the shares then
//! add up to one whatever the mass model; `support_over_weight` says how well they agree.

use serde::{Deserialize, Serialize};

use crate::deposit::{Contact, Partner, Wall};

/// One deposit's contacts and its weight.
#[derive(Clone, Copy, Debug)]
pub struct LoadShareInput<'a> {
    pub contacts: &'a [Contact],
    /// The deposit's weight (N).
    pub weight_n: f64,
}

/// What each boundary carries, as a fraction of what the three carry together.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct LoadShares {
    pub floor: f64,
    pub left_wall: f64,
    pub right_wall: f64,
    /// Both side walls.
    pub walls: f64,
    /// Total upward force of the boundaries over the weight (1 at rest).
    pub support_over_weight: f64,
}

/// The shares of one deposit; refuses a table whose boundaries carry nothing upward (no
/// deposit at rest has that) and a weight that is not positive.
pub fn compute(input: &LoadShareInput) -> anyhow::Result<LoadShares> {
    anyhow::ensure!(
        input.weight_n.is_finite() && input.weight_n > 0.0,
        "the deposit's weight is {} N, expected a positive number",
        input.weight_n
    );
    let (mut floor, mut left, mut right) = (0.0, 0.0, 0.0);
    for c in input.contacts {
        match c.partner {
            Partner::Wall(Wall::Floor) => floor += c.force[1],
            Partner::Wall(Wall::Left) => left += c.force[1],
            Partner::Wall(Wall::Right) => right += c.force[1],
            Partner::Grain(_) => {}
        }
    }
    let support = floor + left + right;
    anyhow::ensure!(
        support > 0.0,
        "the floor and walls push the grains up by {support} N in all: the contact table holds no deposit at rest"
    );
    Ok(LoadShares {
        floor: floor / support,
        left_wall: left / support,
        right_wall: right / support,
        walls: (left + right) / support,
        support_over_weight: support / input.weight_n,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn contact(i: usize, partner: Partner, fx: f64, fy: f64) -> Contact {
        Contact {
            i,
            partner,
            force: [fx, fy],
            point: [0.0, 0.0],
        }
    }

    #[test]
    fn a_column_on_the_floor_puts_all_its_weight_there() {
        // Three grains of weight m g stacked: each carries those above, the floor all three.
        let mg = 0.01;
        let contacts = [
            contact(2, Partner::Grain(1), 0.0, mg),
            contact(1, Partner::Grain(0), 0.0, 2.0 * mg),
            contact(0, Partner::Wall(Wall::Floor), 0.0, 3.0 * mg),
        ];
        let s = compute(&LoadShareInput {
            contacts: &contacts,
            weight_n: 3.0 * mg,
        })
        .unwrap();
        assert_eq!(s.floor, 1.0);
        assert_eq!(s.walls, 0.0);
        assert!((s.support_over_weight - 1.0).abs() < 1e-12);
    }

    #[test]
    fn walls_carry_what_their_friction_holds_up() {
        // A grain wedged between the walls: each wall's friction holds 0.3 of the 1 N weight
        // (normal forces inward, 2 N, cancel), the floor the other 0.4.
        let contacts = [
            contact(0, Partner::Wall(Wall::Left), 2.0, 0.3),
            contact(0, Partner::Wall(Wall::Right), -2.0, 0.3),
            contact(0, Partner::Wall(Wall::Floor), 0.0, 0.4),
        ];
        let s = compute(&LoadShareInput {
            contacts: &contacts,
            weight_n: 1.0,
        })
        .unwrap();
        assert!((s.left_wall - 0.3).abs() < 1e-12 && (s.right_wall - 0.3).abs() < 1e-12);
        assert!((s.walls - 0.6).abs() < 1e-12 && (s.floor - 0.4).abs() < 1e-12);
        // A wall that pulls the grains down (friction against a sinking wall) counts negative.
        let contacts = [
            contact(0, Partner::Wall(Wall::Left), 2.0, -0.1),
            contact(0, Partner::Wall(Wall::Floor), 0.0, 1.1),
        ];
        let s = compute(&LoadShareInput {
            contacts: &contacts,
            weight_n: 1.0,
        })
        .unwrap();
        assert!((s.walls + 0.1).abs() < 1e-12 && (s.floor - 1.1).abs() < 1e-12);
    }

    #[test]
    fn a_table_without_support_or_a_bad_weight_is_refused() {
        let contacts = [contact(1, Partner::Grain(0), 0.0, 1.0)];
        let e = compute(&LoadShareInput {
            contacts: &contacts,
            weight_n: 1.0,
        })
        .unwrap_err();
        assert!(e.to_string().contains("no deposit at rest"), "{e}");
        let e = compute(&LoadShareInput {
            contacts: &contacts,
            weight_n: 0.0,
        })
        .unwrap_err();
        assert!(e.to_string().contains("weight"), "{e}");
    }
}
