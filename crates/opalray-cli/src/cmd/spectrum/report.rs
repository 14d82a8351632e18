//! What the spectrum command reports: each angle's curve of R and T, the CSV of the curves
//! and the summary printed on stdout.

use std::fmt::Write as _;
use std::path::Path;

use opalray::color::SpectrumColor;
use opalray::optics::ClusterOptics;
use opalray::scene::{Dispersion, Illuminant};

use super::Args;

/// R and T over wavelength at one angle.
pub(super) struct AngleCurve {
    /// The angle as given on the command line, degrees.
    pub(super) angle_deg: f64,
    /// cos θ inside the stone.
    pub(super) cos_inside: f64,
    /// Bragg–Snell first-order wavelength, nm.
    pub(super) bragg_nm: f64,
    /// `(wavelength_nm, R, T)` samples.
    pub(super) samples: Vec<(f64, f64, f64)>,
}

impl AngleCurve {
    /// Wavelength and value of the largest R.
    pub(super) fn peak(&self) -> (f64, f64) {
        self.samples.iter().fold(
            (f64::NAN, -1.0),
            |best, &(wl, r, _)| {
                if r > best.1 {
                    (wl, r)
                } else {
                    best
                }
            },
        )
    }

    /// The colour of the light reflected under D65: the curve as a reflectance lit by D65.
    pub(super) fn colour(&self) -> SpectrumColor {
        let reflectance: Vec<(f64, f64)> = self.samples.iter().map(|&(wl, r, _)| (wl, r)).collect();
        SpectrumColor::of_reflectance(&reflectance, Illuminant::D65)
    }
}

/// Decimals that print every multiple of `step` exactly (at most 9).
pub(super) fn decimals_of(step: f64) -> usize {
    (0..9)
        .find(|&d| {
            let scaled = step * 10f64.powi(d as i32);
            (scaled - scaled.round()).abs() < 1e-9 * scaled.max(1.0)
        })
        .unwrap_or(9)
}

pub(super) fn write_csv(
    path: &Path,
    curves: &[AngleCurve],
    decimals: usize,
) -> opalray::Result<()> {
    opalray::output::write_atomic(path, |w| {
        writeln!(w, "wavelength_nm,angle_deg,reflectance,transmittance")?;
        for c in curves {
            for &(wl, r, t) in &c.samples {
                writeln!(w, "{wl:.decimals$},{},{r},{t}", c.angle_deg)?;
            }
        }
        Ok(())
    })
}

/// The report printed on stdout.
pub(super) fn summary(optics: &ClusterOptics, curves: &[AngleCurve], args: &Args) -> String {
    let (crystal, stack) = (&optics.crystal, &optics.stack);
    let mut out = String::new();
    let _ = writeln!(
        out,
        "FCC cluster: D {} nm, n_sphere {}, n_matrix {} (at 589.3 nm), filling {}, {} layers, \
         dispersion {}",
        crystal.sphere_diameter_nm,
        crystal.n_sphere,
        crystal.n_matrix,
        crystal.filling_fraction,
        crystal.layers,
        match crystal.dispersion {
            Dispersion::None => "none",
            Dispersion::Silica => "silica",
        }
    );
    let _ = write!(
        out,
        "  d111 {:.2} nm, n_eff {:.4}",
        stack.d111_nm, stack.n_eff
    );
    match optics.stop_band_nm() {
        Some((lo, hi)) => {
            let _ = writeln!(
                out,
                ", stop band at normal incidence {lo:.2}–{hi:.2} nm ({:.2} % wide)",
                200.0 * (hi - lo) / (hi + lo)
            );
        }
        None => out.push('\n'),
    }
    let frame = if args.inside { "inside" } else { "air" };
    let _ = writeln!(
        out,
        "{:>12} {:>9} {:>10} {:>8} {:>16} {:>10}",
        format!("angle {frame}"),
        "θ inside",
        "peak nm",
        "peak R",
        "Bragg–Snell nm",
        "sRGB D65"
    );
    for c in curves {
        let (peak_nm, peak_r) = c.peak();
        let in_range = (args.from_nm..=args.to_nm).contains(&c.bragg_nm);
        let _ = writeln!(
            out,
            "{:>11.1}° {:>8.1}° {:>10.2} {:>8.4} {:>16.2} {:>10}{}",
            c.angle_deg,
            c.cos_inside.clamp(-1.0, 1.0).acos().to_degrees(),
            peak_nm,
            peak_r,
            c.bragg_nm,
            c.colour().hex(),
            if in_range {
                ""
            } else {
                "  (Bragg line outside --from-nm..--to-nm)"
            }
        );
    }
    out
}
