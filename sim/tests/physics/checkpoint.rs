//! A world written mid-pour and read back continues with the same bits as the original.

use sim::{ContactLaw, GrainState, SleepSettings, Vec2, World};

use super::common::*;

/// 150 squares and rods dropped in a 90 mm box, colliding while the checkpoint is taken.
fn pour() -> World {
    let mut w = world(ContactLaw::default(), Vec2::new(0.0, -10.0), Some(1e-5));
    let width = 0.09;
    add_box(&mut w, width);
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

/// Runs `before` steps, writes the world and reads it back, runs both `after` more steps and
/// compares every byte of the two. Returns the world at the checkpoint and at the end.
fn continue_both(mut original: World, before: u64, after: u64) -> (World, World) {
    original.run(before).unwrap();
    let bytes = postcard::to_stdvec(&original).unwrap();
    let mut restored: World = postcard::from_bytes(&bytes).unwrap();
    let at_checkpoint = original.clone();
    original.run(after).unwrap();
    restored.run(after).unwrap();
    assert_eq!(restored.steps(), at_checkpoint.steps() + after);
    assert!(
        postcard::to_stdvec(&original).unwrap() == postcard::to_stdvec(&restored).unwrap(),
        "the restored world drifted from the original"
    );
    (at_checkpoint, restored)
}

#[test]
fn a_restored_world_continues_bit_for_bit() {
    let (at_checkpoint, end) = continue_both(pour(), 6_000, 4_000);
    // The pour is mid-collision: contacts with tangential history are part of what is restored.
    let contacts = at_checkpoint.contacts().count();
    assert!(contacts > 50, "{contacts} contacts");
    assert!(at_checkpoint.contacts().any(|c| c.displacement != 0.0));
    assert!(end.verlet_rebuilds() > at_checkpoint.verlet_rebuilds());
}

#[test]
fn a_restored_world_with_sleeping_grains_continues_bit_for_bit() {
    // A column of 10 squares asleep on the floor, and a grain falling onto it.
    let n = 10;
    let mut w = world(ContactLaw::default(), Vec2::new(0.0, -10.0), None);
    add_floor(&mut w);
    let square = add_square(&mut w);
    stack_at_equilibrium(&mut w, square, n, 10.0);
    w.set_sleep(Some(SleepSettings::default())).unwrap();
    w.run((0.05 / w.time_step()).ceil() as u64).unwrap();
    assert_eq!(w.sleeping(), n);
    let top = SIDE / 2.0 + n as f64 * SIDE;
    w.add_grain(square, moving(0.0, top + 2e-3, 0.0, 0.0, -1.0))
        .unwrap();
    // Written while the column sleeps; after it the impact wakes part of it, in both worlds.
    let (at_checkpoint, end) = continue_both(w, 100, 5_000);
    assert_eq!(at_checkpoint.sleeping(), n);
    assert!(end.sleeping() < n, "the impact woke no grain");
}
