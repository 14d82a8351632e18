//! Checking a scene after it is parsed: each section's ranges, then what spans sections (the
//! grains a stone would hold, an area light beyond the stone, the spectral image's size);
//! the first problem is returned with its field path and a fix. The range helpers every
//! section's `validate` uses are here.

use super::{DomainsConfig, LightKind, OrientationLaw, Pattern, Scene};
use crate::error::{Error, Result};

/// Most grains of a `domains.pattern = "grains"` stone (about 100 MB of grain data).
pub const MAX_GRAINS: u64 = 250_000;

/// Largest spectral image accepted, bytes (4 GiB).
pub const MAX_SPECTRAL_IMAGE_BYTES: u64 = 4 << 30;

impl Scene {
    /// Check every field's range; the first problem found is returned with its field path.
    pub fn validate(&self) -> Result<()> {
        self.structure.validate()?;
        self.crystal.validate()?;
        self.spectrum.validate("spectrum")?;
        self.light.validate()?;
        self.camera.validate()?;
        self.render.validate()?;
        self.color.validate()?;
        self.domains.validate()?;
        self.body.validate(self.structure.semi_axes_mm)?;
        self.environment.validate()?;
        self.integrator.validate()?;
        if self.domains.pattern == Pattern::Grains {
            self.check_grains()?;
            if self.domains.orientation == OrientationLaw::Correlated {
                self.check_parent_grains()?;
            }
        }
        self.validate_area_light()?;
        // The spectral image is width × height × bins floats: refuse what cannot fit.
        let bytes = u64::from(self.render.width)
            * u64::from(self.render.height)
            * self.spectrum.bins as u64
            * 4;
        if bytes > MAX_SPECTRAL_IMAGE_BYTES {
            return Err(Error::field(
                "render.width",
                format!(
                    "{} × {} pixels × {} bins would need {:.1} GiB for the spectral image, more \
                     than the limit of 4 GiB; lower render.width/height or spectrum.bins",
                    self.render.width,
                    self.render.height,
                    self.spectrum.bins,
                    bytes as f64 / (1u64 << 30) as f64
                ),
            ));
        }
        Ok(())
    }

    /// A sphere or rect light must lie beyond the stone.
    fn validate_area_light(&self) -> Result<()> {
        let kind = self.light.kind;
        if !matches!(kind, LightKind::Sphere | LightKind::Rect) {
            return Ok(());
        }
        let stone = self
            .structure
            .semi_axes_mm
            .iter()
            .fold(0.0f64, |a, &b| a.max(b));
        let d = self.light.distance_mm;
        if kind == LightKind::Sphere && self.light.radius_mm + stone >= d {
            return Err(Error::field(
                "light.radius_mm",
                format!(
                    "a ball of {} mm at {d} mm touches the stone (semi-axis up to {stone} mm); \
                     use a radius below {:.3} mm or a larger light.distance_mm",
                    self.light.radius_mm,
                    d - stone
                ),
            ));
        }
        if kind == LightKind::Rect && stone >= d {
            return Err(Error::field(
                "light.distance_mm",
                format!(
                    "a rect light at {d} mm cuts the stone (semi-axis up to {stone} mm); place \
                     it beyond {stone} mm"
                ),
            ));
        }
        Ok(())
    }
}

impl Scene {
    /// Refuse more grains than [`MAX_GRAINS`], naming the smallest `domains.grain_size_mm`
    /// (in hundredths) that fits.
    fn check_grains(&self) -> Result<()> {
        let axes = self.body.box_semi_axes(self.structure.semi_axes_mm);
        let count_at = |size_mm: f64| {
            DomainsConfig {
                grain_size_mm: size_mm,
                ..self.domains.clone()
            }
            .grain_count(axes)
        };
        let size = self.domains.grain_size_mm;
        let grains = count_at(size);
        if grains <= MAX_GRAINS as f64 {
            return Ok(());
        }
        // The count falls about as the size cubed (less near the box's margins): step up to
        // the first hundredth that fits.
        let mut smallest = (size * (grains / MAX_GRAINS as f64).cbrt() * 100.0).ceil() / 100.0;
        while count_at(smallest) > MAX_GRAINS as f64 {
            smallest += 0.01;
        }
        Err(Error::field(
            "domains.grain_size_mm",
            format!(
                "{size} mm grains would make about {grains:.0} grains in this stone, more than \
                 the limit of {MAX_GRAINS}; use at least {smallest:.2} mm"
            ),
        ))
    }

