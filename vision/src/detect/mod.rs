//! Shape-aware grain detector for backlit photographs of dense deposits.
//!
//! Grains touch face to face with no visible gap, so dark regions cannot be split by
//! thresholds or watersheds. Instead the detector knows the grain's outline and fits it:
//!
//! 0. `levels`: a frame without both a bright background and dark grains apart by more than
//!    its noise (black, white, saturated, uniform) is no backlit photograph: no grains, and a
//!    warning saying why;
//! 1. `normalise`: divide out the uneven backlight, map to a darkness in [0, 1];
//! 2. `scale`: check the stated scale against the sizes the photograph shows (a warning by
//!    default, see [`ScaleCheck`]);
//! 3. `seeds`: candidate positions: nuts' holes (exact centre cues), rods' axis highlights
//!    (`ridges`: a point on the axis and its direction), then the deepest points of the dark
//!    area not yet explained by accepted grains;
//! 4. `fit`: per candidate, a coarse search over angle and position of the rendered model
//!    (`model`) on a downsampled darkness, then sub-pixel, sub-degree refinement;
//! 5. `accept`: greedy acceptance, best fits first, each accepted grain marking its pixels as
//!    explained so touching grains separate and duplicates are refused; repeated while new
//!    seeds in unexplained dark area yield grains;
//! 6. `chains`: rows of rods touching end to end that were fitted shifted along the row
//!    (a stub of unexplained dark area at each end) are refitted with one rod more; where a
//!    seed failed beside unexplained dark area, a neighbouring rod is refitted together with a
//!    rod at the seed (a rod crowded out by its neighbour); a rod fitted across rods lying
//!    at right angles to it (their remainder unexplained beside it) is refitted as those rods;
//!    and a rod accepted with a low agreement is fitted afresh over every angle;
//! 7. `settle`: every rod refined again against its neighbours where they ended up (a grain
//!    accepted before its neighbours leaned into their darkness);
//! 8. `relax` (when [`DetectParams::relax`]): every pose relaxed jointly, image misfit plus
//!    a cost for overlapping outlines, with the jumps that undo a grain turned or slipped in
//!    place, and deaths and births of grains.
//!
//! Photographs above [`TILE_PIXELS`] go through steps 1-8 tile by tile, so memory stays
//! bounded whatever their size.

mod accept;
mod chains;
mod fit;
mod levels;
mod model;
mod nearby;
mod normalise;
mod phases;
mod plane;
mod regions;
mod relax;
mod ridges;
mod scale;
mod seeds;
mod settle;
mod taps;
#[cfg(test)]
mod testing;

use image::{DynamicImage, GenericImageView};

use crate::{GrainOutline, GrainShape};

pub use model::Pose;
pub use phases::Phases;
pub use scale::ScaleCheck;

/// Largest photograph accepted, in pixels: its decoded pixels alone take 0.5-1 GB (8 or 16
/// bits), and a deposit photograph has no reason to be larger.
pub const MAX_PIXELS: u64 = 500_000_000;

/// Photographs larger than this (pixels) are processed in overlapping tiles of about this
/// size: the detector holds several f32 planes of what it works on (about 40 bytes a pixel),
/// so a tile bounds its memory at about 0.7 GB whatever the photograph's size.
pub const TILE_PIXELS: u64 = 16_000_000;

