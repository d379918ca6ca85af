//! A world written mid-pour and read back continues with the same bits as the original.

use sim::{ContactLaw, GrainState, Vec2, Wall, World};

use super::common::*;

/// 150 squares and rods dropped in a 90 mm box, colliding while the checkpoint is taken.
fn pour() -> World {
    let mut w = world(ContactLaw::default(), Vec2::new(0.0, -10.0), Some(1e-5));
    let width = 0.09;
    add_floor(&mut w);
    w.add_wall(Wall::new(Vec2::zeros(), Vec2::new(1.0, 0.0)))
        .unwrap();
    w.add_wall(Wall::new(Vec2::new(width, 0.0), Vec2::new(-1.0, 0.0)))
        .unwrap();
    let square = add_square(&mut w);
    let rod = w.add_shape(rod(), ROD_DENSITY).unwrap();
    let pitch = 0.0105;
    let columns = (width / pitch) as usize;
    for k in 0..150 {
        let (row, col) = (k / columns, k % columns);
        let shape = if k % 3 == 0 { rod } else { square };
        let state = GrainState {
            position: Vec2::new(pitch * (col as f64 + 0.5), pitch * (row as f64 + 0.5)),
            angle: 0.37 * k as f64,
            velocity: Vec2::new(0.3 * ((k % 7) as f64 - 3.0), -1.0),
            angular_velocity: 0.0,
        };
        w.add_grain(shape, state).unwrap();
    }
    w
}

#[test]
fn a_restored_world_continues_bit_for_bit() {
    let mut original = pour();
    original.run(6_000).unwrap();
    let bytes = postcard::to_stdvec(&original).unwrap();
    let mut restored: World = postcard::from_bytes(&bytes).unwrap();
    // The pour is mid-collision: contacts with tangential history are part of what is restored.
    assert!(
        original.contacts().count() > 50,
        "{} contacts",
        original.contacts().count()
    );
    assert!(original.contacts().any(|c| c.displacement != 0.0));
    original.run(4_000).unwrap();
    restored.run(4_000).unwrap();
    assert_eq!(restored.steps(), 10_000);
    assert!(
        postcard::to_stdvec(&original).unwrap() == postcard::to_stdvec(&restored).unwrap(),
        "the restored world drifted from the original"
    );
    assert!(original.verlet_rebuilds() > 1);
}
