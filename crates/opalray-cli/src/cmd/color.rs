//! `opalray color`: the colour of a spectrum given as CSV (paper §3.4).
//!
//! Reads `wavelength_nm,value` lines (any sampling), integrates exactly against the CIE 1931
//! 2° colour-matching functions and prints JSON: XYZ, xy, linear sRGB, encoded sRGB, hex.

use std::path::PathBuf;

use anyhow::Result;
use opalray::color::{parse_spectrum_csv, SpectrumColor};
use opalray::scene::Illuminant;
use serde::Serialize;

/// A CIE illuminant on the command line.
#[derive(clap::ValueEnum, Clone, Copy, Debug)]
pub enum IlluminantArg {
    /// CIE D65, average daylight.
    D65,
    /// CIE A, incandescent tungsten.
    A,
    /// CIE C, the white of the paper's NTSC matrix.
    C,
    /// The equal-energy spectrum.
    E,
}

impl From<IlluminantArg> for Illuminant {
    fn from(arg: IlluminantArg) -> Self {
        match arg {
            IlluminantArg::D65 => Illuminant::D65,
            IlluminantArg::A => Illuminant::A,
            IlluminantArg::C => Illuminant::C,
            IlluminantArg::E => Illuminant::E,
        }
    }
}

/// Arguments of `opalray color`.
///
/// An emission spectrum (the default) is shown at the brightest display level that keeps its
/// chromaticity; a reflectance (`--reflectance`) is lit by the illuminant, adapted (Bradford)
/// to the D65 white of sRGB, and keeps its luminance factor (a white reflector is #ffffff).
#[derive(clap::Args, Debug)]
pub struct Args {
    /// CSV file of `wavelength_nm,value` lines, any sampling, wavelengths increasing (a
    /// header line and `#` comments are allowed). Read as piecewise linear, zero outside.
    #[arg(value_name = "SPECTRUM.csv")]
    pub spectrum: PathBuf,
    /// The values are a reflectance (or transmittance, 0–1) lit by the illuminant; its colour
    /// is white-balanced to sRGB's D65, so a perfect white is #ffffff. Without this flag the
    /// values are an emitted spectrum, shown at the brightest level that keeps its chromaticity.
    #[arg(long)]
    pub reflectance: bool,
    /// Light for `--reflectance` [default: d65].
    #[arg(long, value_enum, value_name = "NAME", ignore_case = true)]
    pub illuminant: Option<IlluminantArg>,
}

/// What `opalray color` prints, in this order.
#[derive(Serialize)]
struct Report {
    file: String,
    mode: &'static str,
    illuminant: Option<String>,
    samples: usize,
    range_nm: [f64; 2],
    xyz: [f64; 3],
    xy: Option<[f64; 2]>,
    srgb_linear: [f64; 3],
    in_gamut: bool,
    srgb: [f64; 3],
    srgb8: [u8; 3],
    hex: String,
}

/// Round for printing: 6 decimals carry everything a colour needs.
fn round6(v: f64) -> f64 {
    (v * 1e6).round() / 1e6
}

/// Run `opalray color`.
pub fn run(args: Args) -> Result<()> {
    if args.illuminant.is_some() && !args.reflectance {
        anyhow::bail!(
            "--illuminant lights a reflectance: add --reflectance, or drop --illuminant for an \
             emission spectrum"
        );
    }
    let text = super::common::read_input("spectrum", &args.spectrum, super::common::MAX_CSV_BYTES)?;
    let samples = parse_spectrum_csv(&text, &args.spectrum)?;
    let (first_nm, last_nm) = (samples[0].0, samples[samples.len() - 1].0);
    if last_nm <= 360.0 || first_nm >= 830.0 {
        anyhow::bail!(
            "{}: the samples cover {first_nm}–{last_nm} nm, outside the 360–830 nm the CIE \
             observer sees; give wavelengths in nm",
            args.spectrum.display()
        );
    }
    let illuminant = Illuminant::from(args.illuminant.unwrap_or(IlluminantArg::D65));
    let color = if args.reflectance {
        SpectrumColor::of_reflectance(&samples, illuminant)
    } else {
        SpectrumColor::of_emission(&samples)
    };
    // Values near f64's limit overflow the colour integrals: refuse rather than print null.
    let finite = color
        .xyz
        .iter()
        .chain(&color.srgb_linear)
        .all(|v| v.is_finite());
    if !finite {
        anyhow::bail!(
            "{}: the values are too large to integrate (XYZ overflows); scale them down, \
             e.g. to at most 1e30",
            args.spectrum.display()
        );
    }
    let report = Report {
        file: args.spectrum.display().to_string(),
        mode: if args.reflectance {
            "reflectance"
        } else {
            "emission"
        },
        illuminant: args.reflectance.then(|| format!("{illuminant:?}")),
        samples: samples.len(),
        range_nm: [samples[0].0, samples[samples.len() - 1].0],
        xyz: color.xyz.map(round6),
        xy: color.xy.map(|xy| xy.map(round6)),
        srgb_linear: color.srgb_linear.map(round6),
        in_gamut: color.in_gamut,
        srgb: color.srgb.map(round6),
        srgb8: color.srgb8,
        hex: color.hex(),
    };
    let text = serde_json::to_string_pretty(&report).expect("JSON values serialise");
    crate::stdio::out(format_args!("{text}"))?;
    Ok(())
}