    /// Correlated orientations draw from parent grains of `domains.correlation_mm`: refuse
    /// more of them than [`MAX_GRAINS`] (they take as long to grow as grains do), naming the
    /// smallest length that fits.
    fn check_parent_grains(&self) -> Result<()> {
        let axes = self.body.box_semi_axes(self.structure.semi_axes_mm);
        let count_at = |length_mm: f64| {
            let parents = DomainsConfig {
                grain_size_mm: length_mm,
                stretch: [1.0; 3],
                boundary_roughness: 0.0,
                ..self.domains.clone()
            };
            parents.grain_count(axes)
        };
        let length = self.domains.correlation_mm;
        let count = count_at(length);
        if count <= MAX_GRAINS as f64 {
            return Ok(());
        }
        // The count falls about as the length cubed; step up to the first hundredth that fits.
        let mut smallest = (length * (count / MAX_GRAINS as f64).cbrt() * 100.0).ceil() / 100.0;
        while count_at(smallest) > MAX_GRAINS as f64 {
            smallest += 0.01;
        }
        Err(Error::field(
            "domains.correlation_mm",
            format!(
                "{length} mm parent grains would make about {count:.0} of them in this stone, \
                 more than the limit of {MAX_GRAINS}; use at least {smallest:.2} mm"
            ),
        ))
    }
}

/// Check that `value` is finite and within `[lo, hi]`; the error names `field` and a fix.
pub(crate) fn check_range(field: &str, value: f64, lo: f64, hi: f64, example: f64) -> Result<()> {
    if value.is_finite() && value >= lo && value <= hi {
        Ok(())
    } else {
        Err(Error::field(
            field,
            format!("must be a number in [{lo}, {hi}], got {value}; try {example}"),
        ))
    }
}

/// Check that the whole number `value` lies in `range`; the error says what the field `must
/// be` and what to `try`.
pub(crate) fn check_count(
    field: &str,
    value: u64,
    range: std::ops::RangeInclusive<u64>,
    must_be: &str,
    try_instead: &str,
) -> Result<()> {
    if range.contains(&value) {
        Ok(())
    } else {
        Err(Error::field(
            field,
            format!("must be {must_be}, got {value}; try {try_instead}"),
        ))
    }
}

