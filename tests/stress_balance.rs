//! Exact answers of the coarse-grained stress (issue 5): the virial stress of a uniformly
//! compressed lattice, and momentum balance on a built static deposit.

use facets::analysis::coarse_grain::{
    Branch, CoarseGrainInput, branches, density_at, grid_points, linspace, stress_at,
};
use facets::deposit::{Partner, SquareStack};

/// A square lattice (spacing a) of grains, each bonded to its right, upper and upper-right
/// neighbours with the same (arbitrary) force per bond type, so every grain is balanced.
/// The virial stress is -(1/a^2) sum over one cell's bonds of f (x) r.
#[test]
fn compressed_lattice_bulk_stress_equals_virial_stress() {
    let a = 5e-3;
    let n = 40;
    let bonds = [
        // (neighbour offset, force on the grain from that neighbour)
        ([1i32, 0i32], [-2.0, 0.3]),
        ([0, 1], [0.25, -1.1]),
        ([1, 1], [-0.4, -0.6]),
    ];
    let mut list = Vec::new();
    for j in 0..n {
        for i in 0..n {
            let ri = [i as f64 * a, j as f64 * a];
            for (off, f) in bonds {
                let rj = [(i + off[0]) as f64 * a, (j + off[1]) as f64 * a];
                list.push(Branch {
                    a: ri,
                    b: rj,
                    force: f,
                });
            }
        }
    }
    let mut virial = [0.0; 4];
    for (off, f) in bonds {
        let r = [-off[0] as f64 * a, -off[1] as f64 * a];
        virial[0] -= f[0] * r[0] / (a * a);
        virial[1] -= f[0] * r[1] / (a * a);
        virial[2] -= f[1] * r[0] / (a * a);
        virial[3] -= f[1] * r[1] / (a * a);
    }
    // w = 2a: the lattice's ripple in the smoothed field is ~exp(-pi^2 w^2 / a^2) = 1e-17;
    // the cut-off error is below exp(-4.5^2) = 1.6e-9. Bulk: farther than the cut-off from
    // the lattice's edges.
    let input = CoarseGrainInput::new(2.0 * a);
    let mid = (n as f64 - 1.0) * a / 2.0;
    let xs = linspace(mid - 3.3 * a, mid + 3.3 * a, 7);
    let points = grid_points(&xs, &xs);
    let scale = virial.iter().fold(0.0f64, |m, v| m.max(v.abs()));
    for s in stress_at(&list, &points, &input) {
        for k in 0..4 {
            assert!(
                (s[k] - virial[k]).abs() < 1e-6 * scale,
                "component {k}: {} vs virial {}",
                s[k],
                virial[k]
            );
        }
    }
}

/// The built stack: exact forces; w = 2 D.
struct Setup {
    stack: SquareStack,
    list: Vec<Branch>,
    centres: Vec<[f64; 2]>,
    masses: Vec<f64>,
    input: CoarseGrainInput,
    weight: f64,
    contacts: Vec<facets::deposit::Contact>,
    deposit: facets::deposit::Deposit,
}

fn setup() -> Setup {
    let stack = SquareStack::default();
    let (deposit, contacts, _) = stack.build(0.1);
    let list = branches(&deposit, &contacts);
    let centres = deposit.grains.iter().map(|g| [g.x, g.y]).collect();
    let masses = vec![stack.grain_mass(); deposit.grains.len()];
    Setup {
        input: CoarseGrainInput::new(2.0 * stack.side),
        weight: stack.grain_mass() * stack.gravity,
        stack,
        list,
        centres,
        masses,
        contacts,
        deposit,
    }
}

#[test]
fn built_deposit_bulk_obeys_div_sigma_plus_rho_g_equals_zero() {
    let s = setup();
    let d = s.stack.side;
    let w = s.input.w;
    // Bulk: at least 3 w (exp(-9) of a wall's boundary term) from walls, floor and surface.
    let xs = linspace(3.0 * w, s.stack.silo_width() - 3.0 * w, 5);
    let ys = linspace(3.0 * w, s.stack.rows as f64 * d - 3.0 * w, 9);
    let centre = grid_points(&xs, &ys);
    // Central differences, step w/50: truncation error ~ (h/w)^2 / 6 ~ 7e-5 relative.
    let h = w / 50.0;
    let shifted = |dx: f64, dy: f64| -> Vec<[f64; 2]> {
        centre.iter().map(|p| [p[0] + dx, p[1] + dy]).collect()
    };
    let sxp = stress_at(&s.list, &shifted(h, 0.0), &s.input);
    let sxm = stress_at(&s.list, &shifted(-h, 0.0), &s.input);
    let syp = stress_at(&s.list, &shifted(0.0, h), &s.input);
    let sym = stress_at(&s.list, &shifted(0.0, -h), &s.input);
    let rho = density_at(&s.centres, &s.masses, &centre, &s.input);
    let g = s.stack.gravity;
    for k in 0..centre.len() {
        // (div sigma)_a = d_x sigma_ax + d_y sigma_ay; components [xx, xy, yx, yy].
        let div_x = (sxp[k][0] - sxm[k][0]) / (2.0 * h) + (syp[k][1] - sym[k][1]) / (2.0 * h);
        let div_y = (sxp[k][2] - sxm[k][2]) / (2.0 * h) + (syp[k][3] - sym[k][3]) / (2.0 * h);
        let rho_g = rho[k] * g;
        // gravity (0, -g): div sigma + rho g = 0 means div_y = rho g.
        assert!(
            div_x.abs() < 0.02 * rho_g,
            "at {:?}: div_x {div_x} vs rho g {rho_g}",
            centre[k]
        );
        assert!(
            (div_y - rho_g).abs() < 0.02 * rho_g,
            "at {:?}: div_y {div_y} vs rho g {rho_g}",
            centre[k]
        );
    }
    // The test is not empty: the wall carries weight, the bulk is loaded.
    assert!(rho[0] > 0.0);
}

