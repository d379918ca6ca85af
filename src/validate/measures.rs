//! What is measured on each realisation (one seed of one case): the quantities the study's
//! findings are judged on, with the conventions of `facets analyse` (the frame the run wrote,
//! less 40 mm at each side wall; stresses coarse-grained with w = 4 D for squares, 3 D for
//! rods, on the silo's centre line).

use std::f64::consts::{FRAC_PI_2, PI};
use std::path::Path;

use anyhow::Context;
use serde::{Deserialize, Serialize};

use super::study::AnalysisSection;
use crate::analysis::coarse_grain::{CoarseGrainInput, branches, stress_at};
use crate::analysis::load_share::{self, LoadShareInput};
use crate::analysis::pressure::{free_surface, janssen_fit, janssen_saturates};
use crate::analysis::rdf::{RdfInput, deposit_rdf};
use crate::analysis::summary::AnalysisParameters;
use crate::deposit::{LoadOptions, Realisation, fold_angle, load_realisation};
use crate::grains::GrainKind;

/// Half-width of the angular windows (around 45 degrees, flat, horizontal, vertical, 2 pi/11).
pub const WINDOW_DEG: f64 = 10.0;
/// The short rods' preferred angle in the study (degrees).
pub const STUDY_ROD53_ANGLE_DEG: f64 = 360.0 / 11.0;
/// Bin width of the histogram whose mode is the rods' preferred angle (degrees).
pub const MODE_BIN_DEG: f64 = 5.0;
/// Depths (h/W) of the pressure profile drawn in the report's figure.
pub const PROFILE_STEP_OVER_W: f64 = 0.05;
pub const PROFILE_POINTS: usize = 50;
/// Spacing of the points the Janssen fit uses, in grain widths (as `facets analyse`).
const FIT_STEP_OVER_D: f64 = 0.5;

/// One measured quantity. The order is the column order of results.csv.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Q {
    PackingFraction,
    FloorShare,
    LeftWallShare,
    RightWallShare,
    WallsShare,
    SupportOverWeight,
    DiagonalShare,
    FlatShare,
    HorizontalShare,
    VerticalShare,
    Near2Pi11Share,
    PreferredAngle,
    G1,
    G131,
    GSqrt2,
    G14,
    G163,
    G2,
    G231,
    G262,
    G3,
    GFaceVertex,
    JanssenLambda,
    JanssenPSat,
    JanssenSaturates,
    POverOverburden1,
    POverOverburden15,
    POverOverburden2,
}

impl Q {
    pub const ALL: [Q; 28] = [
        Q::PackingFraction,
        Q::FloorShare,
        Q::LeftWallShare,
        Q::RightWallShare,
        Q::WallsShare,
        Q::SupportOverWeight,
        Q::DiagonalShare,
        Q::FlatShare,
        Q::HorizontalShare,
        Q::VerticalShare,
        Q::Near2Pi11Share,
        Q::PreferredAngle,
        Q::G1,
        Q::G131,
        Q::GSqrt2,
        Q::G14,
        Q::G163,
        Q::G2,
        Q::G231,
        Q::G262,
        Q::G3,
        Q::GFaceVertex,
        Q::JanssenLambda,
        Q::JanssenPSat,
        Q::JanssenSaturates,
        Q::POverOverburden1,
        Q::POverOverburden15,
        Q::POverOverburden2,
    ];

    pub fn index(self) -> usize {
        self as usize
    }

