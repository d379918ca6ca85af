//! What a reproduction runs: which shapes, which phi0, how many realisations on each side, how
//! large the silos and photographs are. Every size is a field, so the presets below are the
//! only place where `--quick`, `--paper` and the test's tiny run differ.

use serde::{Deserialize, Serialize};

use crate::grains::GrainKind;
use crate::scene::{FrameChoice, Scene, parse_scene};

/// Seeds of the photographed realisations start here; simulation seeds start at 1. The two
/// sides are thus different realisations, as an experiment and its model are.
pub const PHOTO_SEED_OFFSET: u64 = 1_000_000;

/// One grain shape of the study.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ShapePlan {
    pub kind: GrainKind,
    /// Grains poured per filling.
    pub grains: usize,
    /// Feed fractions of the rain.
    pub phi0s: Vec<f64>,
    /// Coarse-graining width of the pressure profile, in grain widths D.
    pub w_over_d: f64,
}

/// Everything a reproduction run needs to know.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Plan {
    /// "quick", "paper" or "tiny".
    pub name: String,
    /// Distance between the silo's side walls (mm). The analysis cuts 40 mm at each wall.
    pub silo_width_mm: f64,
    pub shapes: Vec<ShapePlan>,
    /// Fillings per (shape, phi0) measured on the simulation side.
    pub simulation_realisations: u64,
    /// Fillings per (shape, phi0) photographed for the experiment side (other seeds).
    pub photo_realisations: u64,
    /// Frame the analysis reads: region E (290-410 mm) at paper scale; the whole deposit for
    /// small silos whose deposits do not reach region E. Photographs show the same frame.
    pub frame: FrameChoice,
    /// Scale of the rendered photographs (px/mm).
    pub photo_px_per_mm: f64,
    /// Look of the rendered photographs: clean, lab or hard (`vision::render::Style`).
    pub photo_style: String,
    /// g(r) uses centres at least this many D inside the analysed area and is reported up to
    /// this r: the paper's 4 D needs a frame 8 D across, more than a small silo leaves.
    pub rdf_margin_over_d: f64,
    /// The coarse-graining widths of the w scan (D).
    pub w_scan_over_d: Vec<f64>,
    /// Simulated time allowed for the relaxation after the last grain (s).
    pub max_relaxation_time_s: f64,
}

impl Plan {
    /// `facets reproduce --quick`: the README's main job, small silos and ensembles: a 160 mm
    /// silo (an 80 mm analysed strip), two phi0 a shape, six simulated and three photographed
    /// fillings each. It fits the README's 10-minute budget for the main job on 2 cores.
    pub fn quick() -> Plan {
        Plan {
            name: "quick".into(),
            silo_width_mm: 160.0,
            shapes: vec![
                shape(GrainKind::Square, 240, &[0.05, 0.25], 2.0),
                shape(GrainKind::ShortRod, 300, &[0.05, 0.25], 2.0),
                shape(GrainKind::LongRod, 200, &[0.05, 0.25], 2.0),
            ],
            simulation_realisations: 6,
            photo_realisations: 3,
            frame: FrameChoice::Whole,
            photo_px_per_mm: 8.0,
            photo_style: "lab".into(),
            rdf_margin_over_d: 2.0,
            w_scan_over_d: vec![1.0, 2.0, 3.0],
            max_relaxation_time_s: 1.0,
        }
    }

    /// `facets reproduce --paper`: the paper's silo, grain counts and phi0 values (docs/model.md §1-2),
    /// eight realisations a side.
    pub fn paper() -> Plan {
        let squares = [0.01, 0.025, 0.05, 0.1, 0.25];
        let rods = [0.01, 0.04, 0.1, 0.25];
        Plan {
            name: "paper".into(),
            silo_width_mm: 256.0,
            shapes: vec![
                shape(GrainKind::Square, 3000, &squares, 4.0),
                shape(GrainKind::ShortRod, 9000, &rods, 3.0),
                shape(GrainKind::LongRod, 5000, &rods, 3.0),
            ],
            simulation_realisations: 8,
            photo_realisations: 8,
            frame: FrameChoice::RegionE,
            photo_px_per_mm: 10.0,
            photo_style: "lab".into(),
            rdf_margin_over_d: 4.0,
            w_scan_over_d: vec![1.0, 2.0, 3.0, 4.0, 6.0],
            max_relaxation_time_s: 10.0,
        }
    }

