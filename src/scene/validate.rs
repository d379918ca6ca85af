use super::{Insertion, PlateLaw, Scene, WallKind};

/// A value that parses but makes no sense, with where it lives.
pub struct Invalid {
    pub section: &'static str,
    pub key: &'static str,
    pub message: String,
}

fn invalid(section: &'static str, key: &'static str, message: String) -> Invalid {
    Invalid {
        section,
        key,
        message,
    }
}

fn positive(section: &'static str, key: &'static str, v: f64, unit: &str) -> Result<(), Invalid> {
    if v.is_finite() && v > 0.0 {
        Ok(())
    } else {
        Err(invalid(
            section,
            key,
            format!("is {v}, expected a finite positive number ({unit})"),
        ))
    }
}

fn non_negative(
    section: &'static str,
    key: &'static str,
    v: f64,
    unit: &str,
) -> Result<(), Invalid> {
    if v.is_finite() && v >= 0.0 {
        Ok(())
    } else {
        Err(invalid(
            section,
            key,
            format!("is {v}, expected a finite number >= 0 ({unit})"),
        ))
    }
}

/// A threshold that `inf` turns off.
fn criterion(section: &'static str, key: &'static str, v: f64, unit: &str) -> Result<(), Invalid> {
    if v >= 0.0 {
        Ok(())
    } else {
        Err(invalid(
            section,
            key,
            format!("is {v}, expected a number >= 0 ({unit}), or inf to turn it off"),
        ))
    }
}

