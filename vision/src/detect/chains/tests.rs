//! The repairs on scenes of rods painted at known poses.

use super::doubtful::DOUBTFUL;
use super::*;
use crate::GrainShape;
use crate::detect::ridges::AxisSeed;
use std::ops::RangeBounds;

/// A photograph's darkness made of the coverage of rods (rod53 at 10 px/mm), with what a
/// repair needs to read it.
struct Scene {
    dark: Plane,
    fine: Bordered,
    coarse: Bordered,
    model: Model,
    coarse_model: Model,
}

const FACTOR: usize = 3;
const LENGTH: f64 = 49.0;
const WIDTH: f64 = 30.0;

impl Scene {
    fn of(rods: &[Pose]) -> Scene {
        Scene::sized(rods, 200, 180)
    }

    fn sized(rods: &[Pose], width: usize, height: usize) -> Scene {
        let shape = GrainShape::Rod {
            length: 4.9e-3,
            width: 3e-3,
        };
        let scale = 1e4;
        let model = Model::new(shape, scale);
        let mut dark = Plane::new(width, height, 0.0);
        let mut ones = Plane::new(width, height, 1.0);
        let mut scratch = Bordered::new(&ones);
        for &p in rods {
            model.paint(p, &ones.clone(), &mut dark, &mut ones, &mut scratch);
        }
        Scene {
            fine: Bordered::new(&dark),
            coarse: Bordered::new(&dark.downsample(FACTOR)),
            coarse_model: Model::with_softness(shape, scale / FACTOR as f64, 2.0),
            dark,
            model,
        }
    }

    fn cx(&self) -> Context<'_> {
        Context {
            dark: &self.dark,
            levels: Levels {
                fine: &self.fine,
                fine_free: &self.fine,
                coarse: &self.coarse,
                coarse_free: &self.coarse,
                fine_model: &self.model,
                coarse_model: &self.coarse_model,
                factor: FACTOR as f64,
                period: std::f64::consts::PI,
                finalist_margin: f64::INFINITY,
                finalists: fit::FINALISTS,
            },
            model: &self.model,
            min_confidence: 0.5,
            min_visible: 0.25,
            length: LENGTH,
            width: WIDTH,
        }
    }

    fn found(&self, pose: Pose, confidence: f64) -> Found {
        Found::at(pose, confidence, &self.model)
    }
}

/// What a repair made, to the bit: the number repaired, the rods (poses and agreements)
/// and the free darkness.
type Repaired = (usize, Vec<(Pose, u64)>, Vec<u32>);

/// The repair `on` (run on that many threads) mends both of two cases, `what`, to
/// `truth` on one thread, and gives the same on two and three.
fn assert_both_repaired_alike(
    scene: &Scene,
    truth: &[Pose],
    what: &str,
    on: impl Fn(usize) -> Repaired,
) {
    let one = on(1);
    assert_eq!(one.0, 2, "both {what} repaired");
    let rods: Vec<Found> = one.1.iter().map(|&(p, _)| scene.found(p, 0.9)).collect();
    assert_found(&rods, truth);
    for threads in [2, 3] {
        assert!(on(threads) == one, "{threads} threads differ from one");
    }
}

/// The rods a repair made on one thread (`one`, which `on(1)` gave) are as many as `truth`
/// and every true pose is found among them; two and three threads give the same, to the bit.
fn assert_all_found_alike(
    scene: &Scene,
    truth: &[Pose],
    one: &Repaired,
    on: impl Fn(usize) -> Repaired,
) {
    let rods: Vec<Found> = one.1.iter().map(|&(p, _)| scene.found(p, 0.9)).collect();
    assert_eq!(rods.len(), truth.len(), "{:?}", one.1);
    assert_found(&rods, truth);
    for threads in [2, 3] {
        assert!(on(threads) == *one, "{threads} threads differ from one");
    }
}

/// `repair` mends the rods `found` makes into `truth`: on one thread it keeps a number of
/// trials within `kept` and every true pose is found among as many rods; two and three
/// threads give the same, to the bit.
fn assert_repaired_alike(
    scene: &Scene,
    truth: &[Pose],
    kept: impl RangeBounds<usize> + std::fmt::Debug,
    found: impl Fn() -> Vec<Found>,
    repair: impl Fn(&mut Vec<Found>, &mut Maps, &Context) -> usize + Sync,
) {
    let cx = scene.cx();
    let on = |threads: usize| {
        on_threads(threads, &cx, found(), |found, maps| {
            repair(found, maps, &cx)
        })
    };
    let one = on(1);
    assert!(
        kept.contains(&one.0),
        "{} trials kept, not {kept:?}: {:?}",
        one.0,
        one.1
    );
    assert_all_found_alike(scene, truth, &one, on);
}

/// What a repair makes of `found` on `threads` threads, to the bit.
fn on_threads(
    threads: usize,
    cx: &Context,
    mut found: Vec<Found>,
    repair: impl FnOnce(&mut Vec<Found>, &mut Maps) -> usize + Send,
) -> Repaired {
    let mut maps = painted(&found, &[], cx);
    rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .build()
        .expect("thread pool")
        .install(|| {
            let repaired = repair(&mut found, &mut maps);
            let rods = found
                .iter()
                .map(|g| (g.pose, g.confidence.to_bits()))
                .collect();
            let free = maps.free.data.iter().map(|v| v.to_bits()).collect();
            (repaired, rods, free)
        })
}

/// The acceptance's offsets along a rod's axis.
fn along_axis() -> Vec<(f64, f64)> {
    (-3..=3)
        .flat_map(|k| [-0.5, 0.0, 0.5].map(|b| (k as f64 / 6.0 * (LENGTH - WIDTH), b * WIDTH)))
        .collect()
}

/// The across-highlights repair of the first of the rods `wrong` fitted on `scene`, with
/// the highlights `seeds`: how many it repaired, and the rods after it.
fn across_repaired(scene: &Scene, wrong: &[Pose], seeds: &[AxisSeed]) -> (usize, Vec<Found>) {
    let cx = scene.cx();
    let offsets = along_axis();
    let mut found: Vec<Found> = wrong.iter().map(|&p| scene.found(p, 0.9)).collect();
    let mut maps = painted(&found, &[], &cx);
    let repaired = repair_across_highlights(
        &mut found,
        &mut maps,
        &cx,
        0..1,
        seeds,
        &offsets,
        &offsets,
        4.5,
    );
    (repaired, found)
}

