//! The study's findings F1-F5 (issue 53) as checks on the cases' means and standard errors,
//! each with its criterion stated. A difference counts when it exceeds twice its standard
//! error, sqrt(SE_a^2 + SE_b^2) (the cases' seeds are independent).

use super::measures::{Q, STUDY_ROD53_ANGLE_DEG};
use super::results::CaseStats;
use super::study::Study;
use crate::analysis::stats::MeanErr;
use crate::grains::GrainKind;

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Verdict {
    Reproduced,
    NotReproduced,
    /// A case or a quantity the check needs is absent.
    NotMeasured,
}

impl Verdict {
    pub fn text(self) -> &'static str {
        match self {
            Verdict::Reproduced => "reproduced",
            Verdict::NotReproduced => "not reproduced",
            Verdict::NotMeasured => "not measured",
        }
    }

    fn of(pass: Option<bool>) -> Verdict {
        match pass {
            Some(true) => Verdict::Reproduced,
            Some(false) => Verdict::NotReproduced,
            None => Verdict::NotMeasured,
        }
    }
}

/// One check of a finding: its criterion, the numbers it read and its verdict.
#[derive(Clone, Debug)]
pub struct Check {
    pub criterion: String,
    pub evidence: String,
    pub verdict: Verdict,
}

/// A finding of the study, the cases its table shows and its checks.
#[derive(Clone, Debug)]
pub struct Finding {
    pub id: &'static str,
    pub title: &'static str,
    pub study_says: &'static str,
    /// The (shape, phi0) rows of its table, whether measured or not.
    pub rows: Vec<(GrainKind, f64)>,
    pub columns: Vec<Q>,
    pub checks: Vec<Check>,
}

impl Finding {
    /// Not reproduced when a check fails; reproduced when every check passes; else not
    /// measured.
    pub fn verdict(&self) -> Verdict {
        if self
            .checks
            .iter()
            .any(|c| c.verdict == Verdict::NotReproduced)
        {
            Verdict::NotReproduced
        } else if self.checks.iter().all(|c| c.verdict == Verdict::Reproduced) {
            Verdict::Reproduced
        } else {
            Verdict::NotMeasured
        }
    }
}

const SQUARE_PHI0: [f64; 4] = [0.01, 0.05, 0.25, 0.47];
const ROD3_PHI0: [f64; 2] = [0.04, 0.25];
const ROD53_PHI0: [f64; 1] = [0.04];

/// The measured baseline case (not a variant) of this shape and phi0, if the study has one.
pub fn find<'a>(
    study: &Study,
    stats: &'a [CaseStats],
    shape: GrainKind,
    phi0: f64,
) -> Option<&'a CaseStats> {
    stats.iter().find(|s| {
        let case = &study.cases[s.case];
        !case.is_variant()
            && s.seeds_measured > 0
            && s.shape == Some(shape)
            && (case.scene.feed.phi0 - phi0).abs() < 1e-9
    })
}

pub fn mean_err(m: MeanErr) -> String {
    if m.mean.is_finite() {
        format!("{} +- {}", short(m.mean), short(m.stderr))
    } else {
        "n/a".into()
    }
}

/// Three significant digits, at most three decimals.
pub fn short(x: f64) -> String {
    let a = x.abs();
    if a >= 100.0 {
        format!("{x:.0}")
    } else if a >= 10.0 {
        format!("{x:.1}")
    } else if a >= 1.0 {
        format!("{x:.2}")
    } else {
        format!("{x:.3}")
    }
}

fn finite(m: MeanErr) -> Option<MeanErr> {
    m.mean.is_finite().then_some(m)
}

/// a exceeds b by more than 2 SE of the difference.
fn exceeds(a: MeanErr, b: MeanErr) -> Option<bool> {
    let (a, b) = (finite(a)?, finite(b)?);
    Some(a.mean - b.mean > 2.0 * a.stderr.hypot(b.stderr))
}

