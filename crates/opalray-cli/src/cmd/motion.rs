//! What a sweep moves: the light about the stone (the paper's fig. 11), or the stone rocked
//! (tilt) and turned under fixed lights, or the environment turned about it; and which of
//! these move anything in a given scene.

use anyhow::{bail, Result};
use opalray::scene::{EnvironmentKind, LightKind};
use opalray::Scene;

/// The flags that choose what a sweep moves, and over which range.
#[derive(clap::Args, Debug, Clone, Default)]
pub struct MotionArgs {
    /// Sweep the light's angle from this, degrees (light.angle_deg; a scene with a light):
    /// the paper's fig. 11 [default: −60 to 60].
    #[arg(long, value_name = "DEG", allow_hyphen_values = true)]
    pub light_from: Option<f64>,
    /// Last light angle, degrees.
    #[arg(long, value_name = "DEG", allow_hyphen_values = true)]
    pub light_to: Option<f64>,
    /// The same as --light-from.
    #[arg(
        long,
        value_name = "DEG",
        allow_hyphen_values = true,
        conflicts_with = "light_from"
    )]
    pub from: Option<f64>,
    /// The same as --light-to.
    #[arg(
        long,
        value_name = "DEG",
        allow_hyphen_values = true,
        conflicts_with = "light_to"
    )]
    pub to: Option<f64>,
    /// Rock the stone under fixed lights: its tilt about the picture's horizontal axis from
    /// this, degrees (camera.tilt_deg) [default: −30 to 30; the sweep of a scene without a
    /// light].
    #[arg(
        long,
        value_name = "DEG",
        allow_hyphen_values = true,
        conflicts_with = "tilt"
    )]
    pub tilt_from: Option<f64>,
    /// Last tilt, degrees.
    #[arg(
        long,
        value_name = "DEG",
        allow_hyphen_values = true,
        conflicts_with = "tilt"
    )]
    pub tilt_to: Option<f64>,
    /// Turn the stone about its face's normal under fixed lights, from this, degrees
    /// (camera.turn_deg) [default: −45 to 45].
    #[arg(long, value_name = "DEG", allow_hyphen_values = true)]
    pub turn_from: Option<f64>,
    /// Last turn, degrees.
    #[arg(long, value_name = "DEG", allow_hyphen_values = true)]
    pub turn_to: Option<f64>,
    /// Turn the environment about the stone, from this, degrees (environment.rotation_deg;
    /// the path integrator's and the stored method's lighting) [default: −90 to 90].
    #[arg(long, value_name = "DEG", allow_hyphen_values = true)]
    pub env_from: Option<f64>,
    /// Last environment rotation, degrees.
    #[arg(long, value_name = "DEG", allow_hyphen_values = true)]
    pub env_to: Option<f64>,
}

/// What a sweep moves.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Moves {
    /// The light's angle (light.angle_deg).
    Light,
    /// The stone's tilt (camera.tilt_deg).
    Tilt,
    /// The stone's turn about its face's normal (camera.turn_deg).
    Turn,
    /// The environment's rotation (environment.rotation_deg).
    Environment,
}

impl Moves {
    /// Every kind, in the order flags are checked.
    const ALL: [Moves; 4] = [Moves::Light, Moves::Tilt, Moves::Turn, Moves::Environment];

    /// The word for it in messages and statistics.
    pub fn name(self) -> &'static str {
        match self {
            Moves::Light => "light",
            Moves::Tilt => "tilt",
            Moves::Turn => "turn",
            Moves::Environment => "environment",
        }
    }

    /// Its pair of flags.
    fn flags(self) -> &'static str {
        match self {
            Moves::Light => "--light-from/--light-to",
            Moves::Tilt => "--tilt-from/--tilt-to",
            Moves::Turn => "--turn-from/--turn-to",
            Moves::Environment => "--env-from/--env-to",
        }
    }

    /// Default range and valid range, degrees.
    fn ranges(self) -> ([f64; 2], [f64; 2]) {
        match self {
            Moves::Light => ([-60.0, 60.0], [-89.0, 89.0]),
            Moves::Tilt => ([-30.0, 30.0], [-89.0, 89.0]),
            Moves::Turn => ([-45.0, 45.0], [-360.0, 360.0]),
            Moves::Environment => ([-90.0, 90.0], [-360.0, 360.0]),
        }
    }

    /// Whether moving it changes the picture of `scene`, and if not, why.
    fn moves_in(self, scene: &Scene) -> std::result::Result<(), String> {
        match self {
            Moves::Light if scene.light.kind == LightKind::None => {
                Err("the scene has no light (light.kind = \"none\")".into())
            }
            Moves::Environment
                if !opalray::integrator::of(scene.integrator.method()).sees_environment() =>
            {
                Err(format!(
                    "its renderer sees no environment (integrator.method = \"{}\")",
                    scene.integrator.method().name()
                ))
            }
            Moves::Environment
                if matches!(
                    scene.environment.kind,
                    EnvironmentKind::None | EnvironmentKind::Uniform
                ) =>
            {
                Err(
                    "the scene's environment is the same in every direction about the stone's \
                     normal (environment.kind = \"none\" or \"uniform\")"
                        .into(),
                )
            }
            _ => Ok(()),
        }
    }
}

