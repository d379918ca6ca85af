use clap::Args as ClapArgs;

use facets::grains::GrainKind;
use facets::impact::{ImpactSpec, Target, drop_grain};

/// Drops one grain corner-first onto the floor or onto a resting grain at the paper's contact
/// parameters, and reports the deepest overlap (it exceeds r_i + r_j at these speeds), the
/// contact time, the restitution and the energy balance.
#[derive(Debug, ClapArgs)]
pub struct Args {
    /// Grain kind: square (6.9 mm nut), rod53 (4.9 x 3 mm) or rod3 (8.9 x 3 mm).
    #[arg(long, default_value = "square")]
    kind: GrainKind,
    /// What the grain hits.
    #[arg(long, value_enum, default_value = "grain")]
    onto: Target,
    /// Impact speed (m/s); grains reach the deposit at 3.5 to 5 m/s.
    #[arg(long, default_value_t = 5.0)]
    speed: f64,
    /// Orientation of the dropped grain (degrees); 45 puts a square's corner straight down.
    #[arg(long, default_value_t = 45.0, allow_negative_numbers = true)]
    angle_deg: f64,
    /// Time step (s); by default 1/400 of a binary collision.
    #[arg(long)]
    dt: Option<f64>,
}

pub fn run(args: Args) -> anyhow::Result<()> {
    if !(args.speed.is_finite() && args.speed > 0.0 && args.speed < 100.0) {
        anyhow::bail!(
            "--speed {} m/s: expected a speed between 0 and 100 m/s",
            args.speed
        );
    }
    let spec = ImpactSpec {
        kind: args.kind,
        target: args.onto,
        speed: args.speed,
        angle: args.angle_deg.to_radians(),
        time_step: args.dt,
    };
    let r = drop_grain(&spec)?;
    println!(
        "{} dropped at {} m/s, {} deg, onto the {:?} (dt = {:.3e} s, {} steps)",
        args.kind, args.speed, args.angle_deg, args.onto, r.time_step, r.steps
    );
    println!(
        "deepest overlap       {:.3} mm = {:.2} x (r_i + r_j)",
        r.deepest_overlap * 1e3,
        r.deepest_relative
    );
    println!("contact duration      {:.3} ms", r.contact_duration * 1e3);
    println!("restitution           {:.3}", r.restitution);
    println!(
        "energy before / after {:.4e} J / {:.4e} J ({:+.1} %)",
        r.energy_before,
        r.energy_after,
        100.0 * (r.energy_after - r.energy_before) / r.energy_before.abs()
    );
    println!(
        "least normal force    {:.3e} N (never attractive)",
        r.least_normal_force
    );
    Ok(())
}
