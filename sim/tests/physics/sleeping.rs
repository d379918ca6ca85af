//! Sleeping grains: a deposit at rest falls asleep, a grain landing on it wakes what it
//! disturbs, and waking everything gives back the exact static balance.

use sim::{ContactLaw, SleepSettings, Vec2, World};

use super::common::*;

/// A column of `n` squares on the floor at its equilibrium, with sleep on.
fn column(n: usize) -> (World, usize) {
    let mut w = world(ContactLaw::default(), Vec2::new(0.0, -10.0), None);
    let floor = add_floor(&mut w);
    let square = add_square(&mut w);
    stack_at_equilibrium(&mut w, square, n, 10.0);
    w.set_sleep(Some(SleepSettings::default())).unwrap();
    (w, floor)
}

fn settle(w: &mut World, seconds: f64) {
    let steps = (seconds / w.time_step()).ceil() as u64;
    w.run(steps).unwrap();
}

#[test]
fn a_column_at_rest_falls_asleep_and_keeps_its_balance() {
    let n = 10;
    let (mut w, floor) = column(n);
    settle(&mut w, 0.05);
    assert_eq!(w.sleeping(), n, "every grain of a column at rest sleeps");
    let weight: f64 = (0..n).map(|i| mass(&w, i) * 10.0).sum();
    // Each sleeper holds at most wake_fraction of its weight out of balance.
    let s = SleepSettings::default();
    let floor_load = -w.wall_load(floor).y;
    assert!(
        (floor_load - weight).abs() < s.wake_fraction * weight,
        "floor {floor_load} N, weight {weight} N"
    );
    // Nothing moves while asleep.
    let before: Vec<Vec2> = (0..n).map(|i| w.grain(i).position).collect();
    settle(&mut w, 0.05);
    for (i, p) in before.iter().enumerate() {
        assert_eq!(w.grain(i).position, *p);
    }
}

#[test]
fn a_grain_landing_on_a_sleeping_column_wakes_it_and_the_balance_comes_back() {
    let n = 10;
    let (mut w, floor) = column(n);
    settle(&mut w, 0.05);
    assert_eq!(w.sleeping(), n);
    let square = w.shape_of(0);
    let top = SIDE / 2.0 + n as f64 * SIDE;
    let dropped = w
        .add_grain(square, moving(0.0, top + 2e-3, 0.0, 0.0, -1.0))
        .unwrap()
        .0;
    // Run until the dropped grain has hit the column.
    let mut woken = 0;
    for _ in 0..20_000 {
        w.step().unwrap();
        woken = woken.max(n - (0..n).filter(|&i| w.is_asleep(i)).count());
        if woken > 0 && w.grain(dropped).velocity.y > 0.0 {
            break;
        }
    }
    assert!(woken >= 1, "the impact woke no grain of the column");
    // Waking everything and relaxing gives the exact static balance (test 3's 0.1 %).
    w.set_sleep(None).unwrap();
    assert_eq!(w.sleeping(), 0);
    settle(&mut w, 0.5);
    // The column rings in its lowest mode for seconds (it barely stretches the dashpots):
    // compare the floor load averaged over many periods.
    let steps = (0.2 / w.time_step()).round() as u64;
    let mut mean = 0.0;
    for _ in 0..steps {
        w.step().unwrap();
        mean -= w.wall_load(floor).y / steps as f64;
    }
    let weight: f64 = (0..=n).map(|i| mass(&w, i) * 10.0).sum();
    assert!(
        ((mean - weight) / weight).abs() < 2e-3,
        "floor {mean} N on average, weight {weight} N"
    );
}

#[test]
fn sleeping_grains_give_identical_bits_on_one_and_two_threads() {
    let pour = || {
        let mut w = world(ContactLaw::default(), Vec2::new(0.0, -10.0), Some(1e-5));
        add_box(&mut w, 12.0 * SIDE);
        let square = add_square(&mut w);
        for k in 0..150 {
            let (row, col) = (k / 8, k % 8);
            let x = (col as f64 + 0.75) * 1.45 * SIDE + 1e-4 * row as f64;
            let state = moving(x, SIDE + row as f64 * 1.5 * SIDE, 0.1 * k as f64, 0.0, -0.5);
            w.add_grain(square, state).unwrap();
        }
        w.set_sleep(Some(SleepSettings::default())).unwrap();
        settle(&mut w, 0.6);
        w
    };
    let (one, two) = (on_threads(1, pour), on_threads(2, pour));
    // Most of the pile is at rest after 0.6 s.
    assert!(
        one.sleeping() > 75,
        "{} of 150 grains asleep",
        one.sleeping()
    );
    let bits = |w: &World| -> Vec<u64> {
        (0..w.len())
            .flat_map(|i| {
                let g = w.grain(i);
                [g.position.x, g.position.y, g.angle, g.velocity.x].map(f64::to_bits)
            })
            .collect()
    };
    assert_eq!(bits(&one), bits(&two));
}

