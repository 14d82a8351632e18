//! How a domain crossing draws its reflection (the module outline in [`super`]): each line's
//! share of the light of the path that meets it — of white light before its first
//! reflection, of its own light after ([`PathSpectrum::reflectances`]), the unpolarised
//! mean either way (the choice's probability; the polarised factors go in the weight).

use super::spectral::{PathSpectrum, MAX_DRAWS};
use crate::optics::BraggLine;
use crate::stone::ActiveLine;

/// Most lines one domain crossing can have (one per family normal: 4 + 6 + 12 + 3).
pub(super) const MAX_LINES_PER_CROSSING: usize = 25;
/// Least share of an already reflected path's light a line is drawn with, as a fraction of
/// its share of white light (keeps every branch possible, so the estimate unbiased).
const MIN_SHARE_OF_WHITE: f64 = 0.01;

/// A reflected path's reflectances `(R_s, R_p)` by each line of a crossing at each of its
/// wavelengths.
pub(super) type Reflectances = [[[f32; 2]; MAX_DRAWS]; MAX_LINES_PER_CROSSING];

/// Each line's share in `energy`: of white light ([`line_energy`]); for a path already
/// reflected (`at_path` given), of its own light, what the line reflects at the wavelengths
/// it carries (kept in `at_path`), at least [`MIN_SHARE_OF_WHITE`] of the white share.
pub(super) fn line_shares(
    here: &[ActiveLine],
    path: &PathSpectrum,
    energy: &mut [f64; MAX_LINES_PER_CROSSING],
    at_path: &mut Option<Reflectances>,
) {
    for (i, (e, l)) in energy.iter_mut().zip(here).enumerate() {
        let white = line_energy(&l.line);
        *e = match at_path {
            Some(r) => path
                .reflectances(&l.line, &mut r[i])
                .max(MIN_SHARE_OF_WHITE * white),
            None => white,
        };
    }
}

/// A line's share of white light: its area over wavelength over the 400 nm of the visible.
/// The area is `ν² λ/N` for a weak grating (the side lobes' sum) and `2νλ/(πN)` (the stop
/// band) for a saturated one; `ν² λ / (N (1 + πν/2))` joins the two.
fn line_energy(line: &BraggLine) -> f64 {
    let nu = 0.5 * (line.nu_s + line.nu_p);
    let area = nu * nu * line.center_nm / (line.layers * (1.0 + 0.5 * std::f64::consts::PI * nu));
    (area / 400.0).max(1e-9)
}
