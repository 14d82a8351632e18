//! The stone's sections: what the opal is. Its shape, cell grid and cluster growth
//! (`[structure]`) and the FCC crystal inside each cluster (`[crystal]`), each a parameter
//! table with defaults and a `validate`.

use serde::{Deserialize, Serialize};

use super::{check_positive, check_range};
use crate::error::{Error, Result};

/// Largest cell grid accepted: 64 million cells (about 1.5 GiB of structure data).
pub const MAX_CELLS: u64 = 64_000_000;

/// Opal shape, cell grid and cluster growth (paper §2.4, DESIGN §3).
///
/// | field                    | unit  | default           | valid                      |
/// |--------------------------|-------|-------------------|----------------------------|
/// | `grid`                   | cells | [100, 75, 25]     | each ≥ 1, product ≤ 64 M   |
/// | `semi_axes_mm`           | mm    | [10.0, 7.5, 2.5]  | each in (0, 1000]          |
/// | `mean_radius_cells`      | cells | 6.0               | (0, 1000]                  |
/// | `void_ratio`             | –     | 0.2               | (0, 1)                     |
/// | `seed`                   | –     | 1                 | 0 ..= 2⁶³ − 1              |
/// | `orientation_jitter_deg` | deg   | 0.0               | [0, 180]                   |
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct StructureConfig {
    /// Cells along x, y, z over the ellipsoid's bounding box (paper: 100 × 75 × 25).
    #[serde(deserialize_with = "super::shape::three")]
    pub grid: [usize; 3],
    /// The ellipsoid's semi-axes along x, y, z in millimetres.
    #[serde(deserialize_with = "super::shape::three")]
    pub semi_axes_mm: [f64; 3],
    /// Mean neighbourhood radius `R` of eq. (1), in cells (paper: 6).
    pub mean_radius_cells: f64,
    /// Growth stops once void cells / inside cells falls below this (paper: "the average
    /// void ratio of real opal"; no number given, 0.2 here).
    pub void_ratio: f64,
    /// Seed of every random stream of the scene (structure, light pass, view pass).
    pub seed: u64,
    /// Standard deviation of a random tilt added to each grown patch's orientation, degrees.
    /// 0 reproduces the paper; larger values make neighbouring patches differ more sharply.
    pub orientation_jitter_deg: f64,
}

impl Default for StructureConfig {
    fn default() -> Self {
        StructureConfig {
            grid: [100, 75, 25],
            semi_axes_mm: [10.0, 7.5, 2.5],
            mean_radius_cells: 6.0,
            void_ratio: 0.2,
            seed: 1,
            orientation_jitter_deg: 0.0,
        }
    }
}

impl StructureConfig {
    /// Total number of cells of the grid.
    pub fn cell_count(&self) -> u64 {
        self.grid.iter().map(|&n| n as u64).product()
    }

    /// Check ranges; refuses grids over [`MAX_CELLS`] before anything is allocated.
    pub fn validate(&self) -> Result<()> {
        if self.grid.contains(&0) {
            return Err(Error::field(
                "structure.grid",
                format!(
                    "every size must be at least 1, got {:?}; try [100, 75, 25]",
                    self.grid
                ),
            ));
        }
        let cells = self
            .grid
            .iter()
            .try_fold(1u64, |acc, &n| acc.checked_mul(n as u64))
            .unwrap_or(u64::MAX);
        if cells > MAX_CELLS {
            return Err(Error::field(
                "structure.grid",
                format!(
                    "{:?} is {cells} cells, more than the limit of {MAX_CELLS} \
                     (about {:.0} GiB of memory); use a coarser grid such as [400, 300, 100]",
                    self.grid,
                    cells as f64 * 24.0 / (1u64 << 30) as f64
                ),
            ));
        }
        for (axis, &a) in ["x", "y", "z"].iter().zip(&self.semi_axes_mm) {
            if !(a.is_finite() && a > 0.0 && a <= 1000.0) {
                return Err(Error::field(
                    "structure.semi_axes_mm",
                    format!(
                        "the {axis} semi-axis must be in (0, 1000] mm, got {a}; \
                         try [10.0, 7.5, 2.5]"
                    ),
                ));
            }
        }
        check_positive(
            "structure.mean_radius_cells",
            self.mean_radius_cells,
            1000.0,
            6.0,
        )?;
        if !(self.void_ratio.is_finite() && self.void_ratio > 0.0 && self.void_ratio < 1.0) {
            return Err(Error::field(
                "structure.void_ratio",
                format!(
                    "must be strictly between 0 and 1, got {}; try 0.2",
                    self.void_ratio
                ),
            ));
        }
        if i64::try_from(self.seed).is_err() {
            return Err(Error::field(
                "structure.seed",
                format!(
                    "must be at most {} (TOML integers are signed 64-bit), got {}; try 1",
                    i64::MAX,
                    self.seed
                ),
            ));
        }
        check_range(
            "structure.orientation_jitter_deg",
            self.orientation_jitter_deg,
            0.0,
            180.0,
            0.0,
        )
    }
}