/// What the detector needs to know about the photograph.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct DetectParams {
    /// The outline of the grains in the photograph.
    pub shape: GrainShape,
    /// Pixels per metre.
    pub scale: f64,
    /// Fits whose agreement with the photograph is below this are refused (in [0, 1]).
    pub min_confidence: f64,
    /// Grains cut by the frame are kept when at least this fraction of their area is visible.
    pub min_visible: f64,
    /// Rounds of "look for unexplained dark area and add grains there".
    pub max_rounds: usize,
    /// Sweeps of settling at the end: every grain refined again against its neighbours where
    /// they ended up ([`settle::SWEEPS`] for rods; none for nuts, see `DetectParams::new`).
    pub settle_sweeps: usize,
    /// Distinct coarse poses of each fit refined at full resolution, the best of them kept
    /// (at least one). Fewer is faster and less accurate (docs/results/detector-bench.md, "Speed against accuracy").
    pub finalists: usize,
    /// Rods: after the rounds and the rows' repair, the repairs of the other mistakes the
    /// greedy acceptance makes (rods turned across their neighbours, left out, crowded or
    /// fitted outside the frame). Without them faster and less accurate (README, "Speed
    /// against accuracy").
    pub repairs: bool,
    /// Relax every pose jointly after the acceptance (the `relax` stage): grains turned or
    /// slipped into their neighbours are moved back, duplicates removed and grains missed
    /// added, each only where the whole frame's misfit plus overlap falls.
    pub relax: bool,
    /// What to do with a scale that disagrees with the sizes measured in the photograph.
    pub scale_check: ScaleCheck,
    /// Largest photograph accepted, in pixels.
    pub max_pixels: u64,
    /// Photographs with more pixels are processed in overlapping tiles of about this size.
    pub tile_pixels: u64,
}

impl DetectParams {
    pub fn new(shape: GrainShape, scale: f64) -> Self {
        DetectParams {
            shape,
            scale,
            min_confidence: 0.5,
            min_visible: 0.25,
            max_rounds: 40,
            // Nuts are refined against their neighbours where they ended up by the
            // relaxation, which nudges every grain; settling them first would do it twice
            // (docs/results/detector-bench.md).
            settle_sweeps: match shape {
                GrainShape::Rod { .. } => settle::SWEEPS,
                GrainShape::Square { .. } => 0,
            },
            finalists: fit::FINALISTS,
            repairs: true,
            // Relaxation turns back the nuts fitted turned in gap-free lattices, which nothing
            // else can; the rods' turned and slipped fits it leaves as the repairs left them,
            // at several seconds a frame (docs/results/detector-bench.md, "Joint relaxation").
            relax: matches!(shape, GrainShape::Square { .. }),
            scale_check: ScaleCheck::default(),
            max_pixels: MAX_PIXELS,
            tile_pixels: TILE_PIXELS,
        }
    }
}

/// What the detector may leave out to go faster, each at a cost in accuracy that the README
/// measures ("Speed against accuracy"); the default leaves out nothing.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Shortcuts {
    /// Finalists refined a fit, instead of [`DetectParams::finalists`]' three.
    pub finalists: Option<usize>,
    /// Sweeps of settling, instead of the shape's default.
    pub settle_sweeps: Option<usize>,
    /// Leave out the rods' repairs but the rows'.
    pub no_repairs: bool,
    /// Leave out the joint relaxation (`DetectParams::relax`).
    pub no_relax: bool,
}

impl Shortcuts {
    /// The parameters with these shortcuts taken.
    pub fn apply(&self, mut params: DetectParams) -> DetectParams {
        if let Some(n) = self.finalists {
            params.finalists = n;
        }
        if let Some(n) = self.settle_sweeps {
            params.settle_sweeps = n;
        }
        params.repairs &= !self.no_repairs;
        params.relax &= !self.no_relax;
        params
    }
}

impl Default for DetectParams {
    /// The experiment's nuts at 10 px/mm.
    fn default() -> Self {
        DetectParams::new(GrainShape::nut(6.9e-3), 1e4)
    }
}

/// One detected grain.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Detection {
    /// Centre and angle in the frame (metres, origin bottom-left, y up), theta folded into
    /// [0, symmetry period).
    pub outline: GrainOutline,
    /// Agreement of the fitted model with the photograph, in [0, 1].
    pub confidence: f64,
    /// The outline crosses the edge of the photograph.
    pub cut: bool,
}

