//! `opalray spectrum`: reflectance and transmittance of one FCC cluster over wavelength and
//! angle (paper §2.3, §3.1), as a laboratory reflectance measurement would give them.
//!
//! Input: crystal flags (defaults: the scene's `[crystal]` section) and angles → output: per
//! angle the peak wavelength, peak reflectance, the Bragg–Snell prediction and the sRGB colour
//! of the reflected light under D65 (paper §3.4) on stdout; with `--output` a CSV
//! `wavelength_nm,angle_deg,reflectance,transmittance` on the requested wavelength step
//! (point values, not bin averages); with `--plot` an image of R over wavelength × angle
//! ([`plot`]; the curves, the CSV and the summary: [`report`]). Each angle's whole curve is
//! kept, so the peak and the colour read the same data.
//! With `--dispersion silica` the stack at each wavelength has silica's indices at that
//! wavelength (`optics::scan`, as the reflectance tables are built).

mod label;
mod plot;
mod report;

use std::path::PathBuf;

use anyhow::{anyhow, bail, Result};
use opalray::optics::{cos_inside_from_air, ClusterOptics, ClusterStack};
use opalray::scene::{CrystalConfig, Dispersion};

use crate::outputs::Outputs;
use plot::{write_plot, PlotAxes};
use report::{decimals_of, summary, write_csv, AngleCurve};

/// Most wavelength × angle samples one run computes (about 200 MB of CSV).
const MAX_SAMPLES: usize = 5_000_000;

/// Arguments of `opalray spectrum`.
#[derive(clap::Args, Debug)]
#[command(
    allow_negative_numbers = true,
    after_help = "Angles are measured in air from the normal of a face parallel to the (111) \
        planes, as in laboratory reflectance measurements, and refracted into the cluster's \
        effective index n_eff; with --inside they are angles inside the stone. The peak \
        follows Bragg–Snell, λ = 2·d111·√(n_eff² − sin²θ), and moves to shorter wavelengths \
        as the angle grows. With --dispersion silica both indices follow fused silica's \
        Sellmeier law (Malitson 1965) shifted to --n-sphere and --n-matrix at the sodium d \
        line (589.3 nm), as in the gem presets: the stack at each wavelength has that \
        wavelength's indices, the Bragg–Snell column solves λ = 2·d111·n_eff(λ)·cos θ, and \
        angles in air are refracted at the d line's n_eff, as the renderers' surface does. \
        The default, none, is an empty scene's [crystal] like every other default here, and \
        keeps the paper's constant indices (Bragg–Snell exactly). R and T are unpolarised (mean of s and p). The sRGB column is the \
        colour of the reflected light: the curve as a reflectance lit by D65 (a white \
        reflector is #ffffff; a single narrow line reflects little light, so it is dark), \
        integrated over --from-nm..--to-nm only.\n\n\
        The --plot image (904 × 432 px) shows R over wavelength (across, --from-nm to \
        --to-nm) and angle (up, 0° to the largest of --angles, marked on the right), each \
        wavelength in its own colour, brighter where R is larger.\n\n\
        Examples:\n  \
        opalray spectrum\n  \
        opalray spectrum --diameter 220 --angles 0,15,30,45 --output opal.csv\n  \
        opalray spectrum --angles 0,30,60 --plot opal-spectrum.png\n  \
        opalray spectrum --diameter 200 --dispersion silica --angles 0\n  \
        opalray spectrum --n-matrix 1.0 --layers 20 --from-nm 400 --to-nm 700 --step-nm 0.5"
)]
pub struct Args {
    /// Silica sphere diameter D, nm (50–2000; d111 = D·√(2/3)).
    #[arg(long, value_name = "NM", default_value_t = CrystalConfig::default().sphere_diameter_nm)]
    diameter: f64,
    /// Refractive index of the spheres (1–4).
    #[arg(long, value_name = "X", default_value_t = CrystalConfig::default().n_sphere)]
    n_sphere: f64,
    /// Refractive index of the matrix between the spheres (1–4; 1.0 for air, 1.333 water).
    #[arg(long, value_name = "X", default_value_t = CrystalConfig::default().n_matrix)]
    n_matrix: f64,
    /// Coherent (111) layers N in the cluster (1–100000).
    #[arg(long, value_name = "N", default_value_t = i64::from(CrystalConfig::default().layers))]
    layers: i64,
    /// Angles of incidence in degrees, comma separated, each in [0, 90).
    #[arg(
        long,
        value_name = "DEG,...",
        value_delimiter = ',',
        default_value = "0,30,60"
    )]
    angles: Vec<f64>,
    /// How the indices vary with wavelength: none (constant, the paper's and an empty
    /// scene's) or silica (the gem presets': fused silica's dispersion through the d-line
    /// indices).
    #[arg(long, value_name = "LAW", value_enum, default_value_t = DispersionFlag::None)]
    dispersion: DispersionFlag,
    /// Take --angles as angles inside the stone (between the ray and the (111) normal).
    #[arg(long)]
    inside: bool,
    /// First wavelength, nm.
    #[arg(long, value_name = "NM", default_value_t = 380.0)]
    from_nm: f64,
    /// Last wavelength, nm.
    #[arg(long, value_name = "NM", default_value_t = 780.0)]
    to_nm: f64,
    /// Wavelength step, nm (the lines are a few nm wide: keep it well under 1).
    #[arg(long, value_name = "NM", default_value_t = 0.1)]
    step_nm: f64,
    /// Write wavelength_nm,angle_deg,reflectance,transmittance to this CSV file.
    #[arg(long, value_name = "FILE.csv")]
    output: Option<PathBuf>,
    /// Draw R over wavelength × angle (0° to the largest of --angles) to this PNG.
    #[arg(long, value_name = "FILE.png")]
    plot: Option<PathBuf>,
}

