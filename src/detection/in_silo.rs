//! Where a photograph lies in its silo: what its table's sidecar says (silo width, phi0,
//! frame), so that `facets analyse` reads the table without options.

use anyhow::bail;

use crate::deposit::{DepositMeta, FrameMm, Source};

/// How the photograph's frame in the silo is known.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Framing {
    /// The photograph's bottom-left corner in the silo (mm); its size is its pixels over the
    /// scale.
    Corner([f64; 2]),
    /// The frame stated (`--frame-mm`); the photograph must be of its size.
    Frame(FrameMm),
}

/// A photograph's place: the silo it shows and the rain that built the deposit.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct InSilo {
    pub silo_width_mm: f64,
    pub phi0: f64,
    pub framing: Framing,
}

/// The largest difference between a stated frame and the photograph's size: two pixels, or
/// one per cent of the side (a frame measured on the glass, a photograph cropped by a pixel).
const SIZE_TOLERANCE: f64 = 0.01;

impl InSilo {
    /// The sidecar of a photograph of `columns` x `rows` pixels at `px_per_mm`; refuses a
    /// stated frame of another size (naming `--frame-mm` and the photograph's size), and
    /// numbers out of range by their option (`--phi0`, `--silo-width-mm`, `--frame-mm`).
    pub fn meta(&self, columns: u32, rows: u32, px_per_mm: f64) -> anyhow::Result<DepositMeta> {
        let size = [columns as f64 / px_per_mm, rows as f64 / px_per_mm];
        let frame = match self.framing {
            Framing::Corner([x, y]) => FrameMm {
                x_min: x,
                x_max: x + size[0],
                y_min: y,
                y_max: y + size[1],
            },
            Framing::Frame(f) => {
                let stated = [f.width_mm(), f.height_mm()];
                let off = stated
                    .iter()
                    .zip(size)
                    .any(|(s, p)| (s - p).abs() > (2.0 / px_per_mm).max(SIZE_TOLERANCE * p));
                if off {
                    bail!(
                        "--frame-mm is {} x {} mm, but the photograph is {columns} x {rows} px, \
                         {:.1} x {:.1} mm at --px-per-mm {px_per_mm}: give the frame the \
                         photograph shows",
                        stated[0],
                        stated[1],
                        size[0],
                        size[1]
                    );
                }
                f
            }
        };
        let meta = DepositMeta {
            silo_width_mm: self.silo_width_mm,
            phi0: self.phi0,
            frame_mm: Some(frame),
            areal_density_kg_m2: None,
            gravity_m_s2: None,
            source: Source::Experiment,
        };
        meta.validate_options()?;
        Ok(meta)
    }

    /// Checks the numbers that do not depend on the photograph, before any is read.
    pub fn validate_options(&self) -> anyhow::Result<()> {
        let framing = match self.framing {
            Framing::Corner(c) => {
                if !c.iter().all(|v| v.is_finite()) {
                    bail!("the photograph's corner is {c:?} mm, expected finite numbers");
                }
                None
            }
            Framing::Frame(f) => Some(f),
        };
        DepositMeta {
            silo_width_mm: self.silo_width_mm,
            phi0: self.phi0,
            frame_mm: framing,
            areal_density_kg_m2: None,
            gravity_m_s2: None,
            source: Source::Experiment,
        }
        .validate_options()
    }

    /// The photograph's bottom-left corner in the silo (mm): what its table's coordinates are
    /// shifted by.
    pub fn corner(&self) -> [f64; 2] {
        match self.framing {
            Framing::Corner(c) => c,
            Framing::Frame(f) => [f.x_min, f.y_min],
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_stated_frame_must_be_the_photographs_size() {
        let at = |framing| InSilo {
            silo_width_mm: 160.0,
            phi0: 0.1,
            framing,
        };
        // 600 x 400 px at 10 px/mm: 60 x 40 mm.
        let meta = at(Framing::Corner([10.0, 290.0]))
            .meta(600, 400, 10.0)
            .unwrap();
        let f = meta.frame_mm.unwrap();
        assert_eq!(
            [f.x_min, f.x_max, f.y_min, f.y_max],
            [10.0, 70.0, 290.0, 330.0]
        );
        let stated = FrameMm {
            x_min: 10.0,
            x_max: 70.1,
            y_min: 290.0,
            y_max: 330.0,
        };
        assert_eq!(
            at(Framing::Frame(stated))
                .meta(600, 400, 10.0)
                .unwrap()
                .frame_mm,
            Some(stated)
        );
        let wide = FrameMm {
            x_max: 90.0,
            ..stated
        };
        let e = at(Framing::Frame(wide))
            .meta(600, 400, 10.0)
            .unwrap_err()
            .to_string();
        assert!(
            e.contains("--frame-mm") && e.contains("600 x 400 px"),
            "{e}"
        );
        let e = InSilo {
            phi0: 1.5,
            ..at(Framing::Corner([0.0, 0.0]))
        }
        .validate_options()
        .unwrap_err()
        .to_string();
        assert!(e.contains("--phi0"), "{e}");
    }
}