#[derive(Debug, thiserror::Error)]
pub enum DetectError {
    #[error("invalid detector parameters: {0}")]
    InvalidParams(String),
    #[error(
        "the stated scale {given_px_per_mm:.2} px/mm (--px-per-mm) is implausible for these \
         grains: {what} suggests about {measured_px_per_mm:.2} px/mm; check --px-per-mm and \
         --shape, or give --scale-check warn (or off) to detect at the stated scale"
    )]
    ImplausibleScale {
        given_px_per_mm: f64,
        measured_px_per_mm: f64,
        what: &'static str,
    },
    #[error(
        "the photograph is {width} x {height} px ({mpx:.0} megapixels); the detector accepts at \
         most {limit_mpx:.0} megapixels (it works on larger ones in tiles, but their decoded \
         pixels alone would not fit in memory): split it into overlapping parts"
    )]
    TooLarge {
        width: u32,
        height: u32,
        mpx: f64,
        limit_mpx: f64,
    },
}

/// Finds every grain in a backlit photograph. Grains whose centre lies outside the
/// photograph are not reported; grains whose outline crosses its edge are reported with
/// `cut = true`.
pub fn detect(image: &DynamicImage, params: &DetectParams) -> Result<Vec<Detection>, DetectError> {
    detect_report(image, params).map(|r| r.grains)
}

/// What [`detect_report`] found in one photograph.
#[derive(Clone, Debug, Default)]
pub struct Report {
    pub grains: Vec<Detection>,
    /// Fraction of the photograph's dark pixels that the outlines found explain (by at least
    /// half), in [0, 1]; `None` when the photograph has next to no dark area. Below
    /// [`WELL_EXPLAINED`], the grains in the photograph are likely not the ones asked for.
    pub explained: Option<f64>,
    /// Wall time of each step of the detector (tiles added up).
    pub phases: Phases,
    /// What the user should know of this photograph: why it has no grains (`levels`), a
    /// scale that disagrees with the one measured.
    pub warnings: Vec<String>,
}

/// Below this fraction of the dark pixels explained, the outline asked for likely does not
/// match the grains in the photograph. The benchmark's photographs (both packings, every
/// style, 6 and 10 px/mm, seed 3) with the right outline: nuts 0.95-0.99, rods 0.905-0.986
/// (hard at 6 px/mm lowest); 4.9 mm rods sought as 8.9 mm ones 0.78-0.83, nuts sought as
/// rods 0.66-0.68: the threshold lies half-way between 0.83 and 0.905. 8.9 mm rods sought as
/// 4.9 mm ones are cut in two and explained 0.83-0.95: a fraction cannot tell those.
pub const WELL_EXPLAINED: f64 = 0.87;

/// [`detect`], and how much of the photograph's darkness the grains found explain.
pub fn detect_report(image: &DynamicImage, params: &DetectParams) -> Result<Report, DetectError> {
    validate(params)?;
    let (width, height) = image.dimensions();
    let pixels = width as u64 * height as u64;
    if pixels > params.max_pixels {
        return Err(DetectError::TooLarge {
            width,
            height,
            mpx: pixels as f64 / 1e6,
            limit_mpx: params.max_pixels as f64 / 1e6,
        });
    }
    let width_px = params.shape.width() * params.scale;
    if pixels > 0 && width_px > f64::from(width.max(height)) {
        return Err(DetectError::InvalidParams(format!(
            "at {:.2} px/mm (--px-per-mm) a grain is {width_px:.0} px wide, wider than the \
             photograph ({width} x {height} px)",
            params.scale * 1e-3
        )));
    }
    let mut phases = Phases::default();
    let mut warnings = Vec::new();
    let mut laps = phases::Laps::new(&mut phases);
    let unusable = levels::Levels::of(image).and_then(|l| l.unusable());
    laps.lap("levels");
    if pixels == 0 || unusable.is_some() {
        warnings.extend(unusable.map(|why| format!("no grains: {why}")));
        return Ok(Report {
            grains: Vec::new(),
            explained: None,
            phases,
            warnings,
        });
    }
    let (found, dark_area) = if pixels > params.tile_pixels {
        find_in_tiles(image, params, &mut phases, &mut warnings)?
    } else {
        find(
            image,
            params,
            [0, 0, width, height],
            &mut phases,
            (params.scale_check, &mut warnings),
        )?
    };
    let grains = found
        .into_iter()
        .filter_map(|found| to_detection(found, params, width, height))
        .collect();
    Ok(Report {
        grains,
        explained: dark_area.explained(params),
        phases,
        warnings,
    })
}