    /// The column name in results.csv and results.json.
    pub fn name(self) -> &'static str {
        match self {
            Q::PackingFraction => "packing_fraction",
            Q::FloorShare => "floor_share",
            Q::LeftWallShare => "left_wall_share",
            Q::RightWallShare => "right_wall_share",
            Q::WallsShare => "walls_share",
            Q::SupportOverWeight => "support_over_weight",
            Q::DiagonalShare => "diagonal_share",
            Q::FlatShare => "flat_share",
            Q::HorizontalShare => "horizontal_share",
            Q::VerticalShare => "vertical_share",
            Q::Near2Pi11Share => "near_2pi_11_share",
            Q::PreferredAngle => "preferred_angle_deg",
            Q::G1 => "g_1",
            Q::G131 => "g_1.31",
            Q::GSqrt2 => "g_sqrt2",
            Q::G14 => "g_1.4",
            Q::G163 => "g_1.63",
            Q::G2 => "g_2",
            Q::G231 => "g_2.31",
            Q::G262 => "g_2.62",
            Q::G3 => "g_3",
            Q::GFaceVertex => "g_max_1.15_1.25",
            Q::JanssenLambda => "janssen_lambda_over_w",
            Q::JanssenPSat => "janssen_p_sat_N_m",
            Q::JanssenSaturates => "janssen_saturates",
            Q::POverOverburden1 => "p_over_overburden_h1",
            Q::POverOverburden15 => "p_over_overburden_h1.5",
            Q::POverOverburden2 => "p_over_overburden_h2",
        }
    }

    /// How the report's tables head the quantity.
    pub fn label(self) -> &'static str {
        match self {
            Q::PackingFraction => "phi_f",
            Q::FloorShare => "floor",
            Q::LeftWallShare => "left wall",
            Q::RightWallShare => "right wall",
            Q::WallsShare => "walls",
            Q::SupportOverWeight => "support/weight",
            Q::DiagonalShare => "45 deg +-10",
            Q::FlatShare => "flat +-10",
            Q::HorizontalShare => "horizontal +-10",
            Q::VerticalShare => "vertical +-10",
            Q::Near2Pi11Share => "2pi/11 +-10",
            Q::PreferredAngle => "mode (deg)",
            Q::G1 => "g(1)",
            Q::G131 => "g(1.31)",
            Q::GSqrt2 => "g(sqrt 2)",
            Q::G14 => "g(1.4)",
            Q::G163 => "g(1.63)",
            Q::G2 => "g(2)",
            Q::G231 => "g(2.31)",
            Q::G262 => "g(2.62)",
            Q::G3 => "g(3)",
            Q::GFaceVertex => "max g(1.15-1.25)",
            Q::JanssenLambda => "lambda/W",
            Q::JanssenPSat => "P_sat (N/m)",
            Q::JanssenSaturates => "saturates",
            Q::POverOverburden1 => "P/ob h=W",
            Q::POverOverburden15 => "P/ob h=1.5W",
            Q::POverOverburden2 => "P/ob h=2W",
        }
    }

    /// Whether the quantity is measured for grains of this shape.
    pub fn applies(self, shape: GrainKind) -> bool {
        let square = shape == GrainKind::Square;
        match self {
            Q::DiagonalShare | Q::FlatShare | Q::GSqrt2 | Q::GFaceVertex => square,
            Q::HorizontalShare | Q::VerticalShare | Q::Near2Pi11Share | Q::PreferredAngle => {
                !square
            }
            Q::G131 | Q::G14 | Q::G163 | Q::G231 | Q::G262 => shape == GrainKind::ShortRod,
            _ => true,
        }
    }

    /// The distance (D) at which a g(r) quantity is read.
    fn rdf_distance(self) -> Option<f64> {
        Some(match self {
            Q::G1 => 1.0,
            Q::G131 => 1.31,
            Q::GSqrt2 => 2f64.sqrt(),
            Q::G14 => 1.4,
            Q::G163 => 1.63,
            Q::G2 => 2.0,
            Q::G231 => 2.31,
            Q::G262 => 2.62,
            Q::G3 => 3.0,
            _ => return None,
        })
    }
}

/// The measures of one realisation: a value per [`Q`] (NaN where it does not apply or could
/// not be measured) and P / overburden at h = k [`PROFILE_STEP_OVER_W`] W, k = 1..
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Measures {
    pub values: Vec<f64>,
    pub profile: Vec<f64>,
}

impl Measures {
    pub fn get(&self, q: Q) -> f64 {
        self.values[q.index()]
    }
}

