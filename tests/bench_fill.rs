//! `facets bench fill`: the deviation formulas on synthetic ensembles, their behaviour under
//! the null, and a tiny end-to-end run that writes every output.

use facets::analysis::stats::MeanErr;
use facets::bench::fill::{
    self, BenchConfig, MeasureInput, Measures, PressureMeasure, REFERENCE, ReferenceScene, Setting,
    WITHIN, deviations, l1, pooled, rms, scalar, signed_scalar,
};
use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;
use rand_distr_free::normal;

/// Box-Muller, to keep the test free of another dependency.
mod rand_distr_free {
    use rand::Rng;
    pub fn normal(rng: &mut impl Rng) -> f64 {
        let u: f64 = 1.0 - rng.random::<f64>();
        let v: f64 = rng.random::<f64>();
        (-2.0 * u.ln()).sqrt() * (std::f64::consts::TAU * v).cos()
    }
}

fn me(mean: f64, stderr: f64) -> MeanErr {
    MeanErr { mean, stderr, n: 8 }
}

/// An ensemble's measures with every series shifted by `shift` and standard error `se`.
fn measures(shift: f64, se: f64) -> Measures {
    let f = [0.9, 0.5, 0.4, 0.6, 1.1, 0.3];
    let g = [0.0, 0.2, 2.5, 1.4, 0.9, 1.0, 1.1];
    let p = [0.0, 0.1, 0.25, 0.4, 0.5];
    Measures {
        n_realisations: 8,
        phi_f: me(0.80 + shift, se),
        f: f.iter().map(|v| v + shift).collect(),
        f_err: vec![se; f.len()],
        r: (1..=g.len()).map(|k| k as f64 * 0.5).collect(),
        g: g.iter().map(|v| v + shift).collect(),
        g_err: vec![se; g.len()],
        pressure: Some(PressureMeasure {
            depth_over_w: (0..p.len()).map(|k| k as f64 * 0.05).collect(),
            p: p.iter().map(|v| v + shift).collect(),
            p_err: vec![se; p.len()],
        }),
    }
}

#[test]
fn identical_ensembles_deviate_by_zero_and_a_shift_by_its_z() {
    let reference = measures(0.0, 0.01);
    let same = deviations(&reference, &reference);
    assert_eq!(
        [same.phi_f, same.orientation, same.rdf, same.pressure],
        [0.0; 4]
    );
    assert!(same.within());

    // Every observable shifted by 3 standard errors of each side: z = 0.03 / sqrt(2) / 0.01.
    let shifted = deviations(&measures(0.03, 0.01), &reference);
    let z = 3.0 / 2f64.sqrt();
    for d in [
        shifted.phi_f,
        shifted.orientation,
        shifted.rdf,
        shifted.pressure,
    ] {
        assert!((d - z).abs() < 1e-9, "{d} != {z}");
    }
    assert!(!shifted.within(), "2.12 standard errors is outside 2");
    // 1.9 combined standard errors is within 2.
    let near = deviations(&measures(1.9 * 0.01 * 2f64.sqrt(), 0.01), &reference);
    assert!((near.largest() - 1.9).abs() < 1e-9 && near.within());
}

#[test]
fn the_forms_weigh_bins_as_documented() {
    // L1: sum |diff| / sum sqrt(se_s^2 + se_ref^2) = (1 + 3) / (1 + 1).
    assert!((l1(&[1.0, -3.0], &[1.0, 1.0], &[0.0, 0.0], &[0.0, 0.0]) - 2.0).abs() < 1e-12);
    // RMS: sqrt((1 + 9) / 2) / sqrt((2 + 2) / 2).
    let r = rms(&[1.0, -3.0], &[1.0, 1.0], &[0.0, 0.0], &[1.0, 1.0]);
    assert!((r - 5f64.sqrt() / 2f64.sqrt()).abs() < 1e-12);
    // RMS over the common depth range only: the longer profile's extra point is not used.
    let r2 = rms(&[1.0, -3.0, 100.0], &[1.0; 3], &[0.0, 0.0], &[1.0, 1.0]);
    assert_eq!(r, r2);
    // Scalar: |0.83 - 0.80| / hypot(0.03, 0.04) = 0.6.
    assert!((scalar(me(0.83, 0.03), me(0.80, 0.04)) - 0.6).abs() < 1e-12);
    // Nothing to compare is not a small deviation.
    assert!(l1(&[], &[], &[], &[]).is_nan());
    assert!(l1(&[1.0], &[1.0], &[1.0, 2.0], &[1.0, 1.0]).is_nan());
    let mut no_pressure = measures(0.0, 0.01);
    no_pressure.pressure = None;
    let d = deviations(&no_pressure, &measures(0.0, 0.01));
    assert!(d.pressure.is_nan() && d.largest().is_nan() && !d.within());
    // A difference with no spread to measure it by is infinitely far.
    assert_eq!(scalar(me(1.0, 0.0), me(0.0, 0.0)), f64::INFINITY);
    // The signed form keeps the direction; pooling adds shifts of one sign and cancels others.
    assert!((signed_scalar(me(0.77, 0.03), me(0.80, 0.04)) + 0.6).abs() < 1e-12);
    assert!((pooled(&[-1.31, -0.93, -1.34]) + 3.58 / 3f64.sqrt()).abs() < 1e-12);
    assert!(pooled(&[-1.31, -0.93, -1.34]).abs() > WITHIN);
    assert_eq!(pooled(&[1.5, -1.5]), 0.0);
    assert!(pooled(&[]).is_nan());
}

