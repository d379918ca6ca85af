//! Scenes shared by the physics tests.

use sim::{ContactLaw, GrainState, ShapeId, Spheropolygon, Vec2, Wall, World, WorldSettings};

/// The paper's nut: a 6.9 mm square, r = 0.35 mm (0.05 D), 20.3 kg/m^2.
pub const SIDE: f64 = 6.9e-3;
pub const SQUARE_RADIUS: f64 = 0.35e-3;
pub const NUT_DENSITY: f64 = 20.3;
/// Long rod 8.9 x 3 mm, r = 0.15 mm, 18.5 kg/m^2.
pub const ROD_LENGTH: f64 = 8.9e-3;
pub const ROD_WIDTH: f64 = 3e-3;
pub const ROD_RADIUS: f64 = 0.15e-3;
pub const ROD_DENSITY: f64 = 18.5;

pub fn square() -> Spheropolygon {
    Spheropolygon::rounded_rectangle(SIDE, SIDE, SQUARE_RADIUS).unwrap()
}

pub fn rod() -> Spheropolygon {
    Spheropolygon::rounded_rectangle(ROD_LENGTH, ROD_WIDTH, ROD_RADIUS).unwrap()
}

pub fn world(law: ContactLaw, gravity: Vec2, dt: Option<f64>) -> World {
    World::new(WorldSettings {
        law,
        gravity,
        time_step: dt,
        ..WorldSettings::default()
    })
    .unwrap()
}

/// A floor at y = 0 and side walls at x = 0 and x = `width`; returns the floor's index.
pub fn add_box(world: &mut World, width: f64) -> usize {
    let floor = add_floor(world);
    world
        .add_wall(Wall::new(Vec2::zeros(), Vec2::new(1.0, 0.0)))
        .unwrap();
    world
        .add_wall(Wall::new(Vec2::new(width, 0.0), Vec2::new(-1.0, 0.0)))
        .unwrap();
    floor
}

/// Runs `scene` on a pool of `threads` threads.
pub fn on_threads<T: Send>(threads: usize, scene: impl FnOnce() -> T + Send) -> T {
    rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .build()
        .unwrap()
        .install(scene)
}

/// The next number in [0, 1) of a 64-bit linear congruential stream (reproducible scenes
/// without a dependency).
pub fn uniform(seed: &mut u64) -> f64 {
    *seed = seed
        .wrapping_mul(6364136223846793005)
        .wrapping_add(1442695040888963407);
    (*seed >> 11) as f64 / (1u64 << 53) as f64
}

/// A floor at y = 0; returns its wall index.
pub fn add_floor(world: &mut World) -> usize {
    world
        .add_wall(Wall::new(Vec2::zeros(), Vec2::new(0.0, 1.0)))
        .unwrap()
}

pub fn add_square(world: &mut World) -> ShapeId {
    world.add_shape(square(), NUT_DENSITY).unwrap()
}

pub fn at(x: f64, y: f64, angle: f64) -> GrainState {
    GrainState::at_rest(Vec2::new(x, y), angle)
}

pub fn moving(x: f64, y: f64, angle: f64, vx: f64, vy: f64) -> GrainState {
    GrainState {
        velocity: Vec2::new(vx, vy),
        ..at(x, y, angle)
    }
}

pub fn mass(world: &World, i: usize) -> f64 {
    world.grains().mass[i]
}

/// A column of `n` squares on a floor at y = 0, each contact started at its equilibrium
/// overlap: the one under grain k carries (n - k) m g over two sub-contacts. (A column let to
/// settle by itself rings for seconds: its lowest mode barely stretches the dashpots.)
pub fn stack_at_equilibrium(w: &mut World, square: ShapeId, n: usize, gravity: f64) {
    let m = mass_of_square();
    let k = w.settings().law.normal_stiffness;
    let mut y = SIDE / 2.0 - n as f64 * m * gravity / (2.0 * k);
    for i in 0..n {
        w.add_grain(square, at(0.0, y, 0.0)).unwrap();
        let above = (n - i - 1) as f64;
        y += SIDE - above * m * gravity / (2.0 * k);
    }
}

/// A column of `n` squares on the floor, each grain `lift` (m) per layer above its
/// equilibrium (the top one n x lift), so that the column rings: it trembles at cm/s with
/// forces of several weights while its grains stay within microns of their places. Returns
/// the floor's wall index.
pub fn ringing_column(n: usize, lift: f64) -> (World, usize) {
    let mut w = world(ContactLaw::default(), Vec2::new(0.0, -10.0), None);
    let floor = add_floor(&mut w);
    let square = add_square(&mut w);
    stack_at_equilibrium(&mut w, square, n, 10.0);
    for i in 0..n {
        let mut g = w.grain(i);
        g.position.y += lift * (i + 1) as f64;
        w.set_grain(i, g);
    }
    (w, floor)
}

pub fn mass_of_square() -> f64 {
    square().mass_properties(NUT_DENSITY).unwrap().0
}
