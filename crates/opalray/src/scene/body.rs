//! The stone's body for the stone model (path integrator): its cut (ellipsoid, cabochon,
//! doublet, triplet), where its play of colour lies (throughout or a colour bar), what it sits
//! on, and the potch's scattering (`[body]`).

use serde::{Deserialize, Serialize};

use super::check_range;
use crate::error::{Error, Result};

/// The stone's cut.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum Cut {
    /// The paper's double-convex ellipsoid (`structure.semi_axes_mm`).
    #[default]
    Ellipsoid,
    /// An elliptical dome over a flat or gently domed back (girdle: `structure.semi_axes_mm`
    /// x and y).
    Cabochon,
    /// A thin opal cabochon with a flat back glued on a backing (`backing`, default black).
    Doublet,
    /// An opal slice (`slice_mm`) on a backing under a clear quartz dome (`cap_index`).
    Triplet,
}

/// What the flat back of a cabochon, doublet or triplet is glued on.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum Backing {
    /// Nothing: the back is a polished surface like the dome (a cabochon's default).
    #[default]
    None,
    /// Black glass, onyx or potch: reflects 3 %, diffusely (the doublet's and triplet's
    /// default).
    Black,
    /// Ironstone (boulder opal): a brown diffuse matrix reflecting 6 % (blue) to 22 % (red).
    Ironstone,
}

/// The body.
///
/// | field                     | unit | default      | valid                                          |
/// |---------------------------|------|--------------|------------------------------------------------|
/// | `cut`                     | –    | "ellipsoid"  | "ellipsoid", "cabochon", "doublet", "triplet"  |
/// | `dome_height_mm`          | mm   | 3.0          | [0.2, 50], at most the girdle's smaller semi-axis × 2 |
/// | `back_height_mm`          | mm   | 0.0          | [0, 50]; 0 (flat) with a backing               |
/// | `colour_bar_mm`           | mm   | 0.0          | [0, 50]; 0: play of colour throughout          |
/// | `slice_mm`                | mm   | 1.0          | [0.1, 50], below the dome height (triplet)     |
/// | `backing`                 | –    | by cut       | "none", "black", "ironstone"                   |
/// | `cap_index`               | –    | 1.544        | [1.3, 2.5]                                     |
/// | `potch_extinction_per_mm` | 1/mm | 3.0          | [0.01, 1000]                                   |
/// | `anisotropy`              | –    | 0.4          | [−0.95, 0.95]                                  |
/// | `domain_haze`             | –    | 0.0          | [0, 1]                                         |
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct BodyConfig {
    /// The cut.
    pub cut: Cut,
    /// Cabochon, doublet, triplet: height of the dome above the girdle, mm.
    pub dome_height_mm: f64,
    /// Cabochon: height of the domed back below the girdle, mm (0: flat).
    pub back_height_mm: f64,
    /// Thickness of the layer of play of colour under the dome, mm (a black opal's colour
    /// bar over its potch); 0: the domains fill the stone.
    pub colour_bar_mm: f64,
    /// Triplet: thickness of the opal slice under the quartz cap, mm.
    pub slice_mm: f64,
    /// What the flat back sits on; `None` in a file takes the cut's default.
    pub backing: Option<Backing>,
    /// Triplet: refractive index of the clear cap (quartz 1.544).
    pub cap_index: f64,
    /// Extinction coefficient of the potch, per mm (its mean free path is the inverse).
    pub potch_extinction_per_mm: f64,
    /// Henyey–Greenstein anisotropy `g` of the potch's scattering (0: isotropic).
    pub anisotropy: f64,
    /// Scattering inside the domains as a share of the potch's scattering coefficient
    /// (without its absorption): white opal is milky throughout, crystal opal clear.
    pub domain_haze: f64,
}