/// Every true pose has a rod within a pixel of it, turned from it by less than 0.03.
fn assert_found(found: &[Found], truth: &[Pose]) {
    assert_found_by(found, truth, |g, t| {
        (g.x - t.x).hypot(g.y - t.y) < 1.0 && turn(g.phi, t.phi) < 0.03
    });
}

/// Every true pose has a rod that `matches` it.
fn assert_found_by(found: &[Found], truth: &[Pose], matches: impl Fn(Pose, Pose) -> bool) {
    for &t in truth {
        assert!(
            found.iter().any(|g| matches(g.pose, t)),
            "{t:?} not among {:?}",
            found.iter().map(|g| g.pose).collect::<Vec<_>>()
        );
    }
}

/// A row of three rods end to end fitted shifted by half a length into the photograph's
/// edge, over the half of a fourth rod the edge cuts, leaving half a rod unexplained at
/// its other end: the row is put back and the cut rod added.
#[test]
fn a_row_shifted_into_the_edge_is_put_back_and_its_cut_rod_added() {
    let (repaired, found, truth) = row_repaired(&[0.0, 1.0, 2.0, 3.0], &[0.5, 1.5, 2.5]);
    assert_eq!(repaired, 1);
    assert_eq!(found.len(), 4);
    assert_row_found(&found, &truth);
}

/// Rods at `truth` and a row fitted at `fitted` (both in lengths along y = 90 px, from the
/// photograph's left edge), after the row-shift repair: the rows repaired, the rods, and
/// the true poses.
fn row_repaired(truth: &[f64], fitted: &[f64]) -> (usize, Vec<Found>, Vec<Pose>) {
    let at = |k: f64| Pose {
        x: k * LENGTH,
        y: 90.0,
        phi: 0.0,
    };
    let truth: Vec<Pose> = truth.iter().map(|&k| at(k)).collect();
    let scene = Scene::of(&truth);
    let cx = scene.cx();
    let mut found: Vec<Found> = fitted.iter().map(|&k| scene.found(at(k), 0.9)).collect();
    let mut maps = painted(&found, &[], &cx);
    let repaired = repair(&mut found, &mut maps, &cx, 0..fitted.len());
    (repaired, found, truth)
}

/// The rods fitted at `wrong` in `scene`, after the row repair over all of them: the rows
/// repaired and the rods.
fn rows_repaired(scene: &Scene, wrong: &[Pose]) -> (usize, Vec<Found>) {
    let cx = scene.cx();
    let mut found: Vec<Found> = wrong.iter().map(|&p| scene.found(p, 0.9)).collect();
    let mut maps = painted(&found, &[], &cx);
    let repaired = repair(&mut found, &mut maps, &cx, 0..wrong.len());
    (repaired, found)
}

/// Every true pose of a row has a rod along it. Refined one after another, each rod of a
/// row touching end to end is pushed a pixel or so along by the one before it: a tenth of
/// a length against the half undone.
fn assert_row_found(found: &[Found], truth: &[Pose]) {
    assert_found_by(found, truth, |g, t| {
        (g.x - t.x).abs() < 0.1 * LENGTH && (g.y - t.y).abs() < 1.0 && turn(g.phi, t.phi) < 0.03
    });
}

/// A rod the photograph's left edge cuts, fitted where it is, with a rod lying across its
/// inner end that no fit has found yet: the dark beyond its end is that rod's side, not
/// the stub of a row shifted off it, so the cut rod is not slid in over it (with a cut rod
/// added in its place, as lab rod53 at 10 px/mm did on seeds 26 and 27).
#[test]
fn a_cut_rod_is_not_slid_in_over_a_rod_across_its_end() {
    let cut = Pose {
        x: 0.3 * LENGTH,
        y: 90.0,
        phi: 0.0,
    };
    let across = Pose {
        x: 0.8 * LENGTH + 0.5 * WIDTH,
        y: 90.0,
        phi: std::f64::consts::FRAC_PI_2,
    };
    let scene = Scene::of(&[cut, across]);
    let cx = scene.cx();
    let mut found = vec![scene.found(cut, 0.9)];
    let mut maps = painted(&found, &[], &cx);
    let repaired = repair(&mut found, &mut maps, &cx, 0..1);
    assert_eq!(repaired, 0);
    assert_eq!(found.len(), 1);
    assert_eq!(found[0].pose, cut);
}

/// A row of three rods fitted shifted by nearly half a length out of the photograph's
/// edge, its first rod reaching beyond it: the row is put back, and no rod is added in a
/// room that lies outside the photograph (one there has nothing to fit and, before, failed
/// the whole repair).
#[test]
fn a_row_shifted_out_of_the_edge_is_put_back_without_a_rod_outside() {
    let (repaired, found, truth) = row_repaired(&[0.5, 1.5, 2.5], &[0.05, 1.05, 2.05]);
    assert_eq!(repaired, 1);
    assert_eq!(found.len(), 3, "no rod added outside the photograph");
    assert_row_found(&found, &truth);
}

/// A row of four rods end to end whose second was fitted standing across the row against
/// the first, the third shifted into the rest of its place: the row is shifted back onto
/// the stub the third leaves, and the standing rod refitted along the row in the room.
#[test]
fn a_rod_standing_across_a_row_shifted_onto_it_is_refitted_along_the_row() {
    let at = |x: f64, phi: f64| Pose { x, y: 90.0, phi };
    let truth: Vec<Pose> = (0..4).map(|k| at(30.0 + LENGTH * k as f64, 0.0)).collect();
    let scene = Scene::sized(&truth, 230, 180);
    let standing = at(30.0 + 0.5 * (LENGTH + WIDTH), std::f64::consts::FRAC_PI_2);
    let shifted = at(truth[2].x - (LENGTH - WIDTH), 0.0);
    let wrong = [truth[0], standing, shifted, truth[3]];
    let (repaired, found) = rows_repaired(&scene, &wrong);
    assert_eq!(repaired, 1);
    assert_eq!(found.len(), 4);
    assert_row_found(&found, &truth);
}