/// `--dispersion`: the scene's `crystal.dispersion`.
#[derive(clap::ValueEnum, Clone, Copy, Debug, PartialEq, Eq)]
enum DispersionFlag {
    /// Constant indices (the paper's; an empty scene's `crystal.dispersion`).
    None,
    /// Fused silica's Sellmeier law through the d-line indices (the gem presets').
    Silica,
}

/// Run `opalray spectrum`.
pub fn run(args: Args) -> Result<()> {
    let crystal = crystal_from_flags(&args)?;
    let wavelengths = wavelengths(&args)?;
    check_angles(&args.angles)?;
    let mut outputs = Outputs::new();
    let csv = match &args.output {
        Some(path) => Some(outputs.add("--output", path, &["csv"])?),
        None => None,
    };
    let plot_out = match &args.plot {
        Some(path) => Some(outputs.add("--plot", path, &["png"])?),
        None => None,
    };
    let optics = ClusterOptics::new(&crystal)?;
    let curves: Vec<AngleCurve> = args
        .angles
        .iter()
        .map(|&angle_deg| curve(&optics, angle_deg, args.inside, &wavelengths))
        .collect();
    if let Some(csv) = csv {
        outputs.write(csv, |path| {
            write_csv(path, &curves, decimals_of(args.step_nm))
        })?;
    }
    if let Some(plot_out) = plot_out {
        let axes = PlotAxes {
            from_nm: args.from_nm,
            to_nm: args.to_nm,
            top_deg: args.angles.iter().copied().fold(0.0, f64::max),
            cos_inside: if args.inside {
                cos_of_inside
            } else {
                cos_of_air
            },
            marked_deg: args.angles.clone(),
            angle_title: if args.inside {
                "angle inside the stone (°)"
            } else {
                "angle of incidence in air (°)"
            },
        };
        outputs.write(plot_out, |path| write_plot(path, &optics, &axes))?;
    }
    outputs.commit()?;
    crate::stdio::out_raw(&summary(&optics, &curves, &args))?;
    if let Some(path) = &args.plot {
        crate::stdio::out(format_args!(
            "wrote {} ({} × {} px)",
            path.display(),
            plot::WIDTH_PX,
            plot::HEIGHT_PX
        ))?;
    }
    Ok(())
}