/// The FCC crystal of silica spheres inside every cluster (paper §2.3, DESIGN §4).
/// Defaults model natural precious opal; see `docs/model.md` for the sources.
///
/// | field                | unit | default | valid        |
/// |----------------------|------|---------|--------------|
/// | `sphere_diameter_nm` | nm   | 250     | [50, 2000]   |
/// | `n_sphere`           | –    | 1.45    | [1, 4]       |
/// | `n_matrix`           | –    | 1.42    | [1, 4]       |
/// | `filling_fraction`   | –    | 0.74    | (0, 1)       |
/// | `layers`             | –    | 400     | 1 ..= 100000 |
/// | `diffuse_fraction`   | –    | 0.15    | [0, 1)       |
/// | `angles`             | –    | 181     | 90 ..= 10000 |
/// | `dispersion`         | –    | "none"  | "none", "silica" |
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct CrystalConfig {
    /// Silica sphere diameter `D`, nm.
    pub sphere_diameter_nm: f64,
    /// Refractive index of the silica spheres (at the sodium d line, 589.3 nm, when
    /// `dispersion` gives a law).
    pub n_sphere: f64,
    /// Refractive index of the matrix between spheres (silica cement in natural opal; at the
    /// sodium d line when `dispersion` gives a law).
    pub n_matrix: f64,
    /// Volume fraction of spheres (0.74 for close-packed FCC).
    pub filling_fraction: f64,
    /// Coherent (111) layers `N` in one cluster.
    pub layers: u32,
    /// Share of the Bragg reflection scattered diffusely (stacking faults, size spread).
    pub diffuse_fraction: f64,
    /// Entries of the reflectance tables over incidence angle 0–90° inside the stone.
    pub angles: usize,
    /// How `n_sphere` and `n_matrix` vary with wavelength: constant (the paper's) or by
    /// silica's law ([`crate::optics::dispersion`]).
    pub dispersion: Dispersion,
}

/// How the crystal's indices vary with wavelength (`crystal.dispersion`).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum Dispersion {
    /// Constant over wavelength, as in the paper.
    #[default]
    None,
    /// Fused silica's Sellmeier law (Malitson 1965) for the spheres and the cement alike,
    /// shifted to the scene's indices at the sodium d line:
    /// `n(λ) = n_d + n_silica(λ) − n_silica(589.3 nm)`.
    Silica,
}

impl Default for CrystalConfig {
    fn default() -> Self {
        CrystalConfig {
            sphere_diameter_nm: 250.0,
            n_sphere: 1.45,
            n_matrix: 1.42,
            filling_fraction: 0.74,
            layers: 400,
            diffuse_fraction: 0.15,
            angles: 181,
            dispersion: Dispersion::None,
        }
    }
}

impl CrystalConfig {
    /// Check ranges.
    pub fn validate(&self) -> Result<()> {
        check_range(
            "crystal.sphere_diameter_nm",
            self.sphere_diameter_nm,
            50.0,
            2000.0,
            250.0,
        )?;
        check_range("crystal.n_sphere", self.n_sphere, 1.0, 4.0, 1.45)?;
        check_range("crystal.n_matrix", self.n_matrix, 1.0, 4.0, 1.42)?;
        if !(self.filling_fraction > 0.0 && self.filling_fraction < 1.0) {
            return Err(Error::field(
                "crystal.filling_fraction",
                format!(
                    "must be strictly between 0 and 1, got {}; try 0.74",
                    self.filling_fraction
                ),
            ));
        }
        if !(1..=100_000).contains(&self.layers) {
            return Err(Error::field(
                "crystal.layers",
                format!("must be in 1..=100000, got {}; try 400", self.layers),
            ));
        }
        if !(self.diffuse_fraction >= 0.0 && self.diffuse_fraction < 1.0) {
            return Err(Error::field(
                "crystal.diffuse_fraction",
                format!("must be in [0, 1), got {}; try 0.15", self.diffuse_fraction),
            ));
        }
        if !(90..=10_000).contains(&self.angles) {
            return Err(Error::field(
                "crystal.angles",
                format!("must be in 90..=10000, got {}; try 181", self.angles),
            ));
        }
        Ok(())
    }
}