/// A row runs on through a rod turned 7 degrees from it (as the edge's cut rods are
/// fitted) and stops at one turned 10, or one off its axis by half a width.
#[test]
fn a_row_runs_through_a_slightly_turned_rod_and_stops_at_a_turned_or_offset_one() {
    let scene = Scene::of(&[]);
    let rod = |x: f64, y: f64, deg: f64| {
        scene.found(
            Pose {
                x,
                y,
                phi: f64::to_radians(deg),
            },
            0.9,
        )
    };
    let row = |third: Found| {
        let found = [rod(20.0, 90.0, 0.0), rod(20.0 + LENGTH, 90.0, 0.0), third];
        chain(&found, 0, 1.0, LENGTH, WIDTH)
    };
    let x3 = 20.0 + 2.0 * LENGTH;
    assert_eq!(row(rod(x3, 90.0, 7.0)), [0, 1, 2]);
    assert_eq!(row(rod(x3, 90.0, -7.0)), [0, 1, 2]);
    assert_eq!(row(rod(x3, 90.0, 10.0)), [0, 1]);
    assert_eq!(row(rod(x3, 90.0 + 0.5 * WIDTH, 0.0)), [0, 1]);
}

/// A row runs on through rods fitted the other way round (a rod is the same turned by a
/// half turn), whichever way round its first rod was fitted.
#[test]
fn a_row_runs_on_through_rods_fitted_the_other_way_round() {
    let scene = Scene::of(&[]);
    let rod = |k: f64, deg: f64| {
        scene.found(
            Pose {
                x: 20.0 + k * LENGTH,
                y: 90.0,
                phi: f64::to_radians(deg),
            },
            0.9,
        )
    };
    let found = [
        rod(0.0, 180.0),
        rod(1.0, 0.0),
        rod(2.0, 181.0),
        rod(3.0, 359.0),
    ];
    assert_eq!(chain(&found, 0, -1.0, LENGTH, WIDTH), [0, 1, 2, 3]);
    assert_eq!(chain(&found, 3, -1.0, LENGTH, WIDTH), [3, 2, 1, 0]);
}

/// A row of four rods end to end (fitted either way round) with a rod standing on the side
/// of its last one: the standing rod fitted pushed down into the row's end, and the row as
/// three rods shifted by a third of a length (lab rod3 at 10 px/mm, seed 72 ordered). The
/// row is put back with its fourth rod, and the standing rod stands again where it is.
#[test]
fn a_row_ending_under_a_rod_standing_beside_it_is_put_back() {
    let at = |x: f64, phi: f64| Pose { x, y: 90.0, phi };
    let half_turn = std::f64::consts::PI;
    let row: Vec<Pose> = (0..4)
        .map(|k| at(50.0 + LENGTH * k as f64, half_turn * (k % 2) as f64))
        .collect();
    let standing = Pose {
        x: 200.0,
        y: 90.0 - 0.5 * (WIDTH + LENGTH),
        phi: std::f64::consts::FRAC_PI_2,
    };
    let truth: Vec<Pose> = row.iter().copied().chain([standing]).collect();
    let scene = Scene::sized(&truth, 260, 180);
    let shift = 18.0;
    let wrong: Vec<Pose> = row[..3]
        .iter()
        .map(|p| Pose {
            x: p.x + shift,
            phi: p.phi + half_turn,
            ..*p
        })
        .chain([Pose {
            y: standing.y + 16.0,
            ..standing
        }])
        .collect();
    let (repaired, found) = rows_repaired(&scene, &wrong);
    assert_eq!(repaired, 1);
    assert_eq!(found.len(), 5);
    assert_row_found(&found, &row);
    assert_found_by(&found, &[standing], |g, t| {
        (g.x - t.x).hypot(g.y - t.y) < 2.0 && turn(g.phi, t.phi) < 0.03
    });
}

/// Two short rods face to face, fitted as one rod turned by a right angle across them
/// (the rod53 error), are refitted as the two rods.
#[test]
fn a_rod_across_two_is_refitted_as_the_two() {
    let phi: f64 = 0.3;
    let (s, c) = phi.sin_cos();
    let truth = [-0.5, 0.5].map(|k| Pose {
        x: 100.0 + k * WIDTH * s,
        y: 90.0 + k * WIDTH * c,
        phi,
    });
    let scene = Scene::of(&truth);
    let cx = scene.cx();
    let wrong = Pose {
        x: 100.0,
        y: 90.0,
        phi: phi + std::f64::consts::FRAC_PI_2,
    };
    let mut found = vec![scene.found(wrong, 0.9)];
    let mut maps = painted(&found, &[], &cx);
    assert_eq!(
        repair_turned(&mut found, &mut maps, &cx, &along_axis(), 4.5),
        1
    );
    assert_eq!(found.len(), 2);
    assert_found(&found, &truth);
}

/// Three rods lying flat, face to face in a column, the middle one fitted turned by a right
/// angle across its nearer end and the ends of the two beside it (lab rod53 at 6 px/mm,
/// seed 1, at the left edge): what it leaves unexplained lies to one side of it. It is
/// refitted as the one rod, not two; the same on one, two and three threads.
#[test]
fn a_rod_across_one_and_the_ends_of_two_is_refitted_as_the_one() {
    let truth =
        [(100.0, 60.0), (100.0, 90.0), (100.0, 120.0)].map(|(x, y)| Pose { x, y, phi: 0.0 });
    let scene = Scene::of(&truth);
    let offsets = along_axis();
    // Its axis (L - W) / 2 off the middle rod's centre: the block centred on it holds less
    // than a third of a rod of what it leaves, the block moved across it more.
    let turned = Pose {
        x: 100.0 - 0.5 * (LENGTH - WIDTH),
        y: 90.0,
        phi: std::f64::consts::FRAC_PI_2,
    };
    assert_repaired_alike(
        &scene,
        &truth,
        1..=1,
        || {
            vec![
                scene.found(truth[0], 0.9),
                scene.found(turned, 0.9),
                scene.found(truth[2], 0.9),
            ]
        },
        |found, maps, cx| repair_turned(found, maps, cx, &offsets, 4.5),
    );
}

