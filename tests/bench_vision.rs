//! `facets bench vision` end to end on tiny frames: every source photographed, scored, pooled,
//! written; the same seeds give the same photographs; the splits give different ones.

use facets::bench::vision::{
    self as bench, SourceKind, Split, VisionBench, parse_seeds, write_results_csv,
};
use vision::Shortcuts;
use vision::render::LookRange;

fn tiny(split: Split) -> VisionBench {
    VisionBench {
        px_per_mm: vec![10.0],
        looks: vec![LookRange::LabLike],
        shapes: vec!["square".into()],
        sources: SourceKind::ALL.to_vec(),
        split,
        seeds: parse_seeds("1").unwrap(),
        frame: [0.04, 0.03],
        shortcuts: Shortcuts::default(),
    }
}

#[test]
fn a_tiny_bench_photographs_every_source_and_pools_them() {
    let config = tiny(Split::HeldOut);
    let report = bench::run(&config, &|_| {}).unwrap();
    // Three simulated fills of nuts and the two packings, one photograph each.
    assert_eq!(config.photographs(), 5);
    assert_eq!(report.photos.len(), 5);
    assert_eq!(report.by_source.len(), 5);
    assert_eq!(report.looks.len(), 5);
    let sources: Vec<&str> = report.photos.iter().map(|r| r.source).collect();
    for expected in [
        "square-p01-rough",
        "square-p25-rough",
        "square-p47-rough",
        "packing-ordered",
        "packing-disordered",
    ] {
        assert!(sources.contains(&expected), "{sources:?}");
    }
    // A 40 x 30 mm window of nuts 6.9 mm wide shows at least a few whole ones.
    for r in &report.photos {
        assert!(r.tally.truth_uncut >= 4, "{}: {:?}", r.source, r.tally);
        assert!(r.grains > r.tally.truth_uncut);
        assert_eq!(r.orientation_errors_deg.len(), r.tally.error_pairs);
    }
    let [all] = &report.by_shape[..] else {
        panic!("one pooled row expected, got {}", report.by_shape.len())
    };
    assert_eq!((all.source, all.seed, all.photos), ("all", None, 5));
    let truth: usize = report.photos.iter().map(|r| r.tally.truth_uncut).sum();
    assert_eq!(all.tally.truth_uncut, truth);
    // Lab-like photographs of nuts: the detector finds most of them (the targets are far
    // stricter; this only says the photographs, truth and matching agree).
    assert!(all.tally.recall() > 0.8, "{:?}", all.tally);

    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("bench.csv");
    let rows = report.rows();
    write_results_csv(&out, &rows, config.split, "none").unwrap();
    let text = std::fs::read_to_string(&out).unwrap();
    assert_eq!(text.lines().count(), 1 + 5 + 5 + 1);
    assert!(text.lines().skip(1).all(|l| l.starts_with("held-out,")));
}

#[test]
fn seeds_fix_the_photographs_and_the_splits_differ() {
    let config = tiny_deposits(Split::Tuning);
    let a = bench::run(&config, &|_| {}).unwrap();
    let b = bench::run(&config, &|_| {}).unwrap();
    let held_out = bench::run(&tiny_deposits(Split::HeldOut), &|_| {}).unwrap();
    for ((x, y), z) in a.looks.iter().zip(&b.looks).zip(&held_out.looks) {
        assert_eq!(x.look, y.look);
        assert_ne!(x.look, z.look);
    }
    assert_eq!(without_seconds(&a.sources), without_seconds(&b.sources));
    assert_ne!(
        without_seconds(&a.sources),
        without_seconds(&held_out.sources)
    );
    for (x, y) in a.photos.iter().zip(&b.photos) {
        assert_eq!(x.tally, y.tally);
    }
}

/// The sources table without its last column, the seconds each source took to build (a wall
/// time, which moves with the machine's load).
fn without_seconds(table: &str) -> Vec<&str> {
    table
        .lines()
        .map(|line| {
            line.trim_end_matches('|')
                .rsplit_once('|')
                .map_or(line, |(row, _)| row)
        })
        .collect()
}

fn tiny_deposits(split: Split) -> VisionBench {
    VisionBench {
        sources: vec![SourceKind::Deposits],
        px_per_mm: vec![6.0],
        ..tiny(split)
    }
}

#[test]
fn what_the_bench_cannot_run_is_refused_naming_the_option() {
    let mut tall = tiny(Split::HeldOut);
    tall.frame = [0.1, 0.2];
    let e = tall.validate().unwrap_err().to_string();
    assert!(e.contains("--frame-mm"), "{e}");
    let mut zero = tiny(Split::HeldOut);
    zero.seeds = parse_seeds("0").unwrap();
    let e = zero.validate().unwrap_err().to_string();
    assert!(e.contains("--seed"), "{e}");
    let mut scale = tiny(Split::HeldOut);
    scale.px_per_mm = vec![-1.0];
    let e = scale.validate().unwrap_err().to_string();
    assert!(e.contains("--px-per-mm"), "{e}");
    let mut shape = tiny(Split::HeldOut);
    shape.shapes = vec!["rod".into()];
    let e = shape.validate().unwrap_err().to_string();
    assert!(e.contains("--shapes rod"), "{e}");
}
