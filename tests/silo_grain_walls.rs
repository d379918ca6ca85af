//! Floor and side walls built of fixed grains, as the paper's silo (issue 3): the deposit stays
//! inside, and the contact table, where fixed grains appear as their walls (j = -1, -2, -3),
//! carries the deposit's weight.

use facets::deposit::{Partner, Wall, read_contacts_csv, read_deposit_csv};
use facets::fill::fill;
use facets::scene::parse_scene;

/// 60 squares in a 96 mm silo cut to 120 mm (the side walls need not reach the paper's 750 mm
/// for a deposit 40 mm high); time step and relaxation ratio as tests/silo_fill.rs explains.
const GRAIN_WALLS: &str = r#"
[silo]
width_mm = 96
height_mm = 120
walls = "grains"

[grains]
kind = "square"
count = 60

[feed]
phi0 = 0.1

[run]
time_step_s = 4e-6
relaxation_ratio = 1e-3
max_relaxation_time_s = 2
"#;

#[test]
fn grain_walls_hold_the_deposit_and_carry_its_weight() {
    let scene = parse_scene(GRAIN_WALLS, "grain-walls.toml").unwrap();
    let dir = tempfile::tempdir().unwrap();
    let r = fill(&scene, 7, dir.path(), &mut |_| {}).unwrap();
    assert!(r.relaxed, "not relaxed: {:?}", r.energies);
    assert_eq!(r.grains, 60);
    // 6.9 mm squares edge to edge: a floor 96 + 2 x 6.9 mm long, side walls 120 mm high.
    assert_eq!(r.wall_grains, 16 + 2 * 18);
    let deposit = read_deposit_csv(&dir.path().join("deposit.csv")).unwrap();
    assert_eq!(deposit.grains.len(), 60, "wall grains are not in the table");
    let contacts = read_contacts_csv(&dir.path().join("deposit.contacts.csv"), 60).unwrap();

    let r_c = 0.05 * 6.9e-3;
    let mass = 20.3 * (6.9e-3f64.powi(2) - (4.0 - std::f64::consts::PI) * r_c * r_c);
    let weight = 60.0 * mass * 10.0;
    let on_wall = |w: Wall| {
        contacts
            .iter()
            .filter(move |c| c.partner == Partner::Wall(w))
            .map(|c| c.force)
    };
    let carried: f64 = [Wall::Floor, Wall::Left, Wall::Right]
        .into_iter()
        .flat_map(on_wall)
        .map(|f| f[1])
        .sum();
    assert!(
        (carried - weight).abs() < 0.005 * weight,
        "the grain walls carry {carried} N of {weight} N"
    );
    // The floor does most of it, pushing up; the side walls push inwards.
    let floor: f64 = on_wall(Wall::Floor).map(|f| f[1]).sum();
    assert!(floor > 0.5 * weight, "floor {floor} N");
    assert!(on_wall(Wall::Left).all(|f| f[0] > -1e-9 * weight));
    assert!(on_wall(Wall::Right).all(|f| f[0] < 1e-9 * weight));
    // The engine's loads on the walls agree with the table.
    let pushed_down = -(r.floor_load_n[1] + r.left_wall_load_n[1] + r.right_wall_load_n[1]);
    assert!((pushed_down - carried).abs() < 1e-9 * weight);

    // No grain outside the silo, to within the rounding radius.
    for (k, g) in deposit.grains.iter().enumerate() {
        let half = (g.length / 2.0) * (g.theta.cos().abs() + g.theta.sin().abs());
        assert!(
            g.x - half > -r_c && g.x + half < 0.096 + r_c && g.y - half > -r_c,
            "grain {k} at ({}, {}) mm pokes out of the silo",
            g.x * 1e3,
            g.y * 1e3
        );
    }
}