    /// The end-to-end test's run (`--tiny`, hidden): a 120 mm silo (96 mm would leave a 16 mm
    /// analysed strip, narrower than the 2 x 1.1 D that g(1) needs for squares), one phi0,
    /// two realisations a side, squares and long rods only (short rods add nothing the test
    /// checks that long rods do not, and would double its time).
    pub fn tiny() -> Plan {
        Plan {
            name: "tiny".into(),
            silo_width_mm: 120.0,
            shapes: vec![
                shape(GrainKind::Square, 80, &[0.1], 1.0),
                shape(GrainKind::LongRod, 80, &[0.1], 1.0),
            ],
            simulation_realisations: 2,
            photo_realisations: 1,
            frame: FrameChoice::Whole,
            photo_px_per_mm: 10.0,
            photo_style: "lab".into(),
            rdf_margin_over_d: 1.1,
            w_scan_over_d: vec![1.0, 2.0],
            max_relaxation_time_s: 1.0,
        }
    }

    /// Reads a plan written as JSON (the `plan.json` of an earlier run, edited); errors name
    /// the file, line and column (serde_json's message carries the position).
    pub fn load(path: &std::path::Path) -> anyhow::Result<Plan> {
        let text = std::fs::read_to_string(path)
            .map_err(|e| anyhow::anyhow!("cannot read plan {}: {e}", path.display()))?;
        let plan: Plan =
            serde_json::from_str(&text).map_err(|e| anyhow::anyhow!("{}: {e}", path.display()))?;
        plan.validate()
            .map_err(|e| anyhow::anyhow!("{}: {e:#}", path.display()))?;
        Ok(plan)
    }

    /// Refuses a plan whose sizes cannot give the report, naming the field.
    pub fn validate(&self) -> anyhow::Result<()> {
        anyhow::ensure!(
            !self.shapes.is_empty(),
            "plan {}: `shapes` is empty",
            self.name
        );
        anyhow::ensure!(
            self.simulation_realisations >= 1
                && self.simulation_realisations < PHOTO_SEED_OFFSET
                && self.photo_realisations < PHOTO_SEED_OFFSET,
            "plan {}: `simulation_realisations` must be in 1..{PHOTO_SEED_OFFSET} and `photo_realisations` below it",
            self.name
        );
        anyhow::ensure!(
            self.photo_px_per_mm.is_finite() && self.photo_px_per_mm > 0.0,
            "plan {}: `photo_px_per_mm` = {}, expected a positive scale",
            self.name,
            self.photo_px_per_mm
        );
        anyhow::ensure!(
            vision::render::Style::named(&self.photo_style).is_some(),
            "plan {}: `photo_style` = {:?}, expected clean, lab or hard",
            self.name,
            self.photo_style
        );
        anyhow::ensure!(
            self.rdf_margin_over_d >= 1.05,
            "plan {}: `rdf_margin_over_d` = {}, expected at least 1.05 (g(1) needs the whole bin around r = D)",
            self.name,
            self.rdf_margin_over_d
        );
        for s in &self.shapes {
            for &phi0 in &s.phi0s {
                self.scene(s, phi0)?;
            }
        }
        Ok(())
    }

    /// Seeds of the simulation side.
    pub fn simulation_seeds(&self) -> Vec<u64> {
        (1..=self.simulation_realisations).collect()
    }

    /// Seeds of the photographed side, disjoint from the simulation's.
    pub fn photo_seeds(&self) -> Vec<u64> {
        (1..=self.photo_realisations)
            .map(|k| PHOTO_SEED_OFFSET + k)
            .collect()
    }

