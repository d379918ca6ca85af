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
    /// Sleep by drift instead: a grain whose centre and corners stay within this distance
    /// (mm) for `DRIFT_QUIET_TIME_S` falls asleep, whatever its speed and force, and wakes when
    /// its force changes by `DRIFT_WAKE_FRACTION` of its weight.
    pub sleep_drift_mm: Option<f64>,
    /// Drag on touching grains once the last grain is in (1/s; 0: none) ...
    pub relaxation_drag_per_s: f64,
    /// ... from when kinetic / elastic falls below this (inf: at once).
    pub relaxation_drag_below: f64,
    pub insertion: Insertion,
}

/// Quiet stretch of the drift-sleep settings (s): several periods of a deposit's ringing.
pub const DRIFT_QUIET_TIME_S: f64 = 0.02;
/// Wake threshold of the drift-sleep settings (fraction of the weight): above the force
/// swings of a ringing deposit's neighbours, below an impact's.
pub const DRIFT_WAKE_FRACTION: f64 = 5.0;
/// Drag of the drag settings (1/s): a ringing mode loses its energy as exp(-200 t), so
/// kinetic / elastic falls by 1e4 in about 50 ms.
pub const RELAXATION_DRAG_PER_S: f64 = 200.0;
/// Where the late-drag settings start it (kinetic / elastic): the last grains have landed
/// and the pile only creeps, ten times above the relaxation threshold.
pub const LATE_DRAG_BELOW: f64 = 1e-3;
/// An earlier start, to see whether the relaxation (a fifth of a paper-scale rod fill's
/// grain-steps) can be cut further without moving the deposit.
pub const EARLY_DRAG_BELOW: f64 = 1e-2;

/// dt = t_c / n, drag once kinetic / elastic has fallen below `below` after the last grain.
const fn dragged_from(name: &'static str, what: &'static str, n: f64, below: f64) -> Setting {
    Setting {
        name,
        what,
        steps_per_collision: n,
        relaxation_drag_per_s: RELAXATION_DRAG_PER_S,
        relaxation_drag_below: below,
        ..PLAIN
    }
}

/// The setting every other is measured against.
pub const REFERENCE: &str = "faithful";

/// Every switch off, grains entering above the surface; the settings below name only what
/// they change.
const PLAIN: Setting = Setting {
    name: "",
    what: "",
    time_step_s: None,
    steps_per_collision: 25.0,
    sleep: false,
    sleep_speed_m_s: None,
    sleep_drift_mm: None,
    relaxation_drag_per_s: 0.0,
    relaxation_drag_below: f64::INFINITY,
    insertion: Insertion::Surface,
};

const fn stepped(name: &'static str, what: &'static str, n: f64, sleep: bool) -> Setting {
    Setting {
        name,
        what,
        steps_per_collision: n,
        sleep,
        ..PLAIN
    }
}

/// dt = t_c / n, drag during relaxation, and sleep by a drift of `drift_mm` if some.
const fn dragged(name: &'static str, what: &'static str, n: f64, drift_mm: Option<f64>) -> Setting {
    Setting {
        name,
        what,
        steps_per_collision: n,
        sleep: drift_mm.is_some(),
        sleep_drift_mm: drift_mm,
        relaxation_drag_per_s: RELAXATION_DRAG_PER_S,
        ..PLAIN
    }
}

/// Every setting the bench knows, the reference first.
pub const SETTINGS: [Setting; 22] = [
    Setting {
        name: REFERENCE,
        what: "paper-faithful: dt = 1e-6 s, every grain integrated every step",
        time_step_s: Some(1e-6),
        steps_per_collision: 400.0,
        ..PLAIN
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
        steps_per_collision: 50.0,
        insertion: Insertion::Fixed,
        ..PLAIN
    },
    Setting {
        name: "n25-sleep1cm",
        what: "dt = t_c / 25, grains slower than 1 cm/s for 5 ms sleep (freezes the ringing)",
        sleep: true,
        sleep_speed_m_s: Some(0.01),
        ..PLAIN
    },
    stepped("n12", "dt = t_c / 12, sleep off", 12.0, false),
    stepped("n10", "dt = t_c / 10, sleep off", 10.0, false),
    stepped("n8", "dt = t_c / 8, sleep off", 8.0, false),
    stepped("n6", "dt = t_c / 6, sleep off", 6.0, false),
    stepped(
        "n12-sleep",
        "dt = t_c / 12, resting grains sleep",
        12.0,
        true,
    ),
    Setting {
        name: "n12-drift",
        what: "dt = t_c / 12, grains staying within 0.05 mm for 20 ms sleep (wake at 5 weights)",
        steps_per_collision: 12.0,
        sleep: true,
        sleep_drift_mm: Some(0.05),
        ..PLAIN
    },
    dragged(
        "n25-drag",
        "dt = t_c / 25, drag 200/s on touching grains after the last grain is in",
        25.0,
        None,
    ),
    dragged(
        "n12-drag",
        "dt = t_c / 12, drag 200/s on touching grains after the last grain is in",
        12.0,
        None,
    ),
    dragged_from(
        "n12-latedrag",
        "dt = t_c / 12, drag 200/s on touching grains once kinetic < 1e-3 x elastic",
        12.0,
        LATE_DRAG_BELOW,
    ),
    dragged_from(
        "n10-latedrag",
        "dt = t_c / 10, drag 200/s on touching grains once kinetic < 1e-3 x elastic",
        10.0,
        LATE_DRAG_BELOW,
    ),
    dragged_from(
        "n10-earlydrag",
        "dt = t_c / 10, drag 200/s on touching grains once kinetic < 1e-2 x elastic",
        10.0,
        EARLY_DRAG_BELOW,
    ),
    dragged(
        "n25-drift-drag",
        "n25-drag, and grains staying within 0.05 mm for 20 ms sleep (wake at 5 weights)",
        25.0,
        Some(0.05),
    ),
    dragged(
        "n12-drift-drag",
        "n12-drag, and grains staying within 0.05 mm for 20 ms sleep (wake at 5 weights)",
        12.0,
        Some(0.05),
    ),
];

impl Setting {
    /// The setting called `name`; the error lists the known names.
    pub fn by_name(name: &str) -> anyhow::Result<&'static Setting> {
        named(&SETTINGS, name, |s| s.name, "setting")
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
            relaxation_drag_per_s: self.relaxation_drag_per_s,
            relaxation_drag_below: self.relaxation_drag_below,
            ..defaults
        };
        if let Some(drift) = self.sleep_drift_mm {
            s.model.sleep_drift_mm = drift;
            s.model.sleep_speed_m_s = f64::INFINITY;
            s.model.sleep_force_fraction = f64::INFINITY;
            s.model.sleep_quiet_time_s = DRIFT_QUIET_TIME_S;
            s.model.wake_force_fraction = DRIFT_WAKE_FRACTION;
        }
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
        named(&SCENES, name, |s| s.name, "scene")
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

/// The entry of `list` called `name`; the error lists the known names.
fn named<T>(
    list: &'static [T],
    name: &str,
    name_of: fn(&T) -> &'static str,
    what: &str,
) -> anyhow::Result<&'static T> {
    list.iter().find(|t| name_of(t) == name).ok_or_else(|| {
        let names: Vec<&str> = list.iter().map(name_of).collect();
        anyhow::anyhow!(
            "unknown {what} `{name}`: expected one of {}",
            names.join(", ")
        )
    })
}