/// What moves in `scene`, as the flags that move it: "--tilt-from/--tilt-to, …".
pub fn what_moves(scene: &Scene) -> String {
    Moves::ALL
        .iter()
        .filter(|m| m.moves_in(scene).is_ok())
        .map(|m| format!("{} ({})", m.flags(), m.name()))
        .collect::<Vec<_>>()
        .join(", ")
}

/// Refuse `--light-angle` on a scene without a light, naming what would move.
pub fn check_light_angle(scene: &Scene) -> Result<()> {
    if let Err(why) = Moves::Light.moves_in(scene) {
        bail!(
            "--light-angle: {why}, so the light angle changes nothing; rock the stone with \
             --tilt instead, or set light.kind in a scene file"
        );
    }
    Ok(())
}

impl MotionArgs {
    /// The ends given for `moves`.
    fn ends(&self, moves: Moves) -> [Option<f64>; 2] {
        match moves {
            Moves::Light => [self.light_from.or(self.from), self.light_to.or(self.to)],
            Moves::Tilt => [self.tilt_from, self.tilt_to],
            Moves::Turn => [self.turn_from, self.turn_to],
            Moves::Environment => [self.env_from, self.env_to],
        }
    }

    /// What moves, and from where to where, degrees: the kind whose flags are given (one
    /// kind at most), else the light where `scene` has one, else the tilt. A kind that moves
    /// nothing in `scene` is refused, naming what would move.
    pub fn choose(&self, scene: &Scene) -> Result<(Moves, [f64; 2])> {
        let given: Vec<Moves> = Moves::ALL
            .into_iter()
            .filter(|&m| self.ends(m).iter().any(Option::is_some))
            .collect();
        let moves = match given[..] {
            [] if Moves::Light.moves_in(scene).is_ok() => Moves::Light,
            [] => Moves::Tilt,
            [one] => one,
            [a, b, ..] => bail!(
                "{} and {}: a sweep moves one thing; give the flags of one",
                a.flags(),
                b.flags()
            ),
        };
        if let Err(why) = moves.moves_in(scene) {
            bail!(
                "{}: {why}, so it moves nothing; what moves in this scene: {}",
                moves.flags(),
                what_moves(scene)
            );
        }
        let (default, [lo, hi]) = moves.ranges();
        let ends = self.ends(moves);
        let mut range = [0.0; 2];
        for k in 0..2 {
            let v = ends[k].unwrap_or(default[k]);
            if !(v.is_finite() && (lo..=hi).contains(&v)) {
                let flag = match (moves, k) {
                    (Moves::Light, 0) if self.from.is_some() => "--from",
                    (Moves::Light, 1) if self.to.is_some() => "--to",
                    _ => moves.flags().split('/').nth(k).unwrap_or_default(),
                };
                let what = if moves == Moves::Light {
                    "light angle"
                } else {
                    moves.name()
                };
                bail!(
                    "{flag} {v}: the {what} must be within {lo}° … {hi}°; try {} and {}",
                    default[0],
                    default[1]
                );
            }
            range[k] = v;
        }
        Ok((moves, range))
    }
}

/// `scene` posed for one sweep frame: `value` degrees of what `moves` moves.
pub fn pose(scene: &Scene, moves: Moves, value: f64) -> Scene {
    let mut posed = scene.clone();
    match moves {
        Moves::Light => posed.light.angle_deg = value,
        Moves::Tilt => posed.camera.tilt_deg = value,
        Moves::Turn => posed.camera.turn_deg = value,
        Moves::Environment => posed.environment.rotation_deg = value,
    }
    posed
}

#[cfg(test)]
mod tests {
    use super::*;

    fn preset(name: &str) -> Scene {
        opalray::scene::preset(name).unwrap()
    }

    #[test]
    fn a_gem_without_a_light_sweeps_its_tilt_and_refuses_the_light() {
        let gem = preset("black-opal");
        let none = MotionArgs::default();
        assert_eq!(none.choose(&gem).unwrap(), (Moves::Tilt, [-30.0, 30.0]));
        let light = MotionArgs {
            light_from: Some(-45.0),
            ..Default::default()
        };
        let err = light.choose(&gem).unwrap_err().to_string();
        assert!(
            err.contains("no light") && err.contains("--tilt-from"),
            "{err}"
        );
        assert!(check_light_angle(&gem).is_err());
    }

    #[test]
    fn the_paper_sweeps_its_light_and_refuses_the_environment() {
        let paper = preset("paper");
        let none = MotionArgs::default();
        assert_eq!(none.choose(&paper).unwrap(), (Moves::Light, [-60.0, 60.0]));
        let env = MotionArgs {
            env_to: Some(90.0),
            ..Default::default()
        };
        let err = env.choose(&paper).unwrap_err().to_string();
        assert!(
            err.contains("--env-from/--env-to") && err.contains("--light-from"),
            "{err}"
        );
        assert!(check_light_angle(&paper).is_ok());
    }

    #[test]
    fn two_kinds_at_once_are_refused() {
        let both = MotionArgs {
            tilt_from: Some(-10.0),
            turn_to: Some(10.0),
            ..Default::default()
        };
        assert!(both.choose(&preset("black-opal")).is_err());
    }
}