/// A rod fitted turned by 20 degrees, with the low agreement such a fit has, is fitted
/// again at its true angle; a rod at its true pose, however low its stated agreement,
/// is left where it is.
#[test]
fn a_doubtful_rod_is_turned_to_its_angle_and_a_right_one_kept() {
    let truth = [
        Pose {
            x: 70.0,
            y: 90.0,
            phi: 0.2,
        },
        Pose {
            x: 140.0,
            y: 80.0,
            phi: 1.2,
        },
    ];
    let scene = Scene::of(&truth);
    let cx = scene.cx();
    let turned = Pose {
        phi: truth[0].phi + 20f64.to_radians(),
        ..truth[0]
    };
    let mut found = vec![scene.found(turned, 0.6), scene.found(truth[1], 0.6)];
    let mut maps = painted(&found, &[], &cx);
    let offsets: Vec<(f64, f64)> = [-0.5, 0.0, 0.5]
        .iter()
        .flat_map(|&a| [-0.25, 0.0, 0.25].map(move |b| (a * LENGTH, b * WIDTH)))
        .collect();
    assert_eq!(
        repair_doubtful(&mut found, &mut maps, &cx, &offsets, 4.5),
        1
    );
    assert_found(&found, &truth);
    assert_eq!(found[1].pose, truth[1], "the right rod was moved");
    assert!(found[0].confidence > DOUBTFUL, "{}", found[0].confidence);
}

/// Two doubtful rods, each fitted turned by 20 degrees, the second standing at the end of
/// the first, a third rod at the second one's other end: the second one's trial, worked out
/// ahead beside the first as it was, reads where the first is repaired and is redone, so
/// several threads give what one gives, to the bit (rods and maps).
#[test]
fn doubtful_repairs_do_not_depend_on_the_thread_count() {
    let truth = [(70.0, 90.0, 0.2), (115.0, 88.0, 1.77), (115.0, 130.0, 0.0)]
        .map(|(x, y, phi)| Pose { x, y, phi });
    let scene = Scene::of(&truth);
    let cx = scene.cx();
    let offsets: Vec<(f64, f64)> = [-0.5, 0.0, 0.5]
        .iter()
        .flat_map(|&a| [-0.25, 0.0, 0.25].map(move |b| (a * LENGTH, b * WIDTH)))
        .collect();
    let on = |threads: usize| {
        let mut found: Vec<Found> = truth[..2]
            .iter()
            .map(|&t| {
                let turned = Pose {
                    phi: t.phi + 20f64.to_radians(),
                    ..t
                };
                scene.found(turned, 0.6)
            })
            .collect();
        found.push(scene.found(truth[2], 0.9));
        on_threads(threads, &cx, found, |found, maps| {
            repair_doubtful(found, maps, &cx, &offsets, 4.5)
        })
    };
    assert_both_repaired_alike(&scene, &truth, "rods", on);
}

/// Three rods face to face beside a fourth, fitted as two rods turned the same way across
/// them (the rod3 error: the one with the low agreement cannot turn back while the other
/// holds its place), are refitted together as the three; the four at their true poses,
/// one with a low stated agreement, are left as they are.
#[test]
fn two_rods_turned_across_three_are_refitted_as_the_three() {
    let offsets = along_axis();
    let truth = [(100.0, 60.0), (100.0, 90.0), (100.0, 120.0), (155.0, 90.0)].map(|(x, y)| Pose {
        x,
        y,
        phi: 0.0,
    });
    let scene = Scene::of(&truth);
    let cx = scene.cx();
    // Side by side, turned by 62 degrees, across the three.
    let phi = 62f64.to_radians();
    let (s, c) = phi.sin_cos();
    let wrong = [(-0.5, 0.6), (0.5, 0.94)].map(|(k, confidence)| {
        let (x, y) = (100.0 + k * WIDTH * s, 90.0 + k * WIDTH * c);
        scene.found(Pose { x, y, phi }, confidence)
    });
    let mut found = Vec::from(wrong);
    found.push(scene.found(truth[3], 0.9));
    let mut maps = painted(&found, &[], &cx);
    assert_eq!(
        repair_doubtful(&mut found, &mut maps, &cx, &offsets, 4.5),
        1
    );
    assert_eq!(found.len(), 4);
    assert_found(&found, &truth);

    let mut found: Vec<Found> = truth
        .iter()
        .zip([0.9, 0.6, 0.9, 0.9])
        .map(|(&p, confidence)| scene.found(p, confidence))
        .collect();
    let mut maps = painted(&found, &[], &cx);
    repair_doubtful(&mut found, &mut maps, &cx, &offsets, 4.5);
    assert_eq!(found.len(), 4);
    for (g, t) in found.iter().zip(&truth) {
        assert!((g.pose.x - t.x).hypot(g.pose.y - t.y) < 0.5 && turn(g.pose.phi, t.phi) < 0.01);
    }
}

/// Three rods face to face (`n` of them side by side, `dx` along their axis), the outer
/// two fitted shifted a quarter width onto the middle one, which is missed: its seeds
/// found the outer ones again, and what is left of it is too small for a fit of its own.
fn eaten_into(dx: f64) -> ([Pose; 3], [Pose; 2]) {
    let truth = [60.0, 90.0, 120.0].map(|y| Pose {
        x: 70.0 + dx,
        y,
        phi: 0.0,
    });
    let shift = 0.27 * WIDTH;
    let wrong = [(0, shift), (2, -shift)].map(|(k, d)| Pose {
        y: truth[k].y + d,
        ..truth[k]
    });
    (truth, wrong)
}