/// a is above t by more than 2 SE.
fn above(a: MeanErr, t: f64) -> Option<bool> {
    let a = finite(a)?;
    Some(a.mean - 2.0 * a.stderr > t)
}

fn label(shape: GrainKind, phi0: f64) -> String {
    format!("{} {phi0}", shape.display_name())
}

struct Ctx<'a> {
    study: &'a Study,
    stats: &'a [CaseStats],
}

impl Ctx<'_> {
    fn get(&self, shape: GrainKind, phi0: f64, q: Q) -> Option<MeanErr> {
        find(self.study, self.stats, shape, phi0).and_then(|s| finite(s.get(q)))
    }

    /// `a(shape, pa).q` exceeds `b(shape, pb).q` by more than 2 SE.
    fn compare(&self, criterion: &str, q: Q, a: (GrainKind, f64), b: (GrainKind, f64)) -> Check {
        let (ma, mb) = (self.get(a.0, a.1, q), self.get(b.0, b.1, q));
        let evidence = format!(
            "{} {}: {} against {}: {}",
            q.label(),
            label(a.0, a.1),
            ma.map_or("not measured".into(), mean_err),
            label(b.0, b.1),
            mb.map_or("not measured".into(), mean_err)
        );
        let pass = match (ma, mb) {
            (Some(x), Some(y)) => exceeds(x, y),
            _ => None,
        };
        Check {
            criterion: criterion.into(),
            evidence,
            verdict: Verdict::of(pass),
        }
    }

    /// `test` holds in every measured case of `shape` among `phi0s`; not measured when no
    /// case gives the quantities.
    fn every(
        &self,
        criterion: &str,
        shape: GrainKind,
        phi0s: &[f64],
        qs: &[Q],
        test: &dyn Fn(&CaseStats) -> Option<bool>,
    ) -> Check {
        let mut parts = Vec::new();
        let mut results = Vec::new();
        for &phi0 in phi0s {
            let Some(s) = find(self.study, self.stats, shape, phi0) else {
                continue;
            };
            let values: Vec<String> = qs
                .iter()
                .map(|&q| format!("{} {}", q.label(), mean_err(s.get(q))))
                .collect();
            parts.push(format!("{}: {}", label(shape, phi0), values.join(", ")));
            results.push(test(s));
        }
        let measured: Vec<bool> = results.iter().flatten().copied().collect();
        let pass = if measured.is_empty() {
            None
        } else {
            Some(measured.iter().all(|&p| p))
        };
        Check {
            criterion: criterion.into(),
            evidence: if parts.is_empty() {
                "no case measured".into()
            } else {
                parts.join("; ")
            },
            verdict: Verdict::of(pass),
        }
    }
}

fn rows(shape: GrainKind, phi0s: &[f64]) -> Vec<(GrainKind, f64)> {
    phi0s.iter().map(|&p| (shape, p)).collect()
}