/// Two ensembles of 8 realisations from one distribution, many times: the deviations are of
/// order one and rarely above 2, as the module doc says.
#[test]
fn under_the_null_deviations_are_of_order_one() {
    let mut rng = ChaCha8Rng::seed_from_u64(7);
    let trials = 2000;
    let bins = 18;
    let ensemble = |rng: &mut ChaCha8Rng| -> (Vec<MeanErr>, MeanErr) {
        let per_bin: Vec<MeanErr> = (0..bins)
            .map(|_| MeanErr::of(&(0..8).map(|_| normal(rng)).collect::<Vec<_>>()))
            .collect();
        let scalar = MeanErr::of(&(0..8).map(|_| normal(rng)).collect::<Vec<_>>());
        (per_bin, scalar)
    };
    let (mut sum_s, mut above_s, mut sum_l1, mut above_l1, mut sum_rms) = (0.0, 0, 0.0, 0, 0.0);
    for _ in 0..trials {
        let (a, sa) = ensemble(&mut rng);
        let (b, sb) = ensemble(&mut rng);
        let s = scalar(sa, sb);
        let mean = |v: &[MeanErr]| v.iter().map(|m| m.mean).collect::<Vec<_>>();
        let err = |v: &[MeanErr]| v.iter().map(|m| m.stderr).collect::<Vec<_>>();
        let d1 = l1(&mean(&a), &err(&a), &mean(&b), &err(&b));
        let d2 = rms(&mean(&a), &err(&a), &mean(&b), &err(&b));
        sum_s += s;
        sum_l1 += d1;
        sum_rms += d2;
        above_s += usize::from(s > WITHIN);
        above_l1 += usize::from(d1 > WITHIN);
    }
    let n = trials as f64;
    // |t| with 14 degrees of freedom: mean 0.82, P(|t| > 2) = 6.5 %.
    assert!((0.76..0.88).contains(&(sum_s / n)), "{}", sum_s / n);
    assert!(
        (0.04..0.09).contains(&(above_s as f64 / n)),
        "{}",
        above_s as f64 / n
    );
    // Mean |z| over 18 bins, with estimated errors: about 0.8, and next to never above 2.
    assert!((0.7..0.9).contains(&(sum_l1 / n)), "{}", sum_l1 / n);
    assert!(above_l1 as f64 / n < 0.005, "{}", above_l1 as f64 / n);
    // RMS of z: about 1.
    assert!((0.9..1.1).contains(&(sum_rms / n)), "{}", sum_rms / n);
}

fn pool(threads: usize) -> rayon::ThreadPool {
    rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .build()
        .unwrap()
}