/// Check that `value` is finite and strictly positive and at most `hi`.
pub(crate) fn check_positive(field: &str, value: f64, hi: f64, example: f64) -> Result<()> {
    if value.is_finite() && value > 0.0 && value <= hi {
        Ok(())
    } else {
        Err(Error::field(
            field,
            format!("must be a positive number at most {hi}, got {value}; try {example}"),
        ))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn correlated_grains_too_fine_to_grow_in_time_are_refused() {
        let text = "[integrator]\nmethod = \"path\"\n[domains]\npattern = \"grains\"\n\
                    orientation = \"correlated\"\ncorrelation_mm = 0.1";
        let err = Scene::from_toml_str(text, "t").unwrap_err().to_string();
        assert!(err.contains("domains.correlation_mm"), "{err}");
        // The length it names fits, a hundredth less does not.
        let fits: f64 = err
            .rsplit("at least ")
            .next()
            .and_then(|t| t.strip_suffix(" mm"))
            .and_then(|t| t.parse().ok())
            .unwrap_or_else(|| panic!("no length in {err}"));
        let with =
            |length: f64| Scene::from_toml_str(&text.replace("0.1", &format!("{length}")), "t");
        assert!(with(fits).is_ok(), "{fits}");
        assert!(with(fits - 0.01).is_err(), "{fits}");
    }

    #[test]
    fn the_grain_size_named_for_too_many_grains_fits() {
        // 0.05 mm grains in the paper's stone: about 23 million, over `MAX_GRAINS`.
        let text = "[domains]\npattern = \"grains\"\ngrain_size_mm = 0.05";
        let err = Scene::from_toml_str(text, "t").unwrap_err().to_string();
        assert!(err.contains("domains.grain_size_mm"), "{err}");
        let fits: f64 = err
            .rsplit("at least ")
            .next()
            .and_then(|t| t.strip_suffix(" mm"))
            .and_then(|t| t.parse().ok())
            .unwrap_or_else(|| panic!("no size in {err}"));
        let with = |size: f64| Scene::from_toml_str(&text.replace("0.05", &format!("{size}")), "t");
        assert!(with(fits).is_ok(), "{fits}: {}", with(fits).unwrap_err());
        assert!(with(fits - 0.01).is_err(), "{fits}");
    }

    #[test]
    fn out_of_range_values_are_refused() {
        for (text, field) in [
            ("[structure]\nvoid_ratio = 1.5", "structure.void_ratio"),
            ("[structure]\nvoid_ratio = 0.0", "structure.void_ratio"),
            ("[structure]\nvoid_ratio = nan", "structure.void_ratio"),
            (
                "[structure]\nmean_radius_cells = -6.0",
                "structure.mean_radius_cells",
            ),
            ("[structure]\ngrid = [100, 0, 25]", "structure.grid"),
            (
                "[structure]\nsemi_axes_mm = [10.0, -1.0, 2.0]",
                "structure.semi_axes_mm",
            ),
            (
                "[structure]\ngrid = [100000, 100000, 100000]",
                "structure.grid",
            ),
            (
                "[crystal]\nsphere_diameter_nm = -250.0",
                "crystal.sphere_diameter_nm",
            ),
            ("[crystal]\nn_sphere = 0.9", "crystal.n_sphere"),
            ("[render]\nwidth = 0", "render.width"),
            ("[render]\nbody_tone = 12", "render.body_tone"),
            ("[light]\nangle_deg = 120.0", "light.angle_deg"),
            ("[light]\ncutoff = 0.0", "light.cutoff"),
            ("[light]\ncutoff = 1e-7", "light.cutoff"),
            ("[light]\ncutoff = 0.8", "light.cutoff"),
            ("[light]\ncutoff = nan", "light.cutoff"),
            ("[render]\nwidth = 16384\nheight = 16384", "render.width"),
            (
                "[domains]\npattern = \"grains\"\ngrain_size_mm = 0.05",
                "domains.grain_size_mm",
            ),
            (
                "[domains]\nboundary_roughness = 1.5",
                "domains.boundary_roughness",
            ),
            ("[integrator]\nmethod = \"path\"\nspp = 0", "integrator.spp"),
            (
                "[integrator]\nmethod = \"stored\"\ncell_mm = 5.0",
                "integrator.cell_mm",
            ),
            (
                "[domains]\nsphere_diameter_spread = 0.5",
                "domains.sphere_diameter_spread",
            ),
            (
                "[domains]\ndiameter_correlation_mm = 0.05",
                "domains.diameter_correlation_mm",
            ),
            (
                "[domains]\ndiameter_correlation_mm = -1.0",
                "domains.diameter_correlation_mm",
            ),
            (
                "[domains]\ndiameter_correlation_mm = nan",
                "domains.diameter_correlation_mm",
            ),
            (
                "[domains]\ntilt_correlation_mm = 0.05",
                "domains.tilt_correlation_mm",
            ),
            (
                "[domains]\ntilt_jitter_deg = -1.0",
                "domains.tilt_jitter_deg",
            ),
            (
                "[domains]\ntilt_correlation_mm = 3.0\norientation_spread_deg = 4.0",
                "domains.tilt_jitter_deg",
            ),
        ] {
            let err = Scene::from_toml_str(text, "t").unwrap_err().to_string();
            assert!(err.contains(field), "{text}: {err}");
        }
    }
}
