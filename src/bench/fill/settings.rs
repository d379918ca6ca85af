//! The settings the bench compares and the reference scenes it runs them on.

use crate::scene::{Insertion, ModelSection, Scene, parse_scene};

/// One way to run a filling: how the time step is chosen, whether grains sleep, where grains
/// enter. Everything else is the scene's.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Setting {
    pub name: &'static str,
    /// One line for tables and `--help`.
    pub what: &'static str,
    /// A fixed time step (s); None: dt = t_c / `steps_per_collision`.
    pub time_step_s: Option<f64>,
    pub steps_per_collision: f64,
    pub sleep: bool,
    /// Speed below which a grain may fall asleep (m/s); None: the engine's default.
    pub sleep_speed_m_s: Option<f64>,
    pub insertion: Insertion,
}

/// The setting every other is measured against.
pub const REFERENCE: &str = "faithful";

const fn stepped(name: &'static str, what: &'static str, n: f64, sleep: bool) -> Setting {
    Setting {
        name,
        what,
        time_step_s: None,
        steps_per_collision: n,
        sleep,
        sleep_speed_m_s: None,
        insertion: Insertion::Surface,
    }
}

/// Every setting the bench knows, the reference first.
pub const SETTINGS: [Setting; 9] = [
    Setting {
        name: REFERENCE,
        what: "paper-faithful: dt = 1e-6 s, every grain integrated every step",
        time_step_s: Some(1e-6),
        steps_per_collision: 400.0,
        sleep: false,
        sleep_speed_m_s: None,
        insertion: Insertion::Surface,
    },
    stepped("n400", "dt = t_c / 400, sleep off", 400.0, false),
    stepped("n100", "dt = t_c / 100, sleep off", 100.0, false),
    stepped("n50", "dt = t_c / 50, sleep off", 50.0, false),
    stepped("n25", "dt = t_c / 25, sleep off", 25.0, false),
    stepped(
        "n50-sleep",
        "dt = t_c / 50, resting grains sleep",
        50.0,
        true,
    ),
    stepped(
        "n25-sleep",
        "dt = t_c / 25, resting grains sleep",
        25.0,
        true,
    ),
    Setting {
        name: "fixed-insertion",
        what: "dt = t_c / 50, grains enter at the top of the silo and fall the whole way",
        time_step_s: None,
        steps_per_collision: 50.0,
        sleep: false,
        sleep_speed_m_s: None,
        insertion: Insertion::Fixed,
    },
    Setting {
        name: "n25-sleep1cm",
        what: "dt = t_c / 25, grains slower than 1 cm/s for 5 ms sleep (freezes the ringing)",
        time_step_s: None,
        steps_per_collision: 25.0,
        sleep: true,
        sleep_speed_m_s: Some(0.01),
        insertion: Insertion::Surface,
    },
];

impl Setting {
    /// The setting called `name`; the error lists the known names.
    pub fn by_name(name: &str) -> anyhow::Result<&'static Setting> {
        SETTINGS.iter().find(|s| s.name == name).ok_or_else(|| {
            let names: Vec<&str> = SETTINGS.iter().map(|s| s.name).collect();
            anyhow::anyhow!(
                "unknown setting `{name}`: expected one of {}",
                names.join(", ")
            )
        })
    }

    /// `scene` run this way: the model's other fields back to their defaults, so that a switch
    /// this setting does not name is off (or at its default) whatever the scene file says.
    pub fn apply(&self, scene: &Scene) -> Scene {
        let mut s = scene.clone();
        s.run.time_step_s = self.time_step_s;
        let defaults = ModelSection::default();
        s.model = ModelSection {
            steps_per_collision: self.steps_per_collision,
            sleep: self.sleep,
            sleep_speed_m_s: self.sleep_speed_m_s.unwrap_or(defaults.sleep_speed_m_s),
            ..defaults
        };
        s.feed.insertion = self.insertion;
        s
    }
}

/// A reference scene: one of the small scenes of data-samples/scenes/, compiled in so the bench
/// runs from any folder.
#[derive(Clone, Copy, Debug)]
pub struct ReferenceScene {
    pub name: &'static str,
    pub file: &'static str,
    text: &'static str,
}

/// Squares at phi0 = 0.05 and 0.25, long rods (d = 3) at 0.04 (issue 3).
pub const SCENES: [ReferenceScene; 3] = [
    ReferenceScene {
        name: "square-phi0p05",
        file: "data-samples/scenes/small-square-phi0p05.toml",
        text: include_str!("../../../data-samples/scenes/small-square-phi0p05.toml"),
    },
    ReferenceScene {
        name: "square-phi0p25",
        file: "data-samples/scenes/small-square-phi0p25.toml",
        text: include_str!("../../../data-samples/scenes/small-square-phi0p25.toml"),
    },
    ReferenceScene {
        name: "rod3-phi0p04",
        file: "data-samples/scenes/small-rod3-phi0p04.toml",
        text: include_str!("../../../data-samples/scenes/small-rod3-phi0p04.toml"),
    },
];

impl ReferenceScene {
    pub fn by_name(name: &str) -> anyhow::Result<&'static ReferenceScene> {
        SCENES.iter().find(|s| s.name == name).ok_or_else(|| {
            let names: Vec<&str> = SCENES.iter().map(|s| s.name).collect();
            anyhow::anyhow!(
                "unknown scene `{name}`: expected one of {}",
                names.join(", ")
            )
        })
    }

    /// The scene with `grains` grains, at most `max_relaxation_time_s` of relaxation, run with
    /// `setting`. The result is written back to TOML and read again, so that it passes the same
    /// checks as a scene file; errors name the file and the overrides.
    pub fn build(
        &self,
        grains: usize,
        max_relaxation_time_s: f64,
        setting: &Setting,
    ) -> anyhow::Result<Scene> {
        let mut scene = parse_scene(self.text, self.file)?;
        scene.grains.count = grains;
        scene.run.max_relaxation_time_s = max_relaxation_time_s;
        let scene = setting.apply(&scene);
        let text = toml::to_string(&scene)
            .map_err(|e| anyhow::anyhow!("{}: cannot write the bench scene: {e}", self.file))?;
        parse_scene(
            &text,
            &format!(
                "{} with {grains} grains, max_relaxation_time_s = {max_relaxation_time_s}, setting {}",
                self.file, setting.name
            ),
        )
    }
}