/// Checks every number of a parsed scene, and the geometry they make together.
pub fn validate(s: &Scene) -> Result<(), Invalid> {
    positive("silo", "width_mm", s.silo.width_mm, "mm")?;
    positive("silo", "height_mm", s.silo.height_mm, "mm")?;
    if let Some(r) = s.silo.roughness_mm {
        non_negative("silo", "roughness_mm", r, "mm")?;
        if s.silo.walls != WallKind::Rough {
            return Err(invalid(
                "silo",
                "roughness_mm",
                "is set, but walls is not \"rough\"".into(),
            ));
        }
    }

    let g = &s.grains;
    if g.count == 0 {
        return Err(invalid(
            "grains",
            "count",
            "is 0: a filling needs at least one grain".into(),
        ));
    }
    if let Some(v) = g.length_mm {
        positive("grains", "length_mm", v, "mm")?;
    }
    if let Some(v) = g.width_mm {
        positive("grains", "width_mm", v, "mm")?;
    }
    if let Some(v) = g.areal_density_kg_m2 {
        positive("grains", "areal_density_kg_m2", v, "kg/m^2")?;
    }
    if let Some(v) = g.rounding_fraction {
        if !(v.is_finite() && v > 0.0 && v < 0.5) {
            return Err(invalid(
                "grains",
                "rounding_fraction",
                format!("is {v}, expected a fraction of the width D in (0, 0.5)"),
            ));
        }
    }
    let (length, width) = (g.length() * 1e3, g.width() * 1e3);
    if length < width {
        let key = if g.length_mm.is_some() {
            "length_mm"
        } else {
            "width_mm"
        };
        return Err(invalid(
            "grains",
            key,
            format!("length {length} mm is below width {width} mm: the length is the long side"),
        ));
    }
    if length >= s.silo.width_mm {
        return Err(invalid(
            "silo",
            "width_mm",
            format!(
                "is {} mm, but the grain is {length} mm long: a grain must fit across the silo in every orientation",
                s.silo.width_mm
            ),
        ));
    }

    let f = &s.feed;
    if !(f.phi0.is_finite() && f.phi0 > 0.0 && f.phi0 < 1.0) {
        return Err(invalid(
            "feed",
            "phi0",
            format!(
                "is {}, expected the volume fraction of the rain in (0, 1)",
                f.phi0
            ),
        ));
    }
    positive("feed", "speed_m_s", f.speed_m_s, "m/s")?;
    non_negative("feed", "gap_mm", f.gap_mm, "mm")?;
    if !(f.speed_spread.is_finite() && (0.0..1.0).contains(&f.speed_spread)) {
        return Err(invalid(
            "feed",
            "speed_spread",
            format!(
                "is {}, expected a fraction of the inflow speed in [0, 1)",
                f.speed_spread
            ),
        ));
    }
    non_negative("feed", "spin_rad_s", f.spin_rad_s, "rad/s")?;
    if let Some(h) = f.band_height_mm {
        positive("feed", "band_height_mm", h, "mm")?;
        if h < length {
            return Err(invalid(
                "feed",
                "band_height_mm",
                format!("is {h} mm, below the grain length {length} mm"),
            ));
        }
    }
    if let Some(h) = f.fixed_height_mm {
        non_negative("feed", "fixed_height_mm", h, "mm")?;
        if f.insertion != Insertion::Fixed {
            return Err(invalid(
                "feed",
                "fixed_height_mm",
                "is set, but insertion is not \"fixed\"".into(),
            ));
        }
    }

    let c = &s.contact;
    positive("contact", "normal_stiffness_N_m", c.normal_stiffness, "N/m")?;
    non_negative(
        "contact",
        "tangential_stiffness_N_m",
        c.tangential_stiffness,
        "N/m",
    )?;
    non_negative("contact", "normal_damping_1_s", c.normal_damping, "1/s")?;
    non_negative(
        "contact",
        "tangential_damping_1_s",
        c.tangential_damping,
        "1/s",
    )?;
    non_negative("contact", "friction", c.friction, "dimensionless")?;
    positive("contact", "gravity_m_s2", c.gravity_m_s2, "m/s^2")?;
    if let Some(mu) = c.wall_friction {
        non_negative("contact", "wall_friction", mu, "dimensionless")?;
    }
    validate_plates(s)?;

    let r = &s.run;
    let m = &s.model;
    positive(
        "model",
        "steps_per_collision",
        m.steps_per_collision,
        "steps",
    )?;
    criterion("model", "sleep_speed_m_s", m.sleep_speed_m_s, "m/s")?;
    criterion(
        "model",
        "sleep_force_fraction",
        m.sleep_force_fraction,
        "fraction",
    )?;
    criterion("model", "sleep_drift_mm", m.sleep_drift_mm, "mm")?;
    non_negative("model", "sleep_quiet_time_s", m.sleep_quiet_time_s, "s")?;
    criterion(
        "model",
        "wake_force_fraction",
        m.wake_force_fraction,
        "fraction",
    )?;
    non_negative(
        "model",
        "relaxation_drag_per_s",
        m.relaxation_drag_per_s,
        "1/s",
    )?;
    if m.relaxation_drag_below.is_nan() || m.relaxation_drag_below <= 0.0 {
        return Err(invalid(
            "model",
            "relaxation_drag_below",
            format!(
                "is {}, expected a fraction of the elastic energy > 0, or inf for a drag from the last grain in",
                m.relaxation_drag_below
            ),
        ));
    }
    if let Some(dt) = r.time_step_s {
        positive("run", "time_step_s", dt, "s")?;
    }
    positive(
        "run",
        "relaxation_ratio",
        r.relaxation_ratio,
        "dimensionless",
    )?;
    positive(
        "run",
        "load_balance",
        r.load_balance,
        "fraction of the weight",
    )?;
    non_negative("run", "relaxation_hold_s", r.relaxation_hold_s, "s")?;
    positive("run", "max_relaxation_time_s", r.max_relaxation_time_s, "s")?;
    positive("run", "check_interval_s", r.check_interval_s, "s")?;
    if s.output.snapshot_every_steps == Some(0) {
        return Err(invalid(
            "output",
            "snapshot_every_steps",
            "is 0, expected a positive number of steps (or leave it out)".into(),
        ));
    }
    if let Some(every) = s.output.checkpoint_every_s {
        positive("output", "checkpoint_every_s", every, "s of simulated time")?;
    }
    Ok(())
}

/// The `[plates]` fields its law needs, and none it would ignore.
fn validate_plates(s: &Scene) -> Result<(), Invalid> {
    let p = &s.plates;
    let given = [
        ("friction", p.friction),
        ("load_fraction", p.load_fraction),
        ("drag_per_s", p.drag_per_s),
    ];
    let needed: &[&str] = match p.law {
        PlateLaw::None => &[],
        PlateLaw::Coulomb => &["friction", "load_fraction"],
        PlateLaw::Viscous => &["drag_per_s"],
    };
    for (key, value) in given {
        match (needed.contains(&key), value) {
            (true, Some(v)) => non_negative("plates", key, v, "see the scene reference")?,
            (true, None) => {
                return Err(invalid(
                    "plates",
                    key,
                    format!("is missing: law {:?} needs it", p.law),
                ));
            }
            (false, Some(_)) => {
                return Err(invalid(
                    "plates",
                    key,
                    format!("is set, but law {:?} does not use it", p.law),
                ));
            }
            (false, None) => {}
        }
    }
    Ok(())
}
