//! Rough walls of fixed grains (issue 53): laid behind the silo's outline at random
//! orientations and depths, they hold a deposit by their faces' slopes, where a flat wall can
//! only rub.

use facets::fill::{Silo, fill};
use facets::scene::parse_scene;

/// 70 squares in a 48 mm silo (seven across), cut to 150 mm; the time step and relaxation
/// ratio of tests/silo_grain_walls.rs.
fn scene(walls: &str, wall_friction: f64) -> String {
    format!(
        r#"
[silo]
width_mm = 48
height_mm = 150
walls = "{walls}"

[grains]
kind = "square"
count = 70

[feed]
phi0 = 0.1

[contact]
wall_friction = {wall_friction}

[run]
time_step_s = 4e-6
relaxation_ratio = 1e-3
max_relaxation_time_s = 2
"#
    )
}

/// The side walls' share of the deposit's weight, from the run record.
fn walls_share(walls: &str, wall_friction: f64, seed: u64) -> f64 {
    let scene = parse_scene(&scene(walls, wall_friction), "walls.toml").unwrap();
    let dir = tempfile::tempdir().unwrap();
    let r = fill(&scene, seed, dir.path(), &mut |_| {}).unwrap();
    assert!(r.relaxed, "{walls} walls, seed {seed}: not relaxed");
    -(r.left_wall_load_n[1] + r.right_wall_load_n[1]) / r.weight_n
}

#[test]
fn rough_walls_bear_weight_without_friction_where_flat_walls_cannot() {
    for seed in [1, 2] {
        // A frictionless flat wall pushes along its normal only: horizontally.
        let flat = walls_share("flat", 0.0, seed);
        assert!(flat.abs() < 1e-9, "seed {seed}: flat walls bear {flat}");
        // A frictionless rough wall bears weight on the faces of its grains that slope
        // upwards. In a silo seven grains wide the walls touch most of the deposit: they bear
        // a good part of its weight, of which a tenth is a conservative floor.
        let rough = walls_share("rough", 0.0, seed);
        assert!(rough > 0.1, "seed {seed}: rough walls bear only {rough}");
    }
}

#[test]
fn rough_walls_lie_behind_the_silo_outline_within_their_roughness() {
    let text =
        scene("rough", 0.4).replace("walls = \"rough\"", "walls = \"rough\"\nroughness_mm = 5");
    let scene = parse_scene(&text, "walls.toml").unwrap();
    let silo = Silo::new(&scene, 3).unwrap();
    let (side, r_c) = (6.9e-3, 0.05 * 6.9e-3);
    let grains = silo.world.grains();
    let mut nearest = [f64::INFINITY; 3];
    for (i, &wall) in silo.wall_of.iter().enumerate() {
        let (p, a) = (grains.position[i], grains.angle[i]);
        let half = (side / 2.0 - r_c) * (a.cos().abs() + a.sin().abs()) + r_c;
        // How far the grain's innermost point stands behind its wall's line.
        let depth = match wall {
            facets::fill::FLOOR => -(p.y + half),
            facets::fill::LEFT_WALL => -(p.x + half),
            _ => p.x - half - 0.048,
        };
        assert!(
            (-1e-12..=5e-3 + 1e-12).contains(&depth),
            "wall grain {i} of wall {wall} stands {depth} m behind the line"
        );
        nearest[wall] = nearest[wall].min(depth);
    }
    // Some grain of each wall reaches the line: the silo keeps its width.
    for (wall, d) in nearest.iter().enumerate() {
        assert!(
            *d < 0.5e-3,
            "wall {wall}: nearest grain {d} m behind the line"
        );
    }
    // Behind them, flat walls at the deepest recess keep a grain squeezed between two wall
    // grains at impact inside the silo.
    let walls = silo.world.walls();
    assert_eq!(walls.len(), 3);
    assert!((walls[facets::fill::FLOOR].distance(sim::Vec2::new(0.0, -5e-3))).abs() < 1e-15);
    assert!((walls[facets::fill::LEFT_WALL].distance(sim::Vec2::new(-5e-3, 0.0))).abs() < 1e-15);
    assert!((walls[facets::fill::RIGHT_WALL].distance(sim::Vec2::new(0.053, 0.0))).abs() < 1e-15);
    // A grain every half width along 150 mm of each side wall.
    let on_left = silo
        .wall_of
        .iter()
        .filter(|&&w| w == facets::fill::LEFT_WALL)
        .count();
    assert_eq!(on_left, (0.150f64 / (side / 2.0)).ceil() as usize);
}

#[test]
fn bad_wall_options_are_refused_by_name() {
    let flat_rough =
        scene("flat", 0.4).replace("walls = \"flat\"", "walls = \"flat\"\nroughness_mm = 2");
    let e = parse_scene(&flat_rough, "walls.toml")
        .unwrap_err()
        .to_string();
    assert!(e.contains("roughness_mm") && e.contains("rough"), "{e}");
    let e = parse_scene(&scene("rough", -0.1), "walls.toml")
        .unwrap_err()
        .to_string();
    assert!(e.contains("wall_friction"), "{e}");
    let negative =
        scene("rough", 0.4).replace("walls = \"rough\"", "walls = \"rough\"\nroughness_mm = -1");
    let e = parse_scene(&negative, "walls.toml")
        .unwrap_err()
        .to_string();
    assert!(e.contains("roughness_mm"), "{e}");
}
