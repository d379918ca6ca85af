//! Where each stage writes, under the output folder:
//!
//! ```text
//! OUT/report.md, report.json, plan.json
//! OUT/SHAPE/runs/{simulation,photographed}/phi0_X/seed-N/   fillings (facets sim layout)
//! OUT/SHAPE/photos/phi0_X/seed-N.png, seed-N.truth.csv      rendered photographs
//! OUT/SHAPE/detected/phi0_X/NAME.csv (+ .meta.json, _overlay.png)  detector tables
//! OUT/SHAPE/analysis/{simulation,experiment}/               facets analyse outputs
//! OUT/SHAPE/figures/                                        both sides overlaid (facets compare)
//! ```

use std::path::{Path, PathBuf};

use super::plan::phi0_tag;
use super::simulate::Side;
use crate::grains::GrainKind;

#[derive(Clone, Debug)]
pub struct Layout {
    pub root: PathBuf,
}

impl Layout {
    pub fn new(root: &Path) -> Layout {
        Layout {
            root: root.to_path_buf(),
        }
    }

    pub fn shape_dir(&self, kind: GrainKind) -> PathBuf {
        self.root.join(kind.name())
    }

    pub fn run_dir(&self, kind: GrainKind, phi0: f64, side: Side, seed: u64) -> PathBuf {
        let side = match side {
            Side::Simulation => "simulation",
            Side::Photographed => "photographed",
        };
        self.shape_dir(kind)
            .join("runs")
            .join(side)
            .join(phi0_tag(phi0))
            .join(format!("seed-{seed}"))
    }

    pub fn photo(&self, kind: GrainKind, phi0: f64, seed: u64) -> PathBuf {
        self.shape_dir(kind)
            .join("photos")
            .join(phi0_tag(phi0))
            .join(format!("seed-{seed}.png"))
    }

    pub fn detected_dir(&self, kind: GrainKind, phi0: f64) -> PathBuf {
        self.shape_dir(kind).join("detected").join(phi0_tag(phi0))
    }

    pub fn analysis_dir(&self, kind: GrainKind, experiment: bool) -> PathBuf {
        self.shape_dir(kind).join("analysis").join(if experiment {
            "experiment"
        } else {
            "simulation"
        })
    }

    pub fn figures_dir(&self, kind: GrainKind) -> PathBuf {
        self.shape_dir(kind).join("figures")
    }

    /// `path` relative to the output folder, with forward slashes (for links in report.md).
    pub fn relative(&self, path: &Path) -> String {
        let rel = path.strip_prefix(&self.root).unwrap_or(path);
        rel.components()
            .map(|c| c.as_os_str().to_string_lossy().into_owned())
            .collect::<Vec<_>>()
            .join("/")
    }
}