/// The middle rod of [`eaten_into`] is found at the spot of dark area its neighbours
/// leave unexplained, and they go back to their places; rods at their true poses are left
/// as they are.
#[test]
fn a_rod_its_neighbours_ate_into_is_found_at_what_they_leave() {
    let (truth, wrong) = eaten_into(0.0);
    let scene = Scene::of(&truth);
    let cx = scene.cx();
    let offsets = along_axis();
    let mut found: Vec<Found> = wrong.iter().map(|&p| scene.found(p, 0.9)).collect();
    let mut maps = painted(&found, &[], &cx);
    assert_eq!(
        repair_unexplained(&mut found, &mut maps, &cx, &offsets, 4.5),
        1
    );
    assert_eq!(found.len(), 3);
    assert_found(&found, &truth);

    let mut found: Vec<Found> = truth.iter().map(|&p| scene.found(p, 0.9)).collect();
    let mut maps = painted(&found, &[], &cx);
    assert_eq!(
        repair_unexplained(&mut found, &mut maps, &cx, &offsets, 4.5),
        0
    );
    assert!(found.iter().zip(&truth).all(|(g, &t)| g.pose == t));
}

/// Two blocks of [`eaten_into`] end to end: the second spot's trial, worked out ahead
/// beside the first block as it was, reads where the first is repaired and is redone
/// (and then adds the second block's middle rod too, against the first block now whole),
/// so several threads give what one gives, to the bit (rods and maps). The test fails when
/// the guesses are taken over without the read check.
#[test]
fn unexplained_repairs_do_not_depend_on_the_thread_count() {
    let ((t0, w0), (t1, w1)) = (eaten_into(0.0), eaten_into(LENGTH + 2.0));
    let truth: Vec<Pose> = t0.into_iter().chain(t1).collect();
    let scene = Scene::of(&truth);
    let cx = scene.cx();
    let offsets = along_axis();
    let on = |threads: usize| {
        let found = w0.iter().chain(&w1).map(|&p| scene.found(p, 0.9)).collect();
        on_threads(threads, &cx, found, |found, maps| {
            repair_unexplained(found, maps, &cx, &offsets, 4.5)
        })
    };
    let one = on(1);
    assert_eq!(one.0, 2, "both blocks repaired");
    // The first block within a tenth of a width (the test of one block holds the repair
    // to a pixel); the second's rods come out within 2 px, one of them 3 degrees turned.
    assert_eq!(one.1.len(), truth.len());
    for t in &t0 {
        assert!(
            one.1
                .iter()
                .any(|(p, _)| (p.x - t.x).hypot(p.y - t.y) < 0.1 * WIDTH
                    && turn(p.phi, t.phi) < 2f64.to_radians()),
            "{t:?} not among {:?}",
            one.1
        );
    }
    for threads in [2, 3] {
        assert!(on(threads) == one, "{threads} threads differ from one");
    }
}

/// Two short rods face to face at `(x, y)` and the rod fitted across them, turned by a
/// right angle, with the highlights along the two rods' axes at their centres.
fn across(x: f64, y: f64) -> ([Pose; 2], Pose, [AxisSeed; 2]) {
    let phi: f64 = 0.3;
    let (s, c) = phi.sin_cos();
    let truth = [-0.5, 0.5].map(|k| Pose {
        x: x + k * WIDTH * s,
        y: y + k * WIDTH * c,
        phi,
    });
    let wrong = Pose {
        x,
        y,
        phi: phi + std::f64::consts::FRAC_PI_2,
    };
    (truth, wrong, truth.map(highlight_along))
}

/// The highlight a rod at `p` shows: at its centre, along its axis.
fn highlight_along(p: Pose) -> AxisSeed {
    AxisSeed {
        x: p.x,
        y: p.y,
        phi: p.phi,
        depth: 0.8,
    }
}

/// The rod of [`across`] is refitted as the two rods its highlights belong to.
#[test]
fn a_rod_across_two_is_refitted_by_their_highlights() {
    let (truth, wrong, seeds) = across(100.0, 90.0);
    let scene = Scene::of(&truth);
    let cx = scene.cx();
    let offsets = along_axis();
    let mut found = vec![scene.found(wrong, 0.9)];
    let mut maps = painted(&found, &[], &cx);
    // A rod not among those tried is left as it was.
    assert_eq!(
        repair_across_highlights(
            &mut found,
            &mut maps,
            &cx,
            0..0,
            &seeds,
            &offsets,
            &offsets,
            4.5
        ),
        0
    );
    assert_eq!(found[0].pose, wrong);
    assert_eq!(
        repair_across_highlights(
            &mut found,
            &mut maps,
            &cx,
            0..1,
            &seeds,
            &offsets,
            &offsets,
            4.5
        ),
        1
    );
    assert_eq!(found.len(), 2);
    assert_found(&found, &truth);
}

/// A rod at its true pose with a highlight across its middle (a scratch on the glass, or
/// a stray seed) is left as it is: no rod fitted at that highlight explains the rod.
#[test]
fn a_highlight_across_a_right_rod_leaves_it() {
    let truth = [Pose {
        x: 100.0,
        y: 90.0,
        phi: 0.3,
    }];
    let stray = [AxisSeed {
        x: 100.0,
        y: 90.0,
        phi: 0.3 + std::f64::consts::FRAC_PI_2,
        depth: 0.8,
    }];
    let (repaired, found) = across_repaired(&Scene::of(&truth), &truth, &stray);
    assert_eq!(repaired, 0);
    assert_eq!(found.len(), 1);
    assert_eq!(found[0].pose, truth[0]);
}

/// Two blocks of [`across`] end to end, 2 px apart: the second rod's trial, worked out
/// ahead beside the first block as it was, reads where the first is repaired and is
/// redone, so several threads give what one gives, to the bit (rods and maps). The test
/// fails when the guesses are taken over without the read check.
#[test]
fn across_repairs_do_not_depend_on_the_thread_count() {
    let (s, c) = 0.3f64.sin_cos();
    let half = 0.5 * (LENGTH + 2.0);
    let ((t0, w0, s0), (t1, w1, s1)) = (
        across(100.0 - half * c, 90.0 + half * s),
        across(100.0 + half * c, 90.0 - half * s),
    );
    let truth: Vec<Pose> = t0.into_iter().chain(t1).collect();
    let seeds: Vec<AxisSeed> = s0.into_iter().chain(s1).collect();
    let scene = Scene::of(&truth);
    let cx = scene.cx();
    let offsets = along_axis();
    let on = |threads: usize| {
        let found = [w0, w1].map(|p| scene.found(p, 0.9)).into();
        on_threads(threads, &cx, found, |found, maps| {
            repair_across_highlights(found, maps, &cx, 0..2, &seeds, &offsets, &offsets, 4.5)
        })
    };
    assert_both_repaired_alike(&scene, &truth, "blocks", on);
}