/// Dark pixels (darker than half-way between field and grain) over a region of a
/// photograph, and those of them that no grain found explains by half. Pixels, not summed
/// darkness: the field's faint remaining darkness (noise, dust) over a sparse photograph would
/// outweigh what the grains leave.
#[derive(Clone, Copy, Debug, Default)]
struct DarkArea {
    dark: u64,
    unexplained: u64,
}

impl DarkArea {
    fn add(self, other: DarkArea) -> DarkArea {
        DarkArea {
            dark: self.dark + other.dark,
            unexplained: self.unexplained + other.unexplained,
        }
    }

    /// `None` for dust at most ([`least_dark_px`]).
    fn explained(self, params: &DetectParams) -> Option<f64> {
        let dark = self.dark as f64;
        (dark >= least_dark_px(params)).then(|| 1.0 - self.unexplained as f64 / dark)
    }

    /// Over `region` ([x0, y0, x1, y1], pixels) of the darkness and the free darkness (the
    /// darkness times what is not explained).
    fn over(dark: &plane::Plane, free: &plane::Plane, region: [u32; 4]) -> DarkArea {
        let [x0, y0, x1, y1] = region.map(|v| v as usize);
        let mut area = DarkArea::default();
        for y in y0..y1.min(dark.height) {
            let row = y * dark.width;
            let (x0, x1) = (row + x0, row + x1.min(dark.width));
            for (&d, &f) in dark.data[x0..x1].iter().zip(&free.data[x0..x1]) {
                if d > 0.5 {
                    area.dark += 1;
                    area.unexplained += u64::from(f > 0.5 * d);
                }
            }
        }
        area
    }
}

/// Fewer dark pixels than a tenth of one grain's area: dust at most.
fn least_dark_px(params: &DetectParams) -> f64 {
    0.1 * params.shape.length() * params.shape.width() * params.scale.powi(2)
}

/// Tiles overlap by `margin` on each side of a core; a grain is kept by the tile whose core
/// holds its centre, so every grain is reported once, and a grain centred in a core lies whole
/// in that tile with its neighbours' outlines around it (the margin is 1.5 grain lengths,
/// more than the half-diagonal of a grain plus a neighbour's reach).
fn find_in_tiles(
    image: &DynamicImage,
    params: &DetectParams,
    phases: &mut Phases,
    warnings: &mut Vec<String>,
) -> Result<(Vec<accept::Found>, DarkArea), DetectError> {
    let (width, height) = image.dimensions();
    let length_px = params.shape.length() * params.scale;
    let margin = (1.5 * length_px).ceil() as u32 + 8;
    let side = ((params.tile_pixels as f64).sqrt() as u32).max(4 * margin);
    let core = side - 2 * margin;
    let crop = |x0: u32, y0: u32| {
        let (tx0, ty0) = (x0.saturating_sub(margin), y0.saturating_sub(margin));
        let tx1 = (x0 + core + margin).min(width);
        let ty1 = (y0 + core + margin).min(height);
        (tx0, ty0, image.crop_imm(tx0, ty0, tx1 - tx0, ty1 - ty0))
    };
    let corners = || {
        (0..height)
            .step_by(core as usize)
            .flat_map(move |y0| (0..width).step_by(core as usize).map(move |x0| (x0, y0)))
    };
    // The scale is the photograph's: a tile at the deposit's edge may hold only slivers of
    // the grains it cuts, whose thickness says nothing of it (a block of 8.9 mm rods at 10
    // px/mm measured 1.7 px/mm in its corner tile, 10.5 in the other five; test
    // `the_report_times_each_step_of_the_pipeline`). So every tile measures, and the median
    // of their measurements is checked, before any is searched.
    if params.scale_check != ScaleCheck::Off {
        let mut laps = phases::Laps::new(phases);
        let mut measured: Vec<f64> = corners()
            .filter_map(|(x0, y0)| measured_in(&crop(x0, y0).2, params))
            .collect();
        measured.sort_by(f64::total_cmp);
        if let Some(&m) = measured.get(measured.len() / 2) {
            warnings.extend(scale::judge(
                params.shape,
                params.scale,
                m,
                params.scale_check,
            )?);
        }
        laps.lap("scale and holes");
    }
    let mut all = Vec::new();
    let mut dark_area = DarkArea::default();
    for (x0, y0) in corners() {
        let (tx0, ty0, tile) = crop(x0, y0);
        let (cx1, cy1) = (f64::from(x0 + core), f64::from(y0 + core));
        // The tile's core, in the tile's pixels: each pixel is counted once. A tile of
        // bare field, normalised on its own, may show spurious darkness where the whole
        // photograph shows none: a tile without grains is not counted.
        let core_in_tile = [x0 - tx0, y0 - ty0, x0 + core - tx0, y0 + core - ty0];
        let no_check = (ScaleCheck::Off, &mut Vec::new());
        let (found, in_core) = find(&tile, params, core_in_tile, phases, no_check)?;
        if !found.is_empty() {
            dark_area = dark_area.add(in_core);
        }
        for mut g in found {
            let (dx, dy) = (f64::from(tx0), f64::from(ty0));
            g.pose.x += dx;
            g.pose.y += dy;
            g.corners = g.corners.map(|(c, r)| (c + dx, r + dy));
            let (x, y) = (g.pose.x, g.pose.y);
            if x >= f64::from(x0) && x < cx1 && y >= f64::from(y0) && y < cy1 {
                all.push(g);
            }
        }
    }
    Ok((all, dark_area))
}