/// Two settings (faithful added to n25), 2 seeds, 20 squares: every output written, every
/// number finite, and the same measures on one thread as on two.
#[test]
fn a_tiny_bench_writes_every_output() {
    let out = tempfile::tempdir().unwrap();
    let config = BenchConfig {
        scenes: vec![ReferenceScene::by_name("square-phi0p25").unwrap()],
        settings: vec![Setting::by_name("n25").unwrap()],
        grains: 20,
        seeds: 2,
        first_seed: 1,
        max_relaxation_time_s: 1.0,
        measure: MeasureInput::default(),
        out: out.path().to_path_buf(),
        reuse: false,
    };
    assert_eq!(fill::total_runs(&config), 4);
    let done = std::sync::atomic::AtomicUsize::new(0);
    let report = pool(2)
        .install(|| {
            fill::run_bench(&config, &|_, _, _| {
                done.fetch_add(1, std::sync::atomic::Ordering::Relaxed);
            })
        })
        .unwrap();
    assert_eq!(done.into_inner(), 4);
    // On one thread (into another folder): the same deposits, so the same measures and
    // deviations; only the times differ.
    let other = tempfile::tempdir().unwrap();
    let serial = pool(1)
        .install(|| {
            fill::run_bench(
                &BenchConfig {
                    out: other.path().to_path_buf(),
                    ..config.clone()
                },
                &|_, _, _| {},
            )
        })
        .unwrap();
    for (a, b) in report.rows.iter().zip(&serial.rows) {
        assert_eq!(a.measures, b.measures, "{} {}", a.scene, a.setting);
        assert_eq!(a.deviations, b.deviations, "{} {}", a.scene, a.setting);
    }
    // Run again with reuse: nothing is simulated (the deposits keep their times of change),
    // and the report is the same, recorded times included.
    let deposit = out
        .path()
        .join("runs/square-phi0p25/n25/seed-1/deposit.csv");
    let modified = std::fs::metadata(&deposit).unwrap().modified().unwrap();
    let reused = fill::run_bench(
        &BenchConfig {
            reuse: true,
            ..config.clone()
        },
        &|_, _, _| {},
    )
    .unwrap();
    assert_eq!(
        std::fs::metadata(&deposit).unwrap().modified().unwrap(),
        modified
    );
    for (a, b) in report.rows.iter().zip(&reused.rows) {
        assert_eq!(a.measures, b.measures);
        // JSON keeps the recorded times to the last digit or so.
        assert!((a.wall_s - b.wall_s).abs() <= 1e-12 * a.wall_s);
        assert!((a.cpu_s - b.cpu_s).abs() <= 1e-12 * a.cpu_s);
    }
    let written = fill::write_all(out.path(), &report).unwrap();
    for path in &written {
        assert!(
            std::fs::metadata(path).unwrap().len() > 0,
            "{}",
            path.display()
        );
    }
    assert_eq!(report.rows.len(), 2);
    assert_eq!(report.rows[0].setting, REFERENCE);
    let n25 = &report.rows[1];
    assert_eq!(n25.setting, "n25");
    assert!(
        n25.time_step_s > 1e-6,
        "n25 must step coarser than the faithful 1e-6 s"
    );
    let d = n25.deviations.expect("n25 is compared with faithful");
    for v in [
        d.phi_f,
        d.orientation,
        d.rdf,
        d.pressure,
        n25.speed_up,
        n25.cpu_s,
        n25.wall_s,
    ] {
        assert!(v.is_finite(), "{d:?}, speed-up {}", n25.speed_up);
    }
    // The candidate for the defaults is n25 exactly when it passes.
    let fastest = fill::fastest_within(&report);
    if d.within() {
        assert_eq!(fastest, Some(("n25".to_string(), n25.speed_up)));
    } else {
        assert_eq!(fastest, None);
    }
    // Three scenes where the setting stays within 2 SE alone but its packing fraction is low
    // in each by 1.3 standard errors: pooled, -2.25, and no candidate for the defaults.
    let mut shifted = report.clone();
    shifted.rows.clear();
    for scene in ["a", "b", "c"] {
        let (mut reference, mut setting) = (report.rows[0].clone(), report.rows[1].clone());
        reference.scene = scene.into();
        setting.scene = scene.into();
        let (r, s) = (reference.measures.phi_f, &mut setting.measures.phi_f);
        s.mean = r.mean - 1.3 * r.stderr.hypot(s.stderr);
        setting.deviations = Some(fill::Deviations {
            phi_f: 1.3,
            orientation: 0.5,
            rdf: 0.5,
            pressure: 0.5,
        });
        shifted.rows.extend([reference, setting]);
    }
    assert!((fill::pooled_phi_shift(&shifted, "n25") + 3.9 / 3f64.sqrt()).abs() < 1e-9);
    assert_eq!(fill::fastest_within(&shifted), None);
    // The CSV: a header and one row per scene x setting, numbers that parse and are finite.
    let csv = std::fs::read_to_string(out.path().join("fill.csv")).unwrap();
    let lines: Vec<&str> = csv.lines().collect();
    assert_eq!(lines.len(), 3, "{csv}");
    let header: Vec<&str> = lines[0].split(',').collect();
    let row: Vec<&str> = lines[2].split(',').collect();
    assert_eq!(header.len(), row.len());
    for (name, value) in header.iter().zip(&row) {
        if ["scene", "setting", "within_2se"].contains(name) {
            continue;
        }
        let v: f64 = value.parse().unwrap_or_else(|_| panic!("{name} = {value}"));
        assert!(v.is_finite(), "{name} = {value}");
    }
    let md = std::fs::read_to_string(out.path().join("fill.md")).unwrap();
    assert!(md.contains("| square-phi0p25 | n25 |"), "{md}");
    let png = std::fs::read(out.path().join("speed_vs_error.png")).unwrap();
    assert_eq!(&png[1..4], b"PNG");
}
