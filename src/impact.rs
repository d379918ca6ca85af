//! A single impact, the hardest case of the parameter set (docs/model.md §2): a grain dropped
//! corner-first at several m/s overlaps its target by more than r_i + r_j.

use sim::{Body, ContactLaw, GrainState, Vec2, Wall, World, WorldSettings};

use crate::grains::{DEFAULT_ROUNDING, GrainKind};

/// What the dropped grain hits.
#[derive(Clone, Copy, Debug, PartialEq, Eq, clap::ValueEnum)]
pub enum Target {
    /// A flat floor.
    Floor,
    /// A grain of the same kind resting flat on the floor.
    Grain,
}

#[derive(Clone, Copy, Debug)]
pub struct ImpactSpec {
    pub kind: GrainKind,
    pub target: Target,
    /// Downward speed at the first touch (m/s).
    pub speed: f64,
    /// Orientation of the dropped grain (rad); pi/4 puts a square's corner straight down.
    pub angle: f64,
    /// Time step (s); None for the engine's default.
    pub time_step: Option<f64>,
}

/// What was measured during the impact.
#[derive(Clone, Copy, Debug)]
pub struct ImpactReport {
    pub time_step: f64,
    /// Deepest overlap (m) and the same in units of r_i + r_j.
    pub deepest_overlap: f64,
    pub deepest_relative: f64,
    /// Time from first touch to separation (s).
    pub contact_duration: f64,
    /// Upward over downward speed of the dropped grain's centre.
    pub restitution: f64,
    /// Mechanical energy (kinetic + potential + elastic) before and after (J).
    pub energy_before: f64,
    pub energy_after: f64,
    /// Smallest normal force seen on any sub-contact (N): never negative.
    pub least_normal_force: f64,
    pub steps: u64,
}

pub fn drop_grain(spec: &ImpactSpec) -> anyhow::Result<ImpactReport> {
    let law = ContactLaw::default();
    let g = 10.0;
    let mut world = World::new(WorldSettings {
        law,
        gravity: Vec2::new(0.0, -g),
        time_step: spec.time_step,
        ..WorldSettings::default()
    })?;
    world.add_wall(Wall::new(Vec2::zeros(), Vec2::new(0.0, 1.0)))?;
    let outline = spec.kind.outline(DEFAULT_ROUNDING)?;
    let radius = outline.radius();
    let shape = world.add_shape(outline.clone(), spec.kind.areal_density())?;
    let mut target_top = 0.0;
    let mut reach = radius;
    if spec.target == Target::Grain {
        let (m, _) = outline.mass_properties(spec.kind.areal_density())?;
        let rest = m * g / (2.0 * law.normal_stiffness);
        let half = spec.kind.width() / 2.0;
        world.add_grain(shape, GrainState::at_rest(Vec2::new(0.0, half - rest), 0.0))?;
        target_top = spec.kind.width() - rest;
        reach = 2.0 * radius;
    }
    let (sin, cos) = spec.angle.sin_cos();
    let lowest = outline
        .vertices()
        .iter()
        .map(|v| sin * v.x + cos * v.y)
        .fold(f64::INFINITY, f64::min);
    // Start 0.2 mm above the target with the speed it should have there.
    let gap = 0.2e-3;
    let speed0 = (spec.speed * spec.speed - 2.0 * g * gap).max(0.0).sqrt();
    let start = GrainState {
        position: Vec2::new(0.0, target_top + gap + radius - lowest),
        angle: spec.angle,
        velocity: Vec2::new(0.0, -speed0),
        angular_velocity: 0.0,
    };
    let dropped = world.add_grain(shape, start)?.0;
    world.prime()?;
    let energy_before = world.energies().total();
    let (mut deepest, mut least_force) = (0.0f64, f64::INFINITY);
    let (mut touch_start, mut touched) = (0.0, false);
    let limit = (0.2 / world.time_step()) as u64;
    for _ in 0..limit {
        world.step()?;
        let mut touching = false;
        for c in world.contacts() {
            least_force = least_force.min(c.force.dot(&c.normal));
            if c.first == dropped || c.second == Body::Grain(dropped) {
                touching = true;
                deepest = deepest.max(c.overlap);
            }
        }
        if touching && !touched {
            touched = true;
            touch_start = world.time();
        }
        let v = world.grain(dropped).velocity;
        if touched && !touching && v.y > 0.0 {
            return Ok(ImpactReport {
                time_step: world.time_step(),
                deepest_overlap: deepest,
                deepest_relative: deepest / reach,
                contact_duration: world.time() - touch_start,
                restitution: v.y / spec.speed,
                energy_before,
                energy_after: world.energies().total(),
                least_normal_force: least_force,
                steps: world.steps(),
            });
        }
    }
    anyhow::bail!(
        "the dropped {} did not rebound within 0.2 s (deepest overlap {:.3} mm)",
        spec.kind,
        deepest * 1e3
    )
}
