//! How a photograph looks: light, optics, sensor, glass and the nuts' bores, as one struct with
//! three presets (`look` draws it at random instead).

/// Rendering style. Levels are fractions of the sensor's full scale; sizes on the glass are in
/// millimetres; optical blur is in pixels (it belongs to the lens and sensor, not the deposit).
#[derive(Clone, Debug, PartialEq)]
pub struct Style {
    /// Sensor level of an empty, evenly lit field at the frame centre.
    pub field_level: f64,
    /// Sensor level with no light at all (dark offset).
    pub black_level: f64,
    /// Fraction of the local backlight that still reaches the sensor through a grain (stray
    /// light, flare): 0 gives black grains, larger values lower the contrast.
    pub grain_transmission: f64,
    /// Brightness of the line of front light reflected along a rod's axis, as a fraction of the
    /// local field (0 for none).
    pub rod_highlight: f64,
    /// Width (standard deviation) of that highlight, as a fraction of the rod's width D.
    pub rod_highlight_width: f64,
    /// Relative backlight lost at the frame corners (radial falloff from the centre).
    pub vignetting: f64,
    /// Relative change of the backlight from one side of the frame to the other, along a
    /// direction drawn from the seed.
    pub gradient: f64,
    /// Lens blur: standard deviation of the Gaussian point spread, in pixels (0 for none).
    pub blur_px: f64,
    /// Photo-electrons collected at full scale (shot noise grows as the square root of the
    /// signal); 0 for no shot noise.
    pub full_well: f64,
    /// Standard deviation of the read noise, as a fraction of full scale.
    pub read_noise: f64,
    /// Dust specks on the glass per square centimetre of frame.
    pub dust_per_cm2: f64,
    /// Largest dust speck radius (mm); radii are drawn between a fifth of this and this.
    pub dust_radius_mm: f64,
    /// How much light the densest dust speck blocks (0..1).
    pub dust_opacity: f64,
    /// Scratches on the glass per 100 square centimetres of frame.
    pub scratches_per_100cm2: f64,
    /// Longest scratch (mm); lengths are drawn between a tenth of this and this.
    pub scratch_length_mm: f64,
    /// Scratch width (mm).
    pub scratch_width_mm: f64,
    /// How much light a scratch scatters away (0..1).
    pub scratch_opacity: f64,
    /// Diameter of the light a nut's bore lets through, as a fraction of the nominal bore
    /// (`GrainShape::Square::hole_diameter`): below 1 where thread crests or the parallax of a
    /// lens that is not telecentric narrow it, above 1 for a bore worn or drilled out.
    pub bore_scale: f64,
    /// Width of the chamfer around a nut's bore (mm), seen as a grey ring where front or stray
    /// light glints off its slope (0 for none).
    pub chamfer_mm: f64,
    /// Brightness of that ring, as a fraction of the local field (0..1).
    pub chamfer_glint: f64,
}

impl Style {
    /// Even light, sharp lens, little noise, a few specks.
    pub fn clean() -> Self {
        Style {
            field_level: 0.88,
            black_level: 0.03,
            grain_transmission: 0.02,
            rod_highlight: 0.10,
            rod_highlight_width: 0.12,
            vignetting: 0.05,
            gradient: 0.03,
            blur_px: 0.5,
            full_well: 40_000.0,
            read_noise: 0.002,
            dust_per_cm2: 0.05,
            dust_radius_mm: 0.15,
            dust_opacity: 0.5,
            scratches_per_100cm2: 0.2,
            scratch_length_mm: 15.0,
            scratch_width_mm: 0.05,
            scratch_opacity: 0.15,
            bore_scale: 1.0,
            chamfer_mm: 0.0,
            chamfer_glint: 0.0,
        }
    }

    /// What a careful lab rig gives: uneven backlight, some blur, visible noise, dust and
    /// scratches.
    pub fn lab() -> Self {
        Style {
            field_level: 0.80,
            black_level: 0.04,
            grain_transmission: 0.05,
            rod_highlight: 0.15,
            rod_highlight_width: 0.12,
            vignetting: 0.18,
            gradient: 0.12,
            blur_px: 0.9,
            full_well: 15_000.0,
            read_noise: 0.006,
            dust_per_cm2: 0.3,
            dust_radius_mm: 0.25,
            dust_opacity: 0.7,
            scratches_per_100cm2: 1.0,
            scratch_length_mm: 25.0,
            scratch_width_mm: 0.08,
            scratch_opacity: 0.25,
            bore_scale: 1.0,
            chamfer_mm: 0.0,
            chamfer_glint: 0.0,
        }
    }

    /// A poor photograph: strong blur, low contrast, heavy noise, dirty glass.
    pub fn hard() -> Self {
        Style {
            field_level: 0.60,
            black_level: 0.08,
            grain_transmission: 0.30,
            rod_highlight: 0.25,
            rod_highlight_width: 0.15,
            vignetting: 0.35,
            gradient: 0.25,
            blur_px: 1.8,
            full_well: 4_000.0,
            read_noise: 0.02,
            dust_per_cm2: 1.0,
            dust_radius_mm: 0.4,
            dust_opacity: 0.8,
            scratches_per_100cm2: 3.0,
            scratch_length_mm: 40.0,
            scratch_width_mm: 0.12,
            scratch_opacity: 0.35,
            bore_scale: 1.0,
            chamfer_mm: 0.0,
            chamfer_glint: 0.0,
        }
    }

    /// The preset of that name (clean, lab or hard).
    pub fn named(name: &str) -> Option<Self> {
        match name {
            "clean" => Some(Style::clean()),
            "lab" => Some(Style::lab()),
            "hard" => Some(Style::hard()),
            _ => None,
        }
    }
}