/// Five rods end to end at height `y`, and the row's fit: the middle one turned across
/// it, its neighbours shifted by 7 px into its place; with the middle's highlight.
fn squeezed_row(y: f64) -> (Vec<Pose>, [Pose; 5], AxisSeed) {
    let truth: Vec<Pose> = (0..5)
        .map(|i| Pose {
            x: 40.0 + LENGTH * i as f64,
            y,
            phi: 0.0,
        })
        .collect();
    let shifted = |i: usize, dx: f64| Pose {
        x: truth[i].x + dx,
        ..truth[i]
    };
    let turned = Pose {
        phi: std::f64::consts::FRAC_PI_2,
        ..truth[2]
    };
    let wrong = [
        turned,
        truth[0],
        shifted(1, 7.0),
        shifted(3, -7.0),
        truth[4],
    ];
    let highlight = AxisSeed {
        x: truth[2].x,
        y,
        phi: 0.0,
        depth: 0.8,
    };
    (truth, wrong, highlight)
}

/// Two rows of [`squeezed_row`] face to face, 2 px apart, whose trials read each other's
/// pixels: several threads give what one gives, to the bit (rods and maps).
#[test]
fn row_repairs_do_not_depend_on_the_thread_count() {
    let (t0, w0, h0) = squeezed_row(50.0);
    let (t1, w1, h1) = squeezed_row(50.0 + WIDTH + 2.0);
    let truth: Vec<Pose> = t0.into_iter().chain(t1).collect();
    let scene = Scene::sized(&truth, 280, 140);
    let cx = scene.cx();
    let offsets = along_axis();
    let seeds = [h0, h1];
    let on = |threads: usize| {
        let found = w0.iter().chain(&w1).map(|&p| scene.found(p, 0.9)).collect();
        on_threads(threads, &cx, found, |found, maps| {
            repair_across_highlights(
                found,
                maps,
                &cx,
                [0, 5].into_iter(),
                &seeds,
                &offsets,
                &offsets,
                4.5,
            )
        })
    };
    assert_both_repaired_alike(&scene, &truth, "rows", on);
}

/// A row of five rods end to end whose middle one was fitted turned across the row, its
/// neighbours shifted into its place: the middle's highlight does not say where along
/// the row a rod ends, the rods at the row's ends do, and the row between them is
/// refitted end to end.
#[test]
fn a_row_squeezed_about_a_turned_rod_is_refitted_end_to_end() {
    let (truth, wrong, highlight) = squeezed_row(60.0);
    let scene = Scene::sized(&truth, 280, 120);
    let (repaired, found) = across_repaired(&scene, &wrong, &[highlight]);
    assert_eq!(repaired, 1);
    assert_eq!(found.len(), 5);
    assert_found(&found, &truth);
}

/// The acceptance's offsets about a seed anywhere on a rod's axis.
fn residual_offsets() -> Vec<(f64, f64)> {
    let along = [-3.0, -2.0, -1.0, 0.0, 1.0, 2.0, 3.0].map(|k| k / 6.0 * LENGTH);
    let across = [-0.5, -0.25, 0.0, 0.25, 0.5].map(|k| k * WIDTH);
    along
        .iter()
        .flat_map(|&a| across.iter().map(move |&b| (a, b)))
        .collect()
}

/// A column of two rods standing on the bottom edge of a 200 x 180 px photograph, the
/// lower one cut by it (0.7 of it seen); and the rods fitted there: the upper one shifted
/// a third of a length down onto the cut one, and a rod centred outside the photograph
/// (0.3 of it seen) over what is left of the cut one.
fn cut_column() -> ([Pose; 2], [Pose; 2]) {
    let at = |y| Pose {
        x: 100.0,
        y,
        phi: std::f64::consts::FRAC_PI_2,
    };
    (
        [at(121.0), at(170.0)],
        [at(121.0 + LENGTH / 3.0), at(190.0)],
    )
}

/// The rods of [`cut_column`] fitted wrong: the rod outside is taken away and the column
/// put back, the same on one, two and three threads.
#[test]
fn a_rod_fitted_centred_outside_over_a_cut_rod_is_taken_away_and_the_column_put_back() {
    let (truth, wrong) = cut_column();
    let scene = Scene::sized(&truth, 200, 180);
    let offsets = residual_offsets();
    assert_repaired_alike(
        &scene,
        &truth,
        1..=1,
        || wrong.iter().map(|&p| scene.found(p, 0.9)).collect(),
        |found, maps, cx| repair_outside(found, maps, cx, &offsets, 4.5),
    );
}

/// The rods of [`cut_column`] at their true poses, and a true rod centred outside the
/// photograph (0.3 of it seen) beside them: left as they are.
#[test]
fn a_true_rod_centred_outside_is_kept() {
    let (column, _) = cut_column();
    let mut truth = column.to_vec();
    truth.push(Pose {
        x: 150.0,
        y: 190.0,
        phi: std::f64::consts::FRAC_PI_2,
    });
    let scene = Scene::sized(&truth, 200, 180);
    let cx = scene.cx();
    let mut found: Vec<Found> = truth.iter().map(|&p| scene.found(p, 0.9)).collect();
    let mut maps = painted(&found, &[], &cx);
    let repaired = repair_outside(&mut found, &mut maps, &cx, &residual_offsets(), 4.5);
    assert_eq!(repaired, 0);
    let poses: Vec<Pose> = found.iter().map(|g| g.pose).collect();
    assert_eq!(poses, truth);
}