impl Default for BodyConfig {
    fn default() -> Self {
        BodyConfig {
            cut: Cut::Ellipsoid,
            dome_height_mm: 3.0,
            back_height_mm: 0.0,
            colour_bar_mm: 0.0,
            slice_mm: 1.0,
            backing: None,
            cap_index: 1.544,
            potch_extinction_per_mm: 3.0,
            anisotropy: 0.4,
            domain_haze: 0.0,
        }
    }
}

impl BodyConfig {
    /// The backing in effect: the given one, or the cut's default.
    pub fn backing(&self) -> Backing {
        self.backing.unwrap_or(match self.cut {
            Cut::Doublet | Cut::Triplet => Backing::Black,
            Cut::Ellipsoid | Cut::Cabochon => Backing::None,
        })
    }

    /// Semi-axes of the stone's bounding box (centred on the origin), mm, for a girdle of
    /// semi-axes `semi_axes_mm` x and y (the ellipsoid: `semi_axes_mm` itself).
    pub fn box_semi_axes(&self, semi_axes_mm: [f64; 3]) -> [f64; 3] {
        match self.cut {
            Cut::Ellipsoid => semi_axes_mm,
            Cut::Cabochon => [
                semi_axes_mm[0],
                semi_axes_mm[1],
                0.5 * (self.dome_height_mm + self.back_height_mm),
            ],
            Cut::Doublet | Cut::Triplet => {
                [semi_axes_mm[0], semi_axes_mm[1], 0.5 * self.dome_height_mm]
            }
        }
    }

    /// Check ranges and the combinations a cut allows; `semi_axes_mm` is the girdle's.
    pub fn validate(&self, semi_axes_mm: [f64; 3]) -> Result<()> {
        check_range("body.dome_height_mm", self.dome_height_mm, 0.2, 50.0, 3.0)?;
        check_range("body.back_height_mm", self.back_height_mm, 0.0, 50.0, 0.0)?;
        check_range("body.colour_bar_mm", self.colour_bar_mm, 0.0, 50.0, 1.0)?;
        check_range("body.slice_mm", self.slice_mm, 0.1, 50.0, 1.0)?;
        check_range("body.cap_index", self.cap_index, 1.3, 2.5, 1.544)?;
        check_range(
            "body.potch_extinction_per_mm",
            self.potch_extinction_per_mm,
            0.01,
            1000.0,
            3.0,
        )?;
        check_range("body.anisotropy", self.anisotropy, -0.95, 0.95, 0.4)?;
        check_range("body.domain_haze", self.domain_haze, 0.0, 1.0, 0.0)?;
        let girdle = semi_axes_mm[0].min(semi_axes_mm[1]);
        if self.cut != Cut::Ellipsoid && self.dome_height_mm > 2.0 * girdle {
            return Err(Error::field(
                "body.dome_height_mm",
                format!(
                    "a dome of {} mm over a girdle {girdle} mm in its smaller semi-axis is not a \
                     cabochon; use at most {}",
                    self.dome_height_mm,
                    2.0 * girdle
                ),
            ));
        }
        let backed = self.backing() != Backing::None;
        if backed && self.cut == Cut::Ellipsoid {
            return Err(Error::field(
                "body.backing",
                "an ellipsoid has no flat back to glue on a backing; use body.cut = \"cabochon\" \
                 or \"doublet\", or backing = \"none\"",
            ));
        }
        if backed && self.back_height_mm > 0.0 {
            return Err(Error::field(
                "body.back_height_mm",
                "a backing needs a flat back; set back_height_mm = 0 or backing = \"none\"",
            ));
        }
        if self.cut == Cut::Triplet && self.slice_mm >= self.dome_height_mm {
            return Err(Error::field(
                "body.slice_mm",
                format!(
                    "a triplet's opal slice ({} mm) must be thinner than its dome ({} mm); try {}",
                    self.slice_mm,
                    self.dome_height_mm,
                    0.3 * self.dome_height_mm
                ),
            ));
        }
        Ok(())
    }
}