/// Measures the run in `dir` (its deposit.csv with sidecars, as `fill` writes them).
pub fn measure(dir: &Path, analysis: &AnalysisSection) -> anyhow::Result<Measures> {
    let table = dir.join("deposit.csv");
    let real = load_realisation(&table, &LoadOptions::default())?;
    measure_realisation(&real, analysis).with_context(|| format!("measuring {}", table.display()))
}

/// Measures one realisation (it needs its contacts).
pub fn measure_realisation(
    real: &Realisation,
    analysis: &AnalysisSection,
) -> anyhow::Result<Measures> {
    let mut v = vec![f64::NAN; Q::ALL.len()];
    let contacts = real
        .contacts
        .as_deref()
        .context("no contact table: the load shares and the stress need one")?;
    let area = real.analysed_area()?;
    v[Q::PackingFraction.index()] = area.packing_fraction(&real.deposit);

    let g = real.meta.gravity();
    let weight: f64 = real.masses().iter().sum::<f64>() * g;
    let shares = load_share::compute(&LoadShareInput {
        contacts,
        weight_n: weight,
    })?;
    v[Q::FloorShare.index()] = shares.floor;
    v[Q::LeftWallShare.index()] = shares.left_wall;
    v[Q::RightWallShare.index()] = shares.right_wall;
    v[Q::WallsShare.index()] = shares.walls;
    v[Q::SupportOverWeight.index()] = shares.support_over_weight;

    let thetas: Vec<f64> = area.grains(&real.deposit).map(|g| g.theta).collect();
    orientation(real.shape, &thetas, &mut v);

    let d = real.grain_width();
    let input = RdfInput {
        dr: analysis.rdf_bin_over_d,
        r_max: 4.0,
        margin: analysis.rdf_margin_over_d,
    };
    let points: Vec<[f64; 2]> = real.deposit.grains.iter().map(|g| [g.x, g.y]).collect();
    if let Some(rdf) = deposit_rdf(&points, &area, d, &input) {
        let at = |r: f64| {
            let k = (r / input.dr).round() as usize;
            rdf.g.get(k.wrapping_sub(1)).copied().unwrap_or(f64::NAN)
        };
        for q in Q::ALL {
            if let Some(r) = q.rdf_distance() {
                v[q.index()] = at(r);
            }
        }
        v[Q::GFaceVertex.index()] = rdf
            .r
            .iter()
            .zip(&rdf.g)
            .filter(|(r, _)| (1.15 - 1e-9..=1.25 + 1e-9).contains(*r))
            .map(|(_, g)| *g)
            .fold(f64::NAN, f64::max);
    }

    let profile = pressure(real, contacts, &mut v)?;
    for q in Q::ALL {
        if !q.applies(real.shape) {
            v[q.index()] = f64::NAN;
        }
    }
    Ok(Measures { values: v, profile })
}

/// Shares of the grains in the angular windows, and the rods' preferred angle.
fn orientation(shape: GrainKind, thetas: &[f64], v: &mut [f64]) {
    if thetas.is_empty() {
        return;
    }
    let n = thetas.len() as f64;
    let window = WINDOW_DEG.to_radians();
    let share =
        |inside: &dyn Fn(f64) -> bool| thetas.iter().filter(|&&t| inside(t)).count() as f64 / n;
    if shape == GrainKind::Square {
        let folded = |t: f64| fold_angle(t, FRAC_PI_2);
        v[Q::DiagonalShare.index()] = share(&|t| (folded(t) - FRAC_PI_2 / 2.0).abs() <= window);
        v[Q::FlatShare.index()] = share(&|t| {
            let f = folded(t);
            f <= window || f >= FRAC_PI_2 - window
        });
        return;
    }
    // A rod at theta looks like one at pi - theta in a mirror: the study's f(theta) is
    // symmetric, so angles are measured from the horizontal, 0 to pi/2.
    let from_horizontal = |t: f64| {
        let f = fold_angle(t, PI);
        f.min(PI - f)
    };
    v[Q::HorizontalShare.index()] = share(&|t| from_horizontal(t) <= window);
    v[Q::VerticalShare.index()] = share(&|t| from_horizontal(t) >= FRAC_PI_2 - window);
    let preferred = STUDY_ROD53_ANGLE_DEG.to_radians();
    v[Q::Near2Pi11Share.index()] = share(&|t| (from_horizontal(t) - preferred).abs() <= window);
    let bins = (90.0 / MODE_BIN_DEG).round() as usize;
    let mut counts = vec![0usize; bins];
    for &t in thetas {
        let k = (from_horizontal(t).to_degrees() / MODE_BIN_DEG) as usize;
        counts[k.min(bins - 1)] += 1;
    }
    // The first of equal bins: the fold makes the count of a bin exact, not a float.
    let mode = (0..bins).fold(0, |best, k| if counts[k] > counts[best] { k } else { best });
    v[Q::PreferredAngle.index()] = (mode as f64 + 0.5) * MODE_BIN_DEG;
}

