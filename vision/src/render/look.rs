//! Looks drawn at random: a [`Style`] and the JPEG quality of the photograph's file, drawn from a
//! seed over one of two documented ranges, so that a detector is judged over every photograph a
//! rig of that kind can give rather than on a few it could be tuned to.
//!
//! Every parameter is drawn independently and uniformly over its span (the sensor's full well
//! log-uniformly: it spans a decade). The reason for each span is in the comments of
//! [`LAB_LIKE`] and [`HARD`].

use std::io::Cursor;

use image::codecs::jpeg::JpegEncoder;
use image::{DynamicImage, ImageFormat};
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

use super::{Style, render};
use crate::{Frame, GrainOutline};

/// The kind of rig a look is drawn for.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum LookRange {
    /// What a careful lab rig gives: a diffused backlight in a dark room, a focused lens,
    /// exposure set near full scale, files stored losslessly or at the finest JPEG setting.
    LabLike,
    /// What a poor photograph gives: dim, uneven light, blur, noise, strong stray light, dirty
    /// glass and heavy compression.
    Hard,
}

impl LookRange {
    pub const ALL: [LookRange; 2] = [LookRange::LabLike, LookRange::Hard];

    /// The name the command line and the tables use.
    pub fn name(self) -> &'static str {
        match self {
            LookRange::LabLike => "lab-like",
            LookRange::Hard => "hard",
        }
    }

    /// The spans its looks are drawn from.
    pub fn spans(self) -> &'static Spans {
        match self {
            LookRange::LabLike => &LAB_LIKE,
            LookRange::Hard => &HARD,
        }
    }
}

impl std::str::FromStr for LookRange {
    type Err = String;
    fn from_str(s: &str) -> Result<Self, String> {
        LookRange::ALL
            .into_iter()
            .find(|r| r.name() == s)
            .ok_or_else(|| format!("unknown look range `{s}`: expected lab-like or hard"))
    }
}

/// A closed interval a parameter is drawn from.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Span {
    pub low: f64,
    pub high: f64,
}

const fn span(low: f64, high: f64) -> Span {
    Span { low, high }
}

impl Span {
    pub fn contains(&self, v: f64) -> bool {
        (self.low..=self.high).contains(&v)
    }

    fn uniform(&self, rng: &mut ChaCha8Rng) -> f64 {
        self.low + (self.high - self.low) * rng.random::<f64>()
    }

    fn log_uniform(&self, rng: &mut ChaCha8Rng) -> f64 {
        (self.low.ln() + (self.high.ln() - self.low.ln()) * rng.random::<f64>())
            .exp()
            .clamp(self.low, self.high)
    }
}

/// The spans of one look range, one per [`Style`] field (same names and units) and the file's.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Spans {
    pub field_level: Span,
    pub black_level: Span,
    pub grain_transmission: Span,
    pub rod_highlight: Span,
    pub rod_highlight_width: Span,
    pub vignetting: Span,
    pub gradient: Span,
    pub blur_px: Span,
    /// Drawn log-uniformly.
    pub full_well: Span,
    pub read_noise: Span,
    pub dust_per_cm2: Span,
    pub dust_radius_mm: Span,
    pub dust_opacity: Span,
    pub scratches_per_100cm2: Span,
    pub scratch_length_mm: Span,
    pub scratch_width_mm: Span,
    pub scratch_opacity: Span,
    pub bore_scale: Span,
    pub chamfer_mm: Span,
    pub chamfer_glint: Span,
    /// Chance that the file is lossless (16-bit), not a JPEG.
    pub lossless_chance: f64,
    /// JPEG quality (1-100) of the other files.
    pub jpeg_quality: [u8; 2],
}