/// Every finding, checked on the study's baseline cases.
pub fn findings(study: &Study, stats: &[CaseStats]) -> Vec<Finding> {
    let c = Ctx { study, stats };
    let sq = GrainKind::Square;
    let (long, short_rod) = (GrainKind::LongRod, GrainKind::ShortRod);
    let peak = |s: &CaseStats, qs: &[Q]| -> Option<bool> {
        let mut all = true;
        for &q in qs {
            all &= above(s.get(q), 1.0)?;
        }
        Some(all)
    };
    let f1 = Finding {
        id: "F1",
        title: "squares: 45-degree alignment against the feed",
        study_says: "Strong 45-degree alignment at phi0 = 0.01, weaker as phi0 grows, more flat squares; at phi0 = 0.47 the tendency reverses somewhat.",
        rows: rows(sq, &SQUARE_PHI0),
        columns: vec![Q::DiagonalShare, Q::FlatShare, Q::PackingFraction],
        checks: vec![
            c.every(
                "strong alignment at phi0 = 0.01: the share within 10 deg of 45 deg above 0.5 by more than 2 SE (isotropic: 0.22)",
                sq,
                &[0.01],
                &[Q::DiagonalShare],
                &|s| above(s.get(Q::DiagonalShare), 0.5),
            ),
            c.compare(
                "weaker as phi0 grows: the 45-degree share at 0.01 exceeds that at 0.25 by more than 2 SE",
                Q::DiagonalShare,
                (sq, 0.01),
                (sq, 0.25),
            ),
            c.compare(
                "more flat squares: the share within 10 deg of 0 or 90 deg at 0.25 exceeds that at 0.01 by more than 2 SE",
                Q::FlatShare,
                (sq, 0.25),
                (sq, 0.01),
            ),
            c.compare(
                "the tendency reverses somewhat at 0.47: the 45-degree share at 0.47 exceeds that at 0.25 by more than 2 SE",
                Q::DiagonalShare,
                (sq, 0.47),
                (sq, 0.25),
            ),
        ],
    };
    let f2 = Finding {
        id: "F2",
        title: "squares: g(r) and g(1) against the feed",
        study_says: "g(r) peaks at 1, 2, 3 and none at sqrt 2; a small face-vertex peak near 1.18-1.21 at the two highest phi0; g(1) falls with phi0 up to about 0.2 and then rises again.",
        rows: rows(sq, &SQUARE_PHI0),
        columns: vec![Q::G1, Q::GSqrt2, Q::G2, Q::G3, Q::GFaceVertex],
        checks: vec![
            c.every(
                "peaks at 1, 2 and 3: g above 1 by more than 2 SE at each, in every squares case",
                sq,
                &SQUARE_PHI0,
                &[Q::G1, Q::G2, Q::G3],
                &|s| peak(s, &[Q::G1, Q::G2, Q::G3]),
            ),
            c.every(
                "none at sqrt 2: g(sqrt 2) not above 1 by more than 2 SE, in every squares case",
                sq,
                &SQUARE_PHI0,
                &[Q::GSqrt2],
                &|s| above(s.get(Q::GSqrt2), 1.0).map(|a| !a),
            ),
            c.compare(
                "a face-vertex peak at 0.25: the largest g over 1.15-1.25 at 0.25 exceeds that at 0.01 by more than 2 SE",
                Q::GFaceVertex,
                (sq, 0.25),
                (sq, 0.01),
            ),
            c.compare(
                "a face-vertex peak at 0.47: the largest g over 1.15-1.25 at 0.47 exceeds that at 0.01 by more than 2 SE",
                Q::GFaceVertex,
                (sq, 0.47),
                (sq, 0.01),
            ),
            c.compare(
                "g(1) falls with phi0 up to about 0.2: g(1) at 0.01 exceeds g(1) at 0.25 by more than 2 SE",
                Q::G1,
                (sq, 0.01),
                (sq, 0.25),
            ),
            c.compare(
                "and then rises again: g(1) at 0.47 exceeds g(1) at 0.25 by more than 2 SE",
                Q::G1,
                (sq, 0.47),
                (sq, 0.25),
            ),
        ],
    };
    let f3 = Finding {
        id: "F3",
        title: "long rods: horizontal, integer peaks",
        study_says: "Horizontal preferred, vertical least likely, g(r) peaks at integers (r = 3 above r = 2), a slight rise of horizontal rods with phi0.",
        rows: rows(long, &ROD3_PHI0),
        columns: vec![
            Q::HorizontalShare,
            Q::VerticalShare,
            Q::PreferredAngle,
            Q::G1,
            Q::G2,
            Q::G3,
        ],
        checks: vec![
            c.every(
                "horizontal preferred: the mode of f(theta) (5-degree bins, angle from the horizontal) below 10 deg within 2 SE, in every long-rod case",
                long,
                &ROD3_PHI0,
                &[Q::PreferredAngle],
                &|s| finite(s.get(Q::PreferredAngle)).map(|m| m.mean - 2.0 * m.stderr < 10.0),
            ),
            c.every(
                "vertical least likely: the share within 10 deg of vertical below the isotropic 1/9 by more than 2 SE and below the horizontal share by more than 2 SE, in every long-rod case",
                long,
                &ROD3_PHI0,
                &[Q::VerticalShare, Q::HorizontalShare],
                &|s| {
                    let v = finite(s.get(Q::VerticalShare))?;
                    Some(v.mean + 2.0 * v.stderr < 1.0 / 9.0 && exceeds(s.get(Q::HorizontalShare), v)?)
                },
            ),
            c.every(
                "peaks at the integers: g above 1 by more than 2 SE at 1, 2 and 3, in every long-rod case",
                long,
                &ROD3_PHI0,
                &[Q::G1, Q::G2, Q::G3],
                &|s| peak(s, &[Q::G1, Q::G2, Q::G3]),
            ),
            c.every(
                "r = 3 above r = 2: g(3) exceeds g(2) by more than 2 SE, in every long-rod case",
                long,
                &ROD3_PHI0,
                &[Q::G2, Q::G3],
                &|s| exceeds(s.get(Q::G3), s.get(Q::G2)),
            ),
            c.compare(
                "a slight rise of horizontal rods with phi0: the horizontal share at 0.25 exceeds that at 0.04 by more than 2 SE",
                Q::HorizontalShare,
                (long, 0.25),
                (long, 0.04),
            ),
        ],
    };
    let f4 = Finding {
        id: "F4",
        title: "short rods: the 2 pi/11 angle and the 1.31 peak",
        study_says: "Preferred angle about 2 pi / 11, vertical least likely, another minimum at horizontal; g(r) peaks at 1, 1.31 (long face on short face), 1.63, 2.31, 2.62.",
        rows: rows(short_rod, &ROD53_PHI0),
        columns: vec![
            Q::PreferredAngle,
            Q::Near2Pi11Share,
            Q::HorizontalShare,
            Q::VerticalShare,
            Q::G1,
            Q::G131,
            Q::G14,
            Q::G163,
            Q::G231,
            Q::G262,
        ],
        checks: vec![
            c.every(
                &format!(
                    "preferred angle about 2 pi/11 = {STUDY_ROD53_ANGLE_DEG:.1} deg: the mode of f(theta) (angle from the horizontal) within 2 SE + 2.5 deg (half a bin) of it"
                ),
                short_rod,
                &ROD53_PHI0,
                &[Q::PreferredAngle],
                &|s| {
                    finite(s.get(Q::PreferredAngle))
                        .map(|m| (m.mean - STUDY_ROD53_ANGLE_DEG).abs() < 2.0 * m.stderr + 2.5)
                },
            ),
            c.every(
                "vertical least likely: the share within 10 deg of vertical below the horizontal share by more than 2 SE",
                short_rod,
                &ROD53_PHI0,
                &[Q::VerticalShare, Q::HorizontalShare],
                &|s| exceeds(s.get(Q::HorizontalShare), s.get(Q::VerticalShare)),
            ),
            c.every(
                "another minimum at horizontal: the horizontal share below the share within 10 deg of 2 pi/11 by more than 2 SE",
                short_rod,
                &ROD53_PHI0,
                &[Q::HorizontalShare, Q::Near2Pi11Share],
                &|s| exceeds(s.get(Q::Near2Pi11Share), s.get(Q::HorizontalShare)),
            ),
            c.every(
                "the long-face-on-short-face peak at 1.31 rather than 1.4: g(1.31) exceeds g(1.4) by more than 2 SE",
                short_rod,
                &ROD53_PHI0,
                &[Q::G131, Q::G14],
                &|s| exceeds(s.get(Q::G131), s.get(Q::G14)),
            ),
            c.every(
                "peaks at 1, 1.63, 2.31, 2.62: g above 1 by more than 2 SE at each",
                short_rod,
                &ROD53_PHI0,
                &[Q::G1, Q::G163, Q::G231, Q::G262],
                &|s| peak(s, &[Q::G1, Q::G163, Q::G231, Q::G262]),
            ),
        ],
    };
    let mut f5_rows = rows(sq, &SQUARE_PHI0);
    f5_rows.extend(rows(long, &ROD3_PHI0));
    f5_rows.extend(rows(short_rod, &ROD53_PHI0));
    let f5 = Finding {
        id: "F5",
        title: "stress transmission: Janssen saturation against the overburden",
        study_says: "Pressure (trace of the Goldhirsch stress, w = 4 D squares, 3 D rods, centre line, against h/W): slow-fed squares saturate quickly; faster feeds approach the overburden; long rods close to overburden with little feed dependence; at the highest feeds the pressure can exceed the overburden.",
        rows: f5_rows,
        columns: vec![
            Q::WallsShare,
            Q::FloorShare,
            Q::JanssenLambda,
            Q::JanssenPSat,
            Q::JanssenSaturates,
            Q::POverOverburden1,
            Q::POverOverburden15,
            Q::POverOverburden2,
        ],
        checks: vec![
            c.every(
                "slow-fed squares saturate quickly: at phi0 = 0.01 every seed's Janssen fit saturates, lambda/W below 1 within 2 SE, and the walls carry more than 0.4 of the weight (a Janssen silo with lambda ~ W filled 2.7 W deep puts about 0.6 there)",
                sq,
                &[0.01],
                &[Q::JanssenSaturates, Q::JanssenLambda, Q::WallsShare],
                &|s| {
                    let saturates = finite(s.get(Q::JanssenSaturates))?;
                    let lambda = finite(s.get(Q::JanssenLambda))?;
                    let walls = finite(s.get(Q::WallsShare))?;
                    Some(
                        saturates.mean == 1.0
                            && lambda.mean - 2.0 * lambda.stderr < 1.0
                            && walls.mean > 0.4,
                    )
                },
            ),
            c.compare(
                "faster feeds approach the overburden: P/overburden at h = 2 W at phi0 = 0.47 exceeds that at 0.01 by more than 2 SE",
                Q::POverOverburden2,
                (sq, 0.47),
                (sq, 0.01),
            ),
            c.every(
                "long rods close to the overburden: P/overburden at h = 2 W at least 0.85, in every long-rod case",
                long,
                &ROD3_PHI0,
                &[Q::POverOverburden2],
                &|s| finite(s.get(Q::POverOverburden2)).map(|m| m.mean >= 0.85),
            ),
            {
                let (a, b) = (
                    c.get(long, 0.04, Q::POverOverburden2),
                    c.get(long, 0.25, Q::POverOverburden2),
                );
                Check {
                    criterion: "with little feed dependence: P/overburden at h = 2 W of long rods at 0.04 and 0.25 differ by less than 0.1".into(),
                    evidence: format!(
                        "{}: {}, {}: {}",
                        label(long, 0.04),
                        a.map_or("not measured".into(), mean_err),
                        label(long, 0.25),
                        b.map_or("not measured".into(), mean_err)
                    ),
                    verdict: Verdict::of(a.zip(b).map(|(a, b)| (a.mean - b.mean).abs() < 0.1)),
                }
            },
            c.every(
                "at the highest feeds the pressure can exceed the overburden: P/overburden at h = W, 1.5 W or 2 W of squares at 0.47 above 1 by more than 2 SE",
                sq,
                &[0.47],
                &[Q::POverOverburden1, Q::POverOverburden15, Q::POverOverburden2],
                &|s| {
                    let mut any = None;
                    for q in [Q::POverOverburden1, Q::POverOverburden15, Q::POverOverburden2] {
                        if let Some(a) = above(s.get(q), 1.0) {
                            any = Some(any.unwrap_or(false) || a);
                        }
                    }
                    any
                },
            ),
        ],
    };
    vec![f1, f2, f3, f4, f5]
}
