use anyhow::Context;
use sim::{ShapeId, SimError, Vec2, Wall, World, WorldSettings};

use super::feeder::{Feeder, Rain};
use super::walls::{lay_grain_walls, lay_rough_walls};
use crate::scene::{Insertion, Scene, WallKind};

/// Wall indices in the world, in the order they are added.
pub const FLOOR: usize = 0;
pub const LEFT_WALL: usize = 1;
pub const RIGHT_WALL: usize = 2;

/// The world of a scene, before any grain: floor and side walls, the grain shape, the feeder.
pub struct Silo {
    pub world: World,
    pub shape: ShapeId,
    pub feeder: Feeder,
    pub width: f64,
    pub height: f64,
    /// Bounding radius of the grain outline (m).
    pub reach: f64,
    pub insertion: Insertion,
    /// Surface insertion: gap between free surface and band (m).
    pub gap: f64,
    /// Fixed insertion: height of the band's bottom (m).
    pub fixed_bottom: f64,
    /// The wall (FLOOR, LEFT_WALL, RIGHT_WALL) of each fixed wall grain; these are the first
    /// grains of the world. Empty for flat walls.
    pub wall_of: Vec<usize>,
}

impl Silo {
    pub fn new(scene: &Scene, seed: u64) -> anyhow::Result<Self> {
        let mm = 1e-3;
        let (width, height) = (scene.silo.width_mm * mm, scene.silo.height_mm * mm);
        let g = &scene.grains;
        let mut world = World::new(WorldSettings {
            law: scene.contact.law(),
            gravity: Vec2::new(0.0, -scene.contact.gravity_m_s2),
            time_step: Some(scene.time_step()?),
            wall_friction: scene.contact.wall_friction,
            plate_friction: scene.plates.friction_model(),
            ..WorldSettings::default()
        })
        .context("in the scene's [contact] or [run] section")?;
        let roughness = scene.silo.roughness_mm.map_or(g.width(), |r| r * mm);
        // Rough walls stand in front of flat ones at their deepest recess: at the rain's
        // impact speeds grains overlap by up to a millimetre, and one squeezed between two
        // wall grains would otherwise fall out of the silo.
        let behind = match scene.silo.walls {
            WallKind::Flat => Some(0.0),
            WallKind::Rough => Some(roughness),
            WallKind::Grains => None,
        };
        if let Some(d) = behind {
            world.add_wall(Wall::new(Vec2::new(0.0, -d), Vec2::new(0.0, 1.0)))?;
            world.add_wall(Wall::new(Vec2::new(-d, 0.0), Vec2::new(1.0, 0.0)))?;
            world.add_wall(Wall::new(Vec2::new(width + d, 0.0), Vec2::new(-1.0, 0.0)))?;
        }
        let outline = g.outline()?;
        let (reach, area) = (outline.bounding_radius(), outline.area());
        let shape = world
            .add_shape(outline, g.areal_density())
            .map_err(|e| match e {
                SimError::TimeStepTooLarge { .. } if scene.run.time_step_s.is_some() => {
                    anyhow::Error::new(e).context("field `run.time_step_s` is unstable")
                }
                SimError::TimeStepTooLarge { .. } => anyhow::Error::new(e)
                    .context("field `model.steps_per_collision`: the step it gives is unstable"),
                e => anyhow::Error::new(e).context("in the scene's [grains] section"),
            })?;
        world
            .set_sleep(scene.model.sleep_settings())
            .context("in the scene's [model] section")?;
        let wall_of = match scene.silo.walls {
            WallKind::Flat => Vec::new(),
            WallKind::Grains => {
                lay_grain_walls(&mut world, shape, [g.length(), g.width()], width, height)?
            }
            WallKind::Rough => lay_rough_walls(
                &mut world,
                shape,
                [g.length(), g.width(), g.rounding() * g.width()],
                [width, height],
                roughness,
                seed,
            )?,
        };
        let band_height = scene.feed.band_height_mm.map_or(8.0 * reach, |h| h * mm);
        let feeder = Feeder::new(
            Rain {
                silo_width: width,
                half: [g.length() / 2.0, g.width() / 2.0],
                grain_area: area,
                phi0: scene.feed.phi0,
                speed: scene.feed.speed_m_s,
                band_height,
                total: g.count,
                speed_spread: scene.feed.speed_spread,
                spin: scene.feed.spin_rad_s,
            },
            seed,
        );
        if let Err(largest) = feeder.check_feasible(seed) {
            anyhow::bail!(
                "field `feed.phi0` is {}: a band {:.1} mm high across the {:.1} mm silo cannot hold that many non-overlapping grains; the largest feasible phi0 is about {:.3}",
                scene.feed.phi0,
                2.0 * band_height / mm,
                width / mm,
                (largest * 1000.0).floor() / 1000.0
            );
        }
        let fixed_bottom = scene
            .feed
            .fixed_height_mm
            .map_or(height - band_height, |h| h * mm);
        Ok(Self {
            world,
            shape,
            feeder,
            width,
            height,
            reach,
            insertion: scene.feed.insertion,
            gap: scene.feed.gap_mm * mm,
            fixed_bottom,
            wall_of,
        })
    }
}