#[test]
fn a_trembling_column_sleeps_by_drift_and_not_by_speed() {
    // A column 20 um per layer above its equilibrium rings at cm/s with forces of several
    // weights: the speed criterion never lets it sleep, the drift criterion does.
    let n = 10;
    let trembling = |settings: SleepSettings| {
        let (mut w, _) = ringing_column(n, 20e-6);
        w.set_sleep(Some(settings)).unwrap();
        settle(&mut w, 0.05);
        w.sleeping()
    };
    assert_eq!(trembling(SleepSettings::default()), 0);
    let by_drift = SleepSettings {
        speed: f64::INFINITY,
        force_fraction: f64::INFINITY,
        drift: 0.5e-3,
        quiet_time: 0.02,
        ..SleepSettings::default()
    };
    assert_eq!(trembling(by_drift), n);
    // A drift below the trembling's amplitude keeps them awake.
    let too_strict = SleepSettings {
        drift: 1e-7,
        ..by_drift
    };
    assert_eq!(trembling(too_strict), 0);
}

#[test]
fn a_sleeper_struck_hard_wakes_and_takes_the_momentum() {
    // A square asleep on the floor (by drift, as the fill scenes sleep); another slides into
    // it face on at 1 m/s. The first step of contact changes the sleeper's net force by
    // hundreds of its weights: it must wake and leave with what a head-on collision of equal
    // masses gives it, (1 + e) / 2 of the speed, the pair keeping the momentum brought in
    // (less the floor's friction, 0.4 g on each while it slides: 0.02 m/s in all over the
    // striker's 3 ms and the struck one's 2 ms, and what the sleeper was denied before it
    // woke, under 20 weights for a step: 0.012 m/s; measured: 0.980 kept). Never woken, it
    // would act as a wall: the other bounces back and the momentum is lost.
    let strike = |wake_fraction: f64| {
        let mut w = world(ContactLaw::default(), Vec2::new(0.0, -10.0), None);
        add_floor(&mut w);
        let square = add_square(&mut w);
        let y = SIDE / 2.0;
        w.add_grain(square, at(0.0, y, 0.0)).unwrap();
        w.set_sleep(Some(SleepSettings {
            speed: f64::INFINITY,
            force_fraction: f64::INFINITY,
            drift: 0.05e-3,
            quiet_time: 0.02,
            wake_fraction,
            ..SleepSettings::default()
        }))
        .unwrap();
        settle(&mut w, 0.05);
        assert_eq!(w.sleeping(), 1);
        let gap = 1e-3;
        let striker = w
            .add_grain(
                square,
                moving(-(SIDE + gap), w.grain(0).position.y, 0.0, 1.0, 0.0),
            )
            .unwrap()
            .0;
        settle(&mut w, 2e-3 + gap / 1.0);
        assert!(
            w.contacts().all(|c| matches!(c.second, sim::Body::Wall(_))),
            "the squares still touch"
        );
        (w.grain(0).velocity.x, w.grain(striker).velocity.x)
    };
    let (struck, striker) = strike(20.0);
    // Face on face the paper's grains bounce with e = 0.8-0.95 (collisions.rs): the struck
    // square leaves at (1 + e) / 2 = 0.9-0.975 m/s, less the friction above.
    assert!(
        struck > 0.89 && struck < 0.975,
        "struck square leaves at {struck} m/s, striker at {striker} m/s"
    );
    let kept = struck + striker;
    assert!(
        kept > 1.0 - 0.02 - 0.012 && kept < 1.0,
        "momentum per unit mass {kept} m/s after, 1 m/s before"
    );
    let (struck, striker) = strike(f64::INFINITY);
    assert_eq!(struck, 0.0, "never woken, the sleeper acts as a wall");
    assert!(striker < -0.5, "the striker bounces back: {striker} m/s");
}