/// A careful lab rig.
pub const LAB_LIKE: Spans = Spans {
    // Exposure set so the backlight sits at 65-92 % of full scale: headroom against clipping,
    // most of the sensor's range used.
    field_level: span(0.65, 0.92),
    // A sensor's dark offset.
    black_level: span(0.02, 0.06),
    // With the room dark, only flare and reflections off the front glass reach the sensor
    // through the grains' silhouettes: a few per cent of the field.
    grain_transmission: span(0.01, 0.08),
    // Steel cylinders reflect the room's light along a line on their axis; from none (a dark
    // room) to a quarter of the field.
    rod_highlight: span(0.0, 0.25),
    rod_highlight_width: span(0.08, 0.18),
    // An LED panel behind a diffuser is even to about 10 %, and a lens at a working aperture
    // loses 3-20 % at the corners of the frame.
    vignetting: span(0.03, 0.20),
    gradient: span(0.0, 0.15),
    // A focused lens at a moderate aperture plus demosaicing: about a pixel.
    blur_px: span(0.4, 1.2),
    // Machine-vision and reflex cameras at base sensitivity.
    full_well: span(8_000.0, 40_000.0),
    read_noise: span(0.001, 0.008),
    // Glass wiped before a run still collects some dust and keeps old scratches.
    dust_per_cm2: span(0.05, 0.5),
    dust_radius_mm: span(0.1, 0.3),
    dust_opacity: span(0.4, 0.8),
    scratches_per_100cm2: span(0.2, 1.5),
    scratch_length_mm: span(10.0, 30.0),
    scratch_width_mm: span(0.04, 0.1),
    scratch_opacity: span(0.1, 0.3),
    // An M4 thread's crests narrow the 3.3 mm bore's silhouette by a few per cent, and the
    // parallax of a lens that is not telecentric narrows it by up to 15 % at the frame's edge
    // (a 3 mm thick nut seen 0.25 rad off axis); tolerances open it by up to 5 %.
    bore_scale: span(0.85, 1.05),
    // A DIN 557 nut's bore is countersunk to about the thread's diameter (a ring up to 0.5 mm
    // wide), and little front light glints off it in a dark room.
    chamfer_mm: span(0.0, 0.5),
    chamfer_glint: span(0.0, 0.25),
    // Lab cameras store raw or lossless files, or JPEG at their finest setting.
    lossless_chance: 0.25,
    jpeg_quality: [88, 98],
};

/// A poor photograph.
pub const HARD: Spans = Spans {
    // Underexposed: a short exposure to freeze moving grains, or a dim panel.
    field_level: span(0.30, 0.70),
    black_level: span(0.04, 0.12),
    // Room lights on and reflections on the glass: grains grey, at 10-35 % of the field.
    grain_transmission: span(0.10, 0.35),
    // Room lights on: the rods' axis lines are bright.
    rod_highlight: span(0.15, 0.40),
    rod_highlight_width: span(0.10, 0.25),
    // A single lamp behind a sheet and a wide-angle lens close to the silo.
    vignetting: span(0.20, 0.50),
    gradient: span(0.15, 0.45),
    // Focus off by a little, a cheap lens, or grains moving during the exposure.
    blur_px: span(1.2, 2.5),
    // Small pixels (phones, webcams) at high sensitivity.
    full_well: span(2_000.0, 8_000.0),
    read_noise: span(0.01, 0.03),
    // Glass not wiped: dust and scratches everywhere.
    dust_per_cm2: span(0.5, 2.0),
    dust_radius_mm: span(0.2, 0.5),
    dust_opacity: span(0.6, 0.9),
    scratches_per_100cm2: span(1.0, 5.0),
    scratch_length_mm: span(20.0, 50.0),
    scratch_width_mm: span(0.08, 0.15),
    scratch_opacity: span(0.2, 0.4),
    // A strongly off-axis view (a lens close to the silo) narrows the bores by up to 30 %.
    bore_scale: span(0.70, 1.10),
    // Front light glinting off the countersinks.
    chamfer_mm: span(0.2, 0.7),
    chamfer_glint: span(0.2, 0.6),
    // Phone photographs and frames of compressed video.
    lossless_chance: 0.0,
    jpeg_quality: [55, 85],
};

/// A drawn look: the rendering style and how the photograph's file is stored.
#[derive(Clone, Debug, PartialEq)]
pub struct Look {
    pub style: Style,
    /// JPEG quality of the file, or none for a lossless 16-bit file.
    pub jpeg_quality: Option<u8>,
}