/// The grains of one photograph (or tile), in its pixels, and the darkness over `region`
/// ([x0, y0, x1, y1], pixels) and what of it they leave unexplained; each step's time added
/// to `phases`; the scale checked against what the photograph shows as `scale_check` says, its
/// warning added to the list.
fn find(
    image: &DynamicImage,
    params: &DetectParams,
    region: [u32; 4],
    phases: &mut Phases,
    (scale_check, warnings): (ScaleCheck, &mut Vec<String>),
) -> Result<(Vec<accept::Found>, DarkArea), DetectError> {
    let mut laps = phases::Laps::new(phases);
    let (width, height) = image.dimensions();
    let pixels = width as u64 * height as u64;
    let dark = darkness_of(image, params);
    laps.lap("normalise");
    // Nothing to find, and nothing to tell of what is explained: no tile without grains is
    // counted, and a whole photograph this bare has no fraction.
    if dark.dark_fraction * (pixels as f64) < least_dark_px(params) {
        return Ok((Vec::new(), DarkArea::default()));
    }
    let blobs = holes(params, &dark.plane);
    if scale_check != ScaleCheck::Off
        && let Some(measured) = scale::measured_scale(params.shape, &dark.plane, &blobs)
    {
        warnings.extend(scale::judge(
            params.shape,
            params.scale,
            measured,
            scale_check,
        )?);
    }
    laps.lap("scale and holes");
    let (mut found, mut free) = accept::find_grains(&dark.plane, &blobs, params, &mut laps);
    if params.relax {
        (found, free) = relax::relax(
            &dark.plane,
            found,
            params.shape,
            params.scale,
            params.min_confidence,
            params.min_visible,
        );
        laps.lap("relax");
    }
    let dark_area = DarkArea::over(&dark.plane, &free, region);
    laps.lap("explained");
    Ok((found, dark_area))
}

/// Most settling sweeps and finalists accepted: a bound so that a mistyped count cannot keep
/// the detector busy for hours (each sweep refits every grain) or ask for memory without end.
pub const MAX_SETTLE_SWEEPS: usize = 100;
pub const MAX_FINALISTS: usize = 100;

impl DetectParams {
    /// Checks every number, naming the parameter (and the `facets detect` option that sets
    /// it) and the range expected; [`detect_report`] refuses parameters that fail it.
    pub fn validate(&self) -> Result<(), DetectError> {
        validate(self)
    }
}