    /// The scene of one (shape, phi0): the paper's contact law, inflow and relaxation; the
    /// plan's silo, grain count and frame. Written as TOML and parsed, so it passes the same
    /// checks as a scene file (and `scene.toml` in the run folder reproduces it).
    pub fn scene(&self, shape: &ShapePlan, phi0: f64) -> anyhow::Result<Scene> {
        let text = self.scene_toml(shape, phi0);
        parse_scene(
            &text,
            &format!("plan {} ({} phi0 = {phi0})", self.name, shape.kind.name()),
        )
    }

    pub fn scene_toml(&self, shape: &ShapePlan, phi0: f64) -> String {
        let frame = match self.frame {
            FrameChoice::Auto => "auto",
            FrameChoice::Whole => "whole",
            FrameChoice::RegionE => "region-e",
        };
        format!(
            "# facets reproduce, plan {plan}: {kind} at phi0 = {phi0}\n\
             [silo]\nwidth_mm = {w}\nheight_mm = 750\n\n\
             [grains]\nkind = \"{kind}\"\ncount = {n}\n\n\
             [feed]\nphi0 = {phi0}\n\n\
             [run]\nmax_relaxation_time_s = {relax}\n\n\
             [output]\nframe = \"{frame}\"\n",
            plan = self.name,
            kind = shape.kind.name(),
            w = self.silo_width_mm,
            n = shape.grains,
            relax = self.max_relaxation_time_s,
        )
    }
}

fn shape(kind: GrainKind, grains: usize, phi0s: &[f64], w_over_d: f64) -> ShapePlan {
    ShapePlan {
        kind,
        grains,
        phi0s: phi0s.to_vec(),
        w_over_d,
    }
}

/// Folder name of one phi0 (three decimals, as the figures' names).
pub fn phi0_tag(phi0: f64) -> String {
    format!("phi0_{phi0:.3}")
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn presets_are_valid_and_sides_never_share_a_seed() {
        for plan in [Plan::quick(), Plan::paper(), Plan::tiny()] {
            plan.validate().unwrap();
            let sim = plan.simulation_seeds();
            assert_eq!(sim.len() as u64, plan.simulation_realisations);
            assert!(plan.photo_seeds().iter().all(|s| !sim.contains(s)));
        }
        let paper = Plan::paper();
        assert_eq!(paper.silo_width_mm, 256.0);
        let counts: Vec<usize> = paper.shapes.iter().map(|s| s.grains).collect();
        assert_eq!(counts, [3000, 9000, 5000]);
        assert!(paper.simulation_realisations >= 8);
    }

    #[test]
    fn a_written_plan_reads_back_and_a_bad_field_is_named() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("plan.json");
        let plan = Plan::quick();
        std::fs::write(&path, serde_json::to_string_pretty(&plan).unwrap()).unwrap();
        assert_eq!(Plan::load(&path).unwrap(), plan);
        let text = serde_json::to_string_pretty(&plan)
            .unwrap()
            .replace("\"photo_px_per_mm\"", "\"photo_px\"");
        std::fs::write(&path, text).unwrap();
        let e = format!("{:#}", Plan::load(&path).unwrap_err());
        assert!(
            e.contains("plan.json") && e.contains("photo_px") && e.contains("line"),
            "{e}"
        );
    }

    #[test]
    fn a_bad_size_is_refused_by_name() {
        let mut plan = Plan::tiny();
        plan.shapes[0].phi0s = vec![1.5];
        let e = format!("{:#}", plan.validate().unwrap_err());
        assert!(e.contains("phi0"), "{e}");
        let mut plan = Plan::tiny();
        plan.rdf_margin_over_d = 0.5;
        let e = format!("{:#}", plan.validate().unwrap_err());
        assert!(e.contains("rdf_margin_over_d"), "{e}");
    }
}