impl Look {
    /// The look of `seed` in `range`: the same seed and range give the same look, and one seed
    /// draws independent looks in the two ranges.
    pub fn draw(range: LookRange, seed: u64) -> Look {
        let mut rng = ChaCha8Rng::seed_from_u64(seed);
        rng.set_stream(match range {
            LookRange::LabLike => 1,
            LookRange::Hard => 2,
        });
        let s = range.spans();
        let mut u = |span: &Span| span.uniform(&mut rng);
        let style = Style {
            field_level: u(&s.field_level),
            black_level: u(&s.black_level),
            grain_transmission: u(&s.grain_transmission),
            rod_highlight: u(&s.rod_highlight),
            rod_highlight_width: u(&s.rod_highlight_width),
            vignetting: u(&s.vignetting),
            gradient: u(&s.gradient),
            blur_px: u(&s.blur_px),
            full_well: 0.0,
            read_noise: u(&s.read_noise),
            dust_per_cm2: u(&s.dust_per_cm2),
            dust_radius_mm: u(&s.dust_radius_mm),
            dust_opacity: u(&s.dust_opacity),
            scratches_per_100cm2: u(&s.scratches_per_100cm2),
            scratch_length_mm: u(&s.scratch_length_mm),
            scratch_width_mm: u(&s.scratch_width_mm),
            scratch_opacity: u(&s.scratch_opacity),
            bore_scale: u(&s.bore_scale),
            chamfer_mm: u(&s.chamfer_mm),
            chamfer_glint: u(&s.chamfer_glint),
        };
        let style = Style {
            full_well: s.full_well.log_uniform(&mut rng),
            ..style
        };
        let lossless = rng.random::<f64>() < s.lossless_chance;
        let [q0, q1] = s.jpeg_quality;
        let jpeg_quality = (!lossless).then(|| rng.random_range(q0..=q1));
        Look {
            style,
            jpeg_quality,
        }
    }

    /// The photograph of `grains` over `frame` as its file gives it back: rendered (noise,
    /// dust and light of `seed`), then stored as a 16-bit image or through a JPEG encoding
    /// and decoding at the look's quality.
    pub fn photograph(
        &self,
        grains: &[GrainOutline],
        frame: &Frame,
        seed: u64,
    ) -> Result<DynamicImage, image::ImageError> {
        let rendered = render(grains, frame, &self.style, seed);
        let Some(quality) = self.jpeg_quality else {
            return Ok(rendered.to_image(16));
        };
        let mut file = Vec::new();
        JpegEncoder::new_with_quality(&mut file, quality).encode_image(&rendered.to_luma8())?;
        image::load(Cursor::new(file), ImageFormat::Jpeg)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn within(look: &Look, s: &Spans) -> Vec<&'static str> {
        let st = &look.style;
        let checks = [
            ("field_level", s.field_level.contains(st.field_level)),
            ("black_level", s.black_level.contains(st.black_level)),
            (
                "grain_transmission",
                s.grain_transmission.contains(st.grain_transmission),
            ),
            ("rod_highlight", s.rod_highlight.contains(st.rod_highlight)),
            (
                "rod_highlight_width",
                s.rod_highlight_width.contains(st.rod_highlight_width),
            ),
            ("vignetting", s.vignetting.contains(st.vignetting)),
            ("gradient", s.gradient.contains(st.gradient)),
            ("blur_px", s.blur_px.contains(st.blur_px)),
            ("full_well", s.full_well.contains(st.full_well)),
            ("read_noise", s.read_noise.contains(st.read_noise)),
            ("dust_per_cm2", s.dust_per_cm2.contains(st.dust_per_cm2)),
            (
                "dust_radius_mm",
                s.dust_radius_mm.contains(st.dust_radius_mm),
            ),
            ("dust_opacity", s.dust_opacity.contains(st.dust_opacity)),
            (
                "scratches_per_100cm2",
                s.scratches_per_100cm2.contains(st.scratches_per_100cm2),
            ),
            (
                "scratch_length_mm",
                s.scratch_length_mm.contains(st.scratch_length_mm),
            ),
            (
                "scratch_width_mm",
                s.scratch_width_mm.contains(st.scratch_width_mm),
            ),
            (
                "scratch_opacity",
                s.scratch_opacity.contains(st.scratch_opacity),
            ),
            ("bore_scale", s.bore_scale.contains(st.bore_scale)),
            ("chamfer_mm", s.chamfer_mm.contains(st.chamfer_mm)),
            ("chamfer_glint", s.chamfer_glint.contains(st.chamfer_glint)),
            (
                "jpeg_quality",
                look.jpeg_quality
                    .is_none_or(|q| (s.jpeg_quality[0]..=s.jpeg_quality[1]).contains(&q))
                    && (look.jpeg_quality.is_some() || s.lossless_chance > 0.0),
            ),
        ];
        checks
            .into_iter()
            .filter(|(_, ok)| !ok)
            .map(|(name, _)| name)
            .collect()
    }