#[test]
fn integral_of_sigma_yy_plus_wall_friction_equals_weight_above() {
    let s = setup();
    let d = s.stack.side;
    let reach = s.input.cutoff * s.input.w;
    // The coarse-grained field spills beyond the walls by the kernel's reach; momentum balance
    // holds for the integral over the whole line. Trapezoid on a spacing of w/8 is exact to
    // ~exp(-(pi w / dx)^2) for a Gaussian-smoothed field.
    let dx = s.input.w / 8.0;
    let nx = ((s.stack.silo_width() + 2.0 * reach) / dx).ceil() as usize + 1;
    let xs = linspace(-reach, -reach + (nx - 1) as f64 * dx, nx);
    // Depths at row boundaries, in the part of the stack where rows are alike.
    for row in [12usize, 20, 28] {
        let y = row as f64 * d;
        let points: Vec<[f64; 2]> = xs.iter().map(|&x| [x, y]).collect();
        let stress = stress_at(&s.list, &points, &s.input);
        let integral: f64 = stress.iter().map(|s| s[3]).sum::<f64>() * dx;
        let weight_above = s.deposit.grains.iter().filter(|g| g.y > y).count() as f64 * s.weight;
        let friction_above: f64 = s
            .contacts
            .iter()
            .filter(|c| matches!(c.partner, Partner::Wall(_)) && c.point[1] > y)
            .map(|c| c.force[1])
            .sum();
        // The walls carry a share of the weight well above the 1 % tolerance (about 6 %).
        assert!(
            friction_above > 0.04 * weight_above,
            "walls must carry weight"
        );
        let balance = -integral + friction_above;
        assert!(
            (balance - weight_above).abs() < 0.01 * weight_above,
            "row {row}: -int sigma_yy {} + friction {friction_above} vs weight {weight_above}",
            -integral
        );
    }
}

#[test]
fn stress_does_not_depend_on_the_thread_count() {
    let s = setup();
    let xs = linspace(0.0, s.stack.silo_width(), 23);
    let ys = linspace(0.0, s.stack.rows as f64 * s.stack.side, 31);
    let points = grid_points(&xs, &ys);
    let run = |threads: usize| {
        rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .unwrap()
            .install(|| stress_at(&s.list, &points, &s.input))
    };
    assert_eq!(run(1), run(3));
}

/// The sample deposit read from its files gives the same field as the builder's network, and
/// its coarse-grained density in the bulk equals the areal density of the grains (the stack
/// fills its box completely).
#[test]
fn sample_deposit_field_from_files() {
    use facets::analysis::coarse_grain::compute;
    use facets::deposit::{LoadOptions, load_realisation};
    let path =
        std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("data-samples/deposits/stack.csv");
    let real = load_realisation(&path, &LoadOptions::default()).unwrap();
    let d = real.grain_width();
    // w = 1.5 D: the lattice's ripple in the density is ~4 exp(-pi^2 w^2 / D^2) = 1e-9.
    let input = CoarseGrainInput::new(1.5 * d);
    // Bulk of the 24 x 14 stack: at least the cut-off 4.5 w = 6.75 D from every side.
    let xs = linspace(7.0 * d, 17.0 * d, 5);
    let ys = [7.0 * d];
    let field = compute(&input, &real, grid_points(&xs, &ys)).unwrap();
    let rho = real.meta.areal_density(real.shape);
    for r in &field.density {
        assert!((r - rho).abs() < 1e-6 * rho, "{r} vs {rho}");
    }
    assert!(
        field.sigma.iter().all(|s| s[3] < 0.0 && s[0] < 0.0),
        "compressive"
    );
}

#[test]
fn grid_stress_does_not_depend_on_the_thread_count() {
    use facets::analysis::stress_grid::stress_on_grid;
    let s = setup();
    let xs = linspace(0.0, s.stack.silo_width(), 17);
    let ys = linspace(0.0, s.stack.rows as f64 * s.stack.side, 29);
    let run = |threads: usize| {
        rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .unwrap()
            .install(|| stress_on_grid(&s.list, &xs, &ys, &s.input))
    };
    assert_eq!(run(1), run(3));
}