/// The crystal of the flags, validated; errors name the flag.
fn crystal_from_flags(args: &Args) -> Result<CrystalConfig> {
    let layers = u32::try_from(args.layers).map_err(|_| {
        anyhow!(
            "--layers: must be in 1..=100000, got {}; try {}",
            args.layers,
            CrystalConfig::default().layers
        )
    })?;
    let crystal = CrystalConfig {
        sphere_diameter_nm: args.diameter,
        n_sphere: args.n_sphere,
        n_matrix: args.n_matrix,
        layers,
        dispersion: match args.dispersion {
            DispersionFlag::None => Dispersion::None,
            DispersionFlag::Silica => Dispersion::Silica,
        },
        ..CrystalConfig::default()
    };
    crystal.validate().map_err(|err| match err {
        opalray::Error::InvalidField { field, message } => {
            let flag = match field.as_str() {
                "crystal.sphere_diameter_nm" => "--diameter",
                "crystal.n_sphere" => "--n-sphere",
                "crystal.n_matrix" => "--n-matrix",
                "crystal.layers" => "--layers",
                other => other,
            };
            anyhow!("{flag}: {message}")
        }
        other => other.into(),
    })?;
    Ok(crystal)
}

/// The wavelengths `from, from + step, …, ≤ to`.
fn wavelengths(args: &Args) -> Result<Vec<f64>> {
    let (from, to, step) = (args.from_nm, args.to_nm, args.step_nm);
    if !(from.is_finite() && from > 0.0) {
        bail!("--from-nm: must be a positive number of nm, got {from}; try 380");
    }
    if !(to.is_finite() && to > from) {
        bail!("--to-nm: must be a number greater than --from-nm ({from}), got {to}; try 780");
    }
    if !(step.is_finite() && step > 0.0) {
        bail!("--step-nm: must be a positive number of nm, got {step}; try 0.1");
    }
    let count = ((to - from) / step * (1.0 + 1e-12)).floor() + 1.0;
    let samples = count * args.angles.len() as f64;
    if samples > MAX_SAMPLES as f64 {
        bail!(
            "--step-nm: {step} nm over {from}–{to} nm at {} angles is {samples:.0} samples, \
             more than {MAX_SAMPLES}; use a larger step or a shorter range",
            args.angles.len()
        );
    }
    Ok((0..count as usize)
        .map(|i| from + i as f64 * step)
        .collect())
}

fn check_angles(angles: &[f64]) -> Result<()> {
    for &a in angles {
        if !(a.is_finite() && (0.0..90.0).contains(&a)) {
            bail!(
                "--angles: {a} is not an angle of incidence; give degrees in [0, 90), \
                 e.g. --angles 0,30,60"
            );
        }
    }
    Ok(())
}

/// cos θ inside the stone of an angle taken inside, degrees.
fn cos_of_inside(_: &ClusterStack, angle_deg: f64) -> f64 {
    angle_deg.to_radians().cos()
}

/// cos θ inside the stone of an angle of incidence in air, degrees (Snell into n_eff).
fn cos_of_air(stack: &ClusterStack, angle_deg: f64) -> f64 {
    cos_inside_from_air(stack.n_eff, angle_deg.to_radians())
}

/// R and T at `angle_deg` (inside, or in air refracted at the d line's `n_eff`) over
/// `wavelengths`, and the Bragg–Snell centre there (with a law, its fixed point).
fn curve(optics: &ClusterOptics, angle_deg: f64, inside: bool, wavelengths: &[f64]) -> AngleCurve {
    let cos_inside = if inside {
        cos_of_inside(&optics.stack, angle_deg)
    } else {
        cos_of_air(&optics.stack, angle_deg)
    };
    let bragg_nm = optics.bragg_wavelength_nm(cos_inside);
    let at = optics.at(cos_inside);
    let samples = wavelengths
        .iter()
        .map(|&wl| {
            let (r, t) = at.rt_unpolarized(wl);
            (wl, r, t)
        })
        .collect();
    AngleCurve {
        angle_deg,
        cos_inside,
        bragg_nm,
        samples,
    }
}

#[cfg(test)]
mod tests;
