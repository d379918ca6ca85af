//! `facets bench analysis`: the analysis's speed goals. g(r) of an ensemble of synthetic
//! deposits (goal < 1 s on 2 cores) and the coarse-grained stress on a 200 x 600 grid of
//! built stacks with exact forces (goal < 2 s).

use crate::analysis::coarse_grain::{CoarseGrainInput, branches, linspace};
use crate::analysis::rdf::{self, RdfInput};
use crate::analysis::stress_grid::stress_on_grid;
use crate::deposit::{
    DepositMeta, Ensemble, FrameMm, Realisation, Source, SquareStack, jittered_lattice,
};

use super::process::best_of;
use crate::grains::GrainKind;

/// What to time.
#[derive(Clone, Copy, Debug)]
pub struct AnalysisBench {
    /// Deposits in the g(r) ensemble.
    pub deposits: usize,
    /// Grains per deposit.
    pub grains: usize,
    /// Repetitions of each timing; the best is reported (the machine is shared).
    pub repeat: usize,
}

/// One measure timed.
#[derive(Clone, Debug)]
pub struct Timing {
    pub what: String,
    /// Best wall time (s) and the processor time of that run (s).
    pub wall_s: f64,
    pub cpu_s: f64,
    pub goal_s: f64,
}

impl Timing {
    pub fn met(&self) -> bool {
        self.wall_s < self.goal_s
    }
}

/// Times g(r) and the stress grids.
pub fn run(bench: &AnalysisBench) -> anyhow::Result<Vec<Timing>> {
    let mut timings = Vec::new();
    // g(r): squares (D = 6.9 mm) in a photograph-sized frame, W = 258 mm.
    let side = 6.9e-3;
    let frame = [0.0, 0.258, 0.290, 0.290 + 0.258 * 0.8];
    let realisations: Vec<Realisation> = (0..bench.deposits)
        .map(|k| Realisation {
            name: format!("synthetic {k}"),
            deposit: jittered_lattice(bench.grains, side, side, frame, 0.2, 0.3, k as u64),
            contacts: None,
            meta: DepositMeta {
                silo_width_mm: 258.0,
                phi0: 0.1,
                frame_mm: Some(FrameMm {
                    x_min: frame[0] * 1e3,
                    x_max: frame[1] * 1e3,
                    y_min: frame[2] * 1e3,
                    y_max: frame[3] * 1e3,
                }),
                areal_density_kg_m2: None,
                gravity_m_s2: None,
                source: Source::Experiment,
            },
            shape: GrainKind::Square,
        })
        .collect();
    let ensemble = Ensemble::new(realisations)?;
    let (wall_s, cpu_s, result) = best_of(bench.repeat, || {
        rdf::compute(&RdfInput::default(), &ensemble)
    });
    timings.push(Timing {
        what: format!(
            "g(r): {} deposits x {} grains ({} centres)",
            bench.deposits, bench.grains, result?.n_centres
        ),
        wall_s,
        cpu_s,
        goal_s: 1.0,
    });

    // Stress on paper-scale deposits, built stacks with exact forces:
    // - rods: 20 000 contacts spread over 256 x 645 mm (the area of the paper's 9 000 short rods,
    //   D = 3 mm), w = 3 D = 9 mm as the paper uses for rods;
    // - squares: the paper's 3 000 nuts (37 x 81, D = 6.9 mm), w = 4 D = 27.6 mm.
    let cases = [
        (
            "rods",
            SquareStack {
                columns: 63,
                rows: 159,
                side: 256e-3 / 63.0,
                ..SquareStack::default()
            },
            9e-3,
        ),
        (
            "squares",
            SquareStack {
                columns: 37,
                rows: 81,
                ..SquareStack::default()
            },
            4.0 * 6.9e-3,
        ),
    ];
    for (name, stack, w) in cases {
        let (deposit, contacts, _) = stack.build(0.1);
        let list = branches(&deposit, &contacts);
        let xs = linspace(0.0, stack.silo_width(), 200);
        let ys = linspace(0.0, stack.rows as f64 * stack.side, 600);
        let input = CoarseGrainInput::new(w);
        let (wall_s, cpu_s, _) = best_of(bench.repeat, || stress_on_grid(&list, &xs, &ys, &input));
        timings.push(Timing {
            what: format!(
                "stress ({name}): 200 x 600 grid, {} contacts, w = {:.1} mm",
                list.len(),
                w * 1e3
            ),
            wall_s,
            cpu_s,
            goal_s: 2.0,
        });
    }
    Ok(timings)
}