fn validate(params: &DetectParams) -> Result<(), DetectError> {
    let bad = |m: String| Err(DetectError::InvalidParams(m));
    if !(params.scale.is_finite() && params.scale > 0.0) {
        return bad(format!(
            "scale (--px-per-mm) is {} px/mm, expected a finite number above 0",
            params.scale * 1e-3
        ));
    }
    let (l, w) = (params.shape.length(), params.shape.width());
    if !(l.is_finite() && w.is_finite() && w > 0.0 && l >= w) {
        return bad(format!(
            "grain length {l} m and width {w} m: need length >= width > 0"
        ));
    }
    if let GrainShape::Square { hole_diameter, .. } = params.shape
        && !(hole_diameter >= 0.0 && hole_diameter < w)
    {
        return bad(format!(
            "hole diameter {hole_diameter} m must be in [0, side)"
        ));
    }
    let width_px = w * params.scale;
    if width_px < 5.0 {
        return bad(format!(
            "at {:.2} px/mm (--px-per-mm) a grain is only {width_px:.1} px wide; at least 5 px \
             are needed",
            params.scale * 1e-3
        ));
    }
    if !(0.0..=1.0).contains(&params.min_confidence) {
        return bad(format!(
            "min_confidence (--min-confidence) is {}, expected a number from 0 to 1",
            params.min_confidence
        ));
    }
    if !(0.0..=1.0).contains(&params.min_visible) {
        return bad(format!(
            "min_visible is {}, expected a fraction from 0 to 1",
            params.min_visible
        ));
    }
    if !(1..=MAX_FINALISTS).contains(&params.finalists) {
        return bad(format!(
            "finalists (--finalists) is {}, expected 1 to {MAX_FINALISTS}: a fit refines at \
             least its best coarse pose",
            params.finalists
        ));
    }
    if params.settle_sweeps > MAX_SETTLE_SWEEPS {
        return bad(format!(
            "settle_sweeps (--settle-sweeps) is {}, expected 0 to {MAX_SETTLE_SWEEPS}",
            params.settle_sweeps
        ));
    }
    Ok(())
}

/// The darkness of a photograph (or a tile), its backlight divided out over blocks of two
/// grain lengths.
fn darkness_of(image: &DynamicImage, params: &DetectParams) -> normalise::Darkness {
    let grey = normalise::grey_plane(image);
    let length_px = params.shape.length() * params.scale;
    normalise::darkness(&grey, (2.0 * length_px).round() as usize)
}

/// The scale measured in a photograph (or a tile) from the sizes it shows (pixels per metre),
/// if it shows grains enough.
fn measured_in(image: &DynamicImage, params: &DetectParams) -> Option<f64> {
    let dark = darkness_of(image, params);
    let (w, h) = image.dimensions();
    if dark.dark_fraction * f64::from(w) * f64::from(h) < least_dark_px(params) {
        return None;
    }
    scale::measured_scale(params.shape, &dark.plane, &holes(params, &dark.plane))
}

/// The bright blobs of a darkness that may be nuts' holes; only nuts use them (their
/// centres, and the scale from their size).
fn holes(params: &DetectParams, dark: &plane::Plane) -> Vec<seeds::BrightBlob> {
    match params.shape {
        GrainShape::Square { .. } => seeds::bright_blobs(dark),
        GrainShape::Rod { .. } => Vec::new(),
    }
}

fn to_detection(
    found: accept::Found,
    params: &DetectParams,
    width: u32,
    height: u32,
) -> Option<Detection> {
    let (w, h) = (width as f64, height as f64);
    let p = found.pose;
    if !(0.0..w).contains(&p.x) || !(0.0..h).contains(&p.y) {
        return None;
    }
    let cut = found
        .corners
        .iter()
        .any(|&(c, r)| c < 0.0 || r < 0.0 || c > w || r > h);
    let period = params.shape.symmetry_period();
    let theta = p.phi.rem_euclid(period);
    Some(Detection {
        outline: GrainOutline {
            x: p.x / params.scale,
            y: (h - p.y) / params.scale,
            theta: if theta >= period { 0.0 } else { theta },
            shape: params.shape,
        },
        confidence: found.confidence.clamp(0.0, 1.0),
        cut,
    })
}