/// A rod lying along the bottom edge of a 200 x 180 px photograph, 0.7 of a width in,
/// and the rod beyond it face to face that the edge cuts, centred outside and less than
/// a quarter of it seen (as lab rod53 at 6 px/mm, seed 1, at (249.1, 1.6) mm); the same
/// on the left edge; and the rods fitted there: one turned by a right angle across each
/// rod and its stub.
fn along_edges() -> ([Pose; 4], [Pose; 2]) {
    let right_angle = std::f64::consts::FRAC_PI_2;
    let pose = |x, y, phi| Pose { x, y, phi };
    (
        [
            pose(120.0, 158.0, 0.0),
            pose(120.0, 188.0, 0.0),
            pose(22.0, 60.0, right_angle),
            pose(-8.0, 60.0, right_angle),
        ],
        [
            pose(120.0, 180.0 - 0.5 * LENGTH + 4.0, right_angle),
            pose(0.5 * LENGTH - 4.0, 60.0, 0.0),
        ],
    )
}

/// The rods of [`along_edges`] fitted turned: each is refitted along its edge and the
/// stub added, the same on one, two and three threads.
#[test]
fn a_rod_turned_across_the_edge_is_refitted_along_it_with_the_stub_beyond() {
    let (truth, wrong) = along_edges();
    let scene = Scene::sized(&truth, 200, 180);
    let cx = scene.cx();
    let offsets = residual_offsets();
    let on = |threads: usize| {
        let found = wrong.iter().map(|&p| scene.found(p, 0.9)).collect();
        on_threads(threads, &cx, found, |found, maps| {
            repair_along_edge(found, maps, &cx, &offsets, 4.5)
        })
    };
    assert_both_repaired_alike(&scene, &truth, "turned rods", on);
}

/// A rod lying along the top edge between two rods standing across it that the edge cuts
/// (0.6 of them seen), fitted turned across the edge, the rod on its left fitted shifted
/// by 0.3 of a width into its place (lab rod53 at 6 px/mm, seed 3, at (122.3, 118.4) mm):
/// refitted along the edge with the two beside it, the same on one, two and three threads.
#[test]
fn a_rod_turned_across_the_edge_is_refitted_along_it_with_the_cut_rods_beside_it() {
    let right_angle = std::f64::consts::FRAC_PI_2;
    let standing = |x| Pose {
        x,
        y: 0.6 * LENGTH - 0.5 * LENGTH,
        phi: right_angle,
    };
    let beside = 0.5 * LENGTH + 0.5 * WIDTH + 1.0;
    let truth = [
        Pose {
            x: 100.0,
            y: 0.5 * WIDTH + 1.0,
            phi: 0.0,
        },
        standing(100.0 - beside),
        standing(100.0 + beside),
    ];
    let scene = Scene::sized(&truth, 200, 180);
    let offsets = residual_offsets();
    // Its inner end at the rod's inner face, its outer end out over the edge.
    let turned = Pose {
        x: 100.0,
        y: truth[0].y + 0.5 * WIDTH - 0.5 * LENGTH,
        phi: right_angle,
    };
    let shifted = Pose {
        x: truth[1].x + 0.3 * WIDTH,
        ..truth[1]
    };
    assert_repaired_alike(
        &scene,
        &truth,
        1..=1,
        || {
            [turned, shifted, truth[2]]
                .iter()
                .map(|&p| scene.found(p, 0.9))
                .collect()
        },
        |found, maps, cx| repair_along_edge(found, maps, cx, &offsets, 4.5),
    );
}

/// A rod lying along the top edge with a rod beyond it face to face, centred outside and a
/// fifth of it seen (lab rod53 at 10 px/mm, seed 9, at (51.3, 117.8) mm), fitted as one rod
/// standing across the edge: refitted along the edge, and the rod beyond fitted as a stub.
/// The rod fitted afresh in the standing rod's place over every angle lands on the rod
/// along the edge; it is that rod, not a trial for the refit to beat (without that, nothing
/// is repaired). The stub leaves less than 0.2 L x W unexplained, the edge repair's
/// threshold before session 27 (with it, no stub).
#[test]
fn a_rod_turned_across_the_edge_is_refitted_along_it_when_a_fit_afresh_agrees() {
    let truth = [
        Pose {
            x: 100.0,
            y: 0.5 * WIDTH + 6.0,
            phi: 0.0,
        },
        Pose {
            x: 100.0,
            y: 6.0 - 0.5 * WIDTH,
            phi: 0.0,
        },
    ];
    let scene = Scene::sized(&truth, 200, 180);
    let offsets = residual_offsets();
    let turned = Pose {
        x: 92.0,
        y: WIDTH + 6.0 - 0.5 * LENGTH,
        phi: std::f64::consts::FRAC_PI_2,
    };
    let cx = scene.cx();
    let mut found = vec![scene.found(turned, 0.9)];
    let mut maps = painted(&found, &[], &cx);
    let repaired = repair_along_edge(&mut found, &mut maps, &cx, &offsets, 4.5);
    assert_eq!(repaired, 1);
    assert_eq!(
        found.len(),
        2,
        "the rod along the edge and the stub beyond it"
    );
    assert_found(&found, &truth);
}

/// A rod standing across the bottom edge, cut by it (0.8 of it seen), beside a rod lying
/// along it: both true, both left as they are.
#[test]
fn a_true_rod_standing_across_the_edge_is_kept() {
    let right_angle = std::f64::consts::FRAC_PI_2;
    let truth = [
        Pose {
            x: 100.0,
            y: 180.0 - 0.3 * LENGTH,
            phi: right_angle,
        },
        Pose {
            x: 100.0 + 0.5 * WIDTH + 0.5 * LENGTH + 1.0,
            y: 180.0 - 0.5 * WIDTH - 1.0,
            phi: 0.0,
        },
    ];
    let scene = Scene::sized(&truth, 200, 180);
    let cx = scene.cx();
    let mut found: Vec<Found> = truth.iter().map(|&p| scene.found(p, 0.9)).collect();
    let mut maps = painted(&found, &[], &cx);
    let repaired = repair_along_edge(&mut found, &mut maps, &cx, &residual_offsets(), 4.5);
    assert_eq!(repaired, 0);
    let poses: Vec<Pose> = found.iter().map(|g| g.pose).collect();
    assert_eq!(poses, truth);
}