/// The Janssen fit of P = -trace / 2 on the centre line, P over the overburden at h = W,
/// 1.5 W and 2 W, and the profile for the figure. Depths within 2 w of the floor are left
/// out: the kernel reaches below the floor there, where there are no grains.
fn pressure(
    real: &Realisation,
    contacts: &[crate::deposit::Contact],
    v: &mut [f64],
) -> anyhow::Result<Vec<f64>> {
    let d = real.grain_width();
    let w = AnalysisParameters::default().w_over_d_for(real.shape) * d;
    let cg = CoarseGrainInput::new(w);
    let silo_width = real.meta.silo_width();
    let x_c = 0.5 * silo_width;
    let surface = free_surface(real, x_c, w);
    let deepest = surface - 2.0 * w;
    let mut profile = vec![f64::NAN; PROFILE_POINTS];
    if !(deepest.is_finite() && deepest > 0.0) {
        return Ok(profile);
    }
    let branches = branches(&real.deposit, contacts);
    let pressure_at = |hs: &[f64]| -> Vec<f64> {
        let points: Vec<[f64; 2]> = hs.iter().map(|h| [x_c, surface - h]).collect();
        stress_at(&branches, &points, &cg)
            .iter()
            .map(|s| -0.5 * (s[0] + s[3]))
            .collect()
    };
    let dh = FIT_STEP_OVER_D * d;
    let fit_h: Vec<f64> = (0..)
        .map(|k| k as f64 * dh)
        .take_while(|&h| h <= deepest)
        .collect();
    if fit_h.len() >= 4 {
        let fit = janssen_fit(&fit_h, &pressure_at(&fit_h), silo_width);
        v[Q::JanssenLambda.index()] = fit.lambda_over_w;
        v[Q::JanssenPSat.index()] = fit.p_sat;
        v[Q::JanssenSaturates.index()] = if janssen_saturates(fit.lambda_over_w) {
            1.0
        } else {
            0.0
        };
    }
    // The overburden of a column of the analysed area's packing fraction.
    let area = real.analysed_area()?;
    let rho_g = area.packing_fraction(&real.deposit)
        * real.meta.areal_density(real.shape)
        * real.meta.gravity();
    let hs: Vec<f64> = (1..=PROFILE_POINTS)
        .map(|k| k as f64 * PROFILE_STEP_OVER_W * silo_width)
        .take_while(|&h| h <= deepest)
        .collect();
    for (k, (p, h)) in pressure_at(&hs).iter().zip(&hs).enumerate() {
        profile[k] = p / (rho_g * h);
    }
    let at = |h_over_w: f64| {
        let k = (h_over_w / PROFILE_STEP_OVER_W).round() as usize;
        profile[k - 1]
    };
    v[Q::POverOverburden1.index()] = at(1.0);
    v[Q::POverOverburden15.index()] = at(1.5);
    v[Q::POverOverburden2.index()] = at(2.0);
    Ok(profile)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn quantities_are_listed_once_in_their_order() {
        for (k, q) in Q::ALL.iter().enumerate() {
            assert_eq!(q.index(), k);
        }
        let mut names: Vec<&str> = Q::ALL.iter().map(|q| q.name()).collect();
        names.sort();
        names.dedup();
        assert_eq!(names.len(), Q::ALL.len());
    }

    fn stack_realisation(stack: &crate::deposit::SquareStack) -> Realisation {
        let (deposit, contacts, meta) = stack.build(0.05);
        Realisation {
            name: "stack".into(),
            deposit,
            contacts: Some(contacts),
            meta,
            shape: GrainKind::Square,
        }
    }

    #[test]
    fn a_stack_of_columns_has_half_the_overburden_as_pressure_and_the_walls_their_friction() {
        use crate::deposit::SquareStack;
        // Columns carrying only their own weight: sigma_yy = -rho g h, sigma_xx = 0, so
        // P = -trace/2 is half the overburden at every depth, and the profile never saturates.
        let columns = SquareStack {
            columns: 16,
            rows: 60,
            lateral: 0.0,
            wall_friction: 0.0,
            ..SquareStack::default()
        };
        let m =
            measure_realisation(&stack_realisation(&columns), &AnalysisSection::default()).unwrap();
        for q in [
            Q::POverOverburden1,
            Q::POverOverburden15,
            Q::POverOverburden2,
        ] {
            assert!((m.get(q) - 0.5).abs() < 0.005, "{}: {}", q.name(), m.get(q));
        }
        assert_eq!(m.get(Q::JanssenSaturates), 0.0);
        assert_eq!(m.get(Q::FloorShare), 1.0);
        assert!((m.get(Q::PackingFraction) - 1.0).abs() < 1e-9);
        assert_eq!((m.get(Q::FlatShare), m.get(Q::DiagonalShare)), (1.0, 0.0));
        assert!(
            m.get(Q::PreferredAngle).is_nan(),
            "a rod quantity on squares"
        );
        // Walls squeezing the rows and holding mu_w of that by friction: their share of the
        // weight is the sum of those frictions.
        let squeezed = SquareStack {
            columns: 16,
            rows: 60,
            ..SquareStack::default()
        };
        let weight = squeezed.grain_mass() * squeezed.gravity * (16.0 * 60.0);
        let held: f64 = (0..60)
            .map(|r| 2.0 * squeezed.wall_friction * squeezed.wall_normal(r))
            .sum();
        let m = measure_realisation(&stack_realisation(&squeezed), &AnalysisSection::default())
            .unwrap();
        assert!((m.get(Q::WallsShare) - held / weight).abs() < 1e-12);
        assert!((m.get(Q::LeftWallShare) - m.get(Q::RightWallShare)).abs() < 1e-12);
        assert!((m.get(Q::SupportOverWeight) - 1.0).abs() < 1e-12);
    }

    #[test]
    fn angular_windows_and_the_mode() {
        let mut v = vec![f64::NAN; Q::ALL.len()];
        // Squares: two at 45 degrees, one flat (at 88 = -2), one at 20 (neither).
        let deg = |d: f64| d.to_radians();
        orientation(
            GrainKind::Square,
            &[deg(45.0), deg(50.0), deg(88.0), deg(20.0)],
            &mut v,
        );
        assert_eq!(v[Q::DiagonalShare.index()], 0.5);
        assert_eq!(v[Q::FlatShare.index()], 0.25);
        // Rods: 150 degrees is 30 from the horizontal; 95 is vertical; 5 and 178 horizontal.
        let rods = [
            deg(150.0),
            deg(31.0),
            deg(33.0),
            deg(95.0),
            deg(5.0),
            deg(178.0),
        ];
        orientation(GrainKind::LongRod, &rods, &mut v);
        assert_eq!(v[Q::HorizontalShare.index()], 2.0 / 6.0);
        assert_eq!(v[Q::VerticalShare.index()], 1.0 / 6.0);
        assert_eq!(v[Q::Near2Pi11Share.index()], 3.0 / 6.0);
        assert_eq!(v[Q::PreferredAngle.index()], 32.5);
    }
}