    #[test]
    fn looks_stay_in_their_ranges_and_cover_them() {
        for range in LookRange::ALL {
            let looks: Vec<Look> = (0..400).map(|seed| Look::draw(range, seed)).collect();
            for (seed, look) in looks.iter().enumerate() {
                let out = within(look, range.spans());
                assert!(
                    out.is_empty(),
                    "{range:?} seed {seed}: {out:?} out of range"
                );
            }
            // Uniform draws reach both ends of a span: 400 draws all miss its lowest (or
            // highest) 5 % with a chance of 0.95^400, about 1e-9.
            let blur = range.spans().blur_px;
            let width = blur.high - blur.low;
            let (lo, hi) = looks.iter().fold((f64::MAX, f64::MIN), |(a, b), l| {
                (a.min(l.style.blur_px), b.max(l.style.blur_px))
            });
            assert!(lo < blur.low + 0.05 * width && hi > blur.high - 0.05 * width);
            let lossless = looks.iter().filter(|l| l.jpeg_quality.is_none()).count();
            let expected = range.spans().lossless_chance * looks.len() as f64;
            assert!((lossless as f64 - expected).abs() <= 4.0 * expected.sqrt() + 1e-9);
        }
    }

    #[test]
    fn a_seed_gives_one_look_per_range() {
        for range in LookRange::ALL {
            assert_eq!(Look::draw(range, 7), Look::draw(range, 7));
            assert_ne!(Look::draw(range, 7), Look::draw(range, 8));
        }
        assert_ne!(
            Look::draw(LookRange::LabLike, 7).style.blur_px,
            Look::draw(LookRange::Hard, 7).style.blur_px
        );
        for range in LookRange::ALL {
            assert_eq!(range.name().parse::<LookRange>(), Ok(range));
        }
        assert!("lab".parse::<LookRange>().unwrap_err().contains("lab-like"));
    }

    #[test]
    fn a_jpeg_look_gives_back_an_eight_bit_photograph_near_the_render() {
        let frame = Frame {
            width: 0.02,
            height: 0.02,
            scale: 10e3,
        };
        let nut = GrainOutline {
            x: 0.01,
            y: 0.01,
            theta: 0.3,
            shape: crate::GrainShape::nut(6.9e-3),
        };
        let mut look = Look::draw(LookRange::LabLike, 3);
        look.jpeg_quality = Some(60);
        let photo = look.photograph(&[nut], &frame, 1).unwrap();
        assert!(matches!(photo, DynamicImage::ImageLuma8(_)));
        let exact = render(&[nut], &frame, &look.style, 1).to_luma8();
        let compressed = photo.to_luma8();
        assert_eq!(compressed.dimensions(), exact.dimensions());
        let mean_error = exact
            .pixels()
            .zip(compressed.pixels())
            .map(|(a, b)| f64::from(a.0[0].abs_diff(b.0[0])))
            .sum::<f64>()
            / f64::from(exact.width() * exact.height());
        // Quality 60 keeps the picture (a few levels of 255 on average) but changes it.
        assert!(mean_error > 0.0 && mean_error < 8.0, "{mean_error}");
        look.jpeg_quality = None;
        assert!(matches!(
            look.photograph(&[nut], &frame, 1).unwrap(),
            DynamicImage::ImageLuma16(_)
        ));
    }
}