/// Three rows of rods lying flat, the middle one fitted turned by 74 degrees across the rods
/// above and below it (lab rod53 at 10 px/mm, seed 4): those two agree poorly, the turned
/// one well. The doubtful rod and the turned rod are refitted together at the doubtful
/// rod's angle; the same on one, two and three threads.
#[test]
fn a_rod_turned_across_a_doubtful_one_is_refitted_at_its_angle() {
    let truth =
        [(100.0, 60.0), (100.0, 90.0), (100.0, 120.0)].map(|(x, y)| Pose { x, y, phi: 0.0 });
    let scene = Scene::of(&truth);
    let turned = Pose {
        phi: 74f64.to_radians(),
        ..truth[1]
    };
    let offsets = residual_offsets();
    assert_repaired_alike(
        &scene,
        &truth,
        1..,
        || {
            vec![
                scene.found(truth[0], 0.55),
                scene.found(turned, 0.95),
                scene.found(truth[2], 0.55),
            ]
        },
        |found, maps, cx| repair_doubtful(found, maps, cx, &offsets, 4.5),
    );
}

/// Three rows of two rods lying flat, end to end; in the middle row the first rod is
/// fitted turned by 45 degrees (agreeing poorly) and the second shifted a quarter length
/// into its place (lab rod53 at 10 px/mm, seed 4, at the right edge): refitted alone, the
/// turned rod has no room to turn back. With the rows around it refitted together at the
/// rows' angle, every rod is found; the same on one, two and three threads.
#[test]
fn a_doubtful_rod_with_a_neighbour_shifted_into_its_place_is_refitted_with_the_rows() {
    let truth = [60.0, 90.0, 120.0]
        .into_iter()
        .flat_map(|y| [70.0, 70.0 + LENGTH + 1.0].map(|x| Pose { x, y, phi: 0.0 }))
        .collect::<Vec<_>>();
    let scene = Scene::of(&truth);
    let offsets = residual_offsets();
    assert_repaired_alike(
        &scene,
        &truth,
        1..,
        || {
            truth
                .iter()
                .enumerate()
                .map(|(k, &p)| match k {
                    2 => scene.found(
                        Pose {
                            phi: 45f64.to_radians(),
                            ..p
                        },
                        0.55,
                    ),
                    3 => scene.found(
                        Pose {
                            x: p.x - 0.25 * LENGTH,
                            ..p
                        },
                        0.9,
                    ),
                    _ => scene.found(p, 0.9),
                })
                .collect()
        },
        |found, maps, cx| repair_doubtful(found, maps, cx, &offsets, 4.5),
    );
}

/// The rods of [`two_rods_turned_across_three_are_refitted_as_the_three`], with a fifth rod
/// turned like the wrong two, rightly, within a length of the doubtful one: the wrong two
/// are refitted as the three and the fifth rod is left at its angle; the same on one, two
/// and three threads. (Here the trial over every angle keeps it; lab rod3 at 10 px/mm,
/// seed 7, needed the rods overlapping the doubtful one refitted without it.)
#[test]
fn rods_turned_across_a_block_are_refitted_and_a_true_rod_turned_alike_kept() {
    let phi = 62f64.to_radians();
    let mut truth: Vec<Pose> = [(100.0, 60.0), (100.0, 90.0), (100.0, 120.0), (155.0, 90.0)]
        .map(|(x, y)| Pose { x, y, phi: 0.0 })
        .to_vec();
    truth.push(Pose {
        x: 45.0,
        y: 80.0,
        phi,
    });
    let scene = Scene::of(&truth);
    let (s, c) = phi.sin_cos();
    let offsets = along_axis();
    assert_repaired_alike(
        &scene,
        &truth,
        1..,
        || {
            let mut found: Vec<Found> = [(-0.5, 0.6), (0.5, 0.94)]
                .into_iter()
                .map(|(k, confidence)| {
                    let (x, y) = (100.0 + k * WIDTH * s, 90.0 + k * WIDTH * c);
                    scene.found(Pose { x, y, phi }, confidence)
                })
                .collect();
            found.push(scene.found(truth[3], 0.9));
            found.push(scene.found(truth[4], 0.9));
            found
        },
        |found, maps, cx| repair_doubtful(found, maps, cx, &offsets, 4.5),
    );
}

/// Two short rods face to face beside a rod standing by the right edge, read as the same
/// block turned by a right angle: a rod standing across the pair (the true pair's
/// highlights inside it) and two rods lying face to face where the standing rod is. `x0` is
/// the block's left side.
fn mirrored_block(x0: f64, y0: f64) -> ([Pose; 3], [Pose; 3], [AxisSeed; 2]) {
    let (half_l, half_w) = (0.5 * LENGTH, 0.5 * WIDTH);
    let stand = std::f64::consts::FRAC_PI_2;
    let lie = |x, y| Pose { x, y, phi: 0.0 };
    let truth = [
        lie(x0 + half_l, y0 + half_w),
        lie(x0 + half_l, y0 + WIDTH + half_w),
        Pose {
            x: x0 + LENGTH + half_w,
            y: y0 + WIDTH,
            phi: stand,
        },
    ];
    let wrong = [
        Pose {
            x: x0 + half_w,
            y: y0 + WIDTH,
            phi: stand,
        },
        lie(x0 + WIDTH + half_l, y0 + half_w),
        lie(x0 + WIDTH + half_l, y0 + WIDTH + half_w),
    ];
    (truth, wrong, [truth[0], truth[1]].map(highlight_along))
}

/// [`mirrored_block`] by the right edge is refitted as it is: the rod standing across the
/// pair comes off with both rods fitted where the standing rod is, which each cover a part
/// of the pair (with either alone off, the rod fitted at a highlight lies across the other).
#[test]
fn a_block_read_turned_by_the_edge_is_refitted_as_it_is() {
    let (truth, wrong, seeds) = mirrored_block(115.0, 60.0);
    let (repaired, found) = across_repaired(&Scene::of(&truth), &wrong, &seeds);
    assert_eq!(repaired, 1);
    assert_eq!(found.len(), 3);
    assert_found(&found, &truth);
}
