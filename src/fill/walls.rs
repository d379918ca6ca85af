//! The silo's floor and side walls built of fixed grains, as the paper built them (docs/model.md §2), and
//! the deposit's view of contacts: grain indices counted from the first deposit grain, and a
//! fixed grain's contact reported as one with its wall.

use std::ops::Range;

use std::f64::consts::FRAC_PI_2;

use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use sim::{Body, ContactRecord, ShapeId, Vec2, World};

use super::silo::{FLOOR, LEFT_WALL, RIGHT_WALL, Silo};

/// Lays fixed grains of `shape` (an outline `length` x `width`, long axis along x) edge to edge,
/// long side along the wall: the floor with its top face on y = 0, running under the side walls
/// to close the corners, and the side walls with their inner faces on x = 0 and x = `silo_width`
/// up to `silo_height`. Returns each fixed grain's wall, in the order of their world indices.
pub(crate) fn lay_grain_walls(
    world: &mut World,
    shape: ShapeId,
    [length, width]: [f64; 2],
    silo_width: f64,
    silo_height: f64,
) -> anyhow::Result<Vec<usize>> {
    let mut wall_of = Vec::new();
    let mut x = -width + length / 2.0;
    while x - length / 2.0 < silo_width + width {
        world.add_fixed_grain(shape, Vec2::new(x, -width / 2.0), 0.0)?;
        wall_of.push(FLOOR);
        x += length;
    }
    let upright = std::f64::consts::FRAC_PI_2;
    for (wall, x) in [
        (LEFT_WALL, -width / 2.0),
        (RIGHT_WALL, silo_width + width / 2.0),
    ] {
        let mut y = length / 2.0;
        while y - length / 2.0 < silo_height {
            world.add_fixed_grain(shape, Vec2::new(x, y), upright)?;
            wall_of.push(wall);
            y += length;
        }
    }
    Ok(wall_of)
}

/// Lays rough walls: fixed grains of `shape` (an outline `length` x `width` with rounding
/// `rounding`, long axis along x) at random orientations, one every half width along the floor
/// and each side wall, each at a random height or position along the wall (within half a
/// spacing of its slot) and set back behind the wall's line by a random depth, uniform in
/// [0, `roughness`]: the wall's innermost points touch the silo's outline (x = 0, x =
/// `silo_width`, y = 0), and the face a deposit meets is uneven on the scale of a grain and of
/// `roughness`. Consecutive grains overlap (two fixed grains never interact), so no grain
/// passes between them. Returns each fixed grain's wall, in the order of their world indices.
pub(crate) fn lay_rough_walls(
    world: &mut World,
    shape: ShapeId,
    [length, width, rounding]: [f64; 3],
    [silo_width, silo_height]: [f64; 2],
    roughness: f64,
    seed: u64,
) -> anyhow::Result<Vec<usize>> {
    // Its own stream: the walls do not shift the feeder's.
    let mut rng = ChaCha8Rng::seed_from_u64(seed ^ ROUGH_WALL_STREAM);
    let spacing = width / 2.0;
    // Half the extent of the outline along the axis at `angle` from its length: the core's
    // projection plus the rounding.
    let half_extent = |angle: f64| {
        let (core_l, core_w) = (length - 2.0 * rounding, width - 2.0 * rounding);
        0.5 * core_l * angle.cos().abs() + 0.5 * core_w * angle.sin().abs() + rounding
    };
    let mut wall_of = Vec::new();
    let mut lay = |world: &mut World, wall: usize, along: f64, rng: &mut ChaCha8Rng| {
        let angle = rng.random::<f64>() * std::f64::consts::PI;
        let along = along + (rng.random::<f64>() - 0.5) * spacing;
        let depth = rng.random::<f64>() * roughness;
        let position = match wall {
            FLOOR => Vec2::new(along, -depth - half_extent(angle + FRAC_PI_2)),
            LEFT_WALL => Vec2::new(-depth - half_extent(angle), along),
            _ => Vec2::new(silo_width + depth + half_extent(angle), along),
        };
        world.add_fixed_grain(shape, position, angle)?;
        wall_of.push(wall);
        anyhow::Ok(())
    };
    let reach = length.hypot(width) / 2.0;
    let mut x = -roughness - 2.0 * reach;
    while x < silo_width + roughness + 2.0 * reach {
        lay(world, FLOOR, x, &mut rng)?;
        x += spacing;
    }
    for wall in [LEFT_WALL, RIGHT_WALL] {
        let mut y = spacing / 2.0;
        while y - spacing / 2.0 < silo_height {
            lay(world, wall, y, &mut rng)?;
            y += spacing;
        }
    }
    Ok(wall_of)
}

/// Mixed into the run's seed for the rough walls' random stream.
const ROUGH_WALL_STREAM: u64 = 0x726f_7567_685f_7761;

impl Silo {
    /// World indices of the poured grains (the fixed wall grains come first).
    pub fn deposit_grains(&self) -> Range<usize> {
        self.wall_of.len()..self.world.len()
    }

    /// A contact as the deposit sees it: the deposit grain (index from the first poured grain),
    /// the other body (a deposit grain, or the silo wall FLOOR, LEFT_WALL or RIGHT_WALL, fixed
    /// grains included) and the force on the deposit grain.
    pub fn deposit_side(&self, c: &ContactRecord) -> (usize, Body, Vec2) {
        let first = self.wall_of.len();
        let wall = |g: usize| self.wall_of.get(g).copied();
        match c.second {
            Body::Wall(k) => (c.first - first, Body::Wall(k), c.force),
            Body::Grain(j) => match (wall(c.first), wall(j)) {
                (Some(k), _) => (j - first, Body::Wall(k), -c.force),
                (None, Some(k)) => (c.first - first, Body::Wall(k), c.force),
                (None, None) => (c.first - first, Body::Grain(j - first), c.force),
            },
        }
    }

    /// Force the deposit exerts on the floor, the left and the right wall (N), indexed by FLOOR,
    /// LEFT_WALL, RIGHT_WALL; the plates of a quasi-2D cell carry the rest
    /// ([`World::plate_load`](sim::World::plate_load)).
    pub fn wall_loads(&self) -> [Vec2; 3] {
        let mut loads = [Vec2::zeros(); 3];
        for (k, load) in loads.iter_mut().enumerate() {
            if k < self.world.walls().len() {
                *load = self.world.wall_load(k);
            }
        }
        if !self.wall_of.is_empty() {
            for c in self.world.contacts() {
                if let (_, Body::Wall(k), force) = self.deposit_side(&c) {
                    if !matches!(c.second, Body::Wall(_)) {
                        loads[k] -= force;
                    }
                }
            }
        }
        loads
    }

    /// Mass of the poured grains (kg).
    pub fn deposit_mass(&self) -> f64 {
        self.world.grains().mass[self.deposit_grains()].iter().sum()
    }
}
