//! The look's sections: how the opal is lit, seen and coloured. The light (`[light]`), the
//! camera (`[camera]`), image size and shading (`[render]`) and spectrum → RGB (`[color]`),
//! each a parameter table with defaults and a `validate`.

use serde::{Deserialize, Serialize};

use super::{check_count, check_positive, check_range};
use crate::error::{Error, Result};

/// Kind of light source.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum LightKind {
    /// Parallel rays from a distant source (the default, as in fig. 10).
    Directional,
    /// A point source at `distance_mm` from the opal's centre.
    Point,
    /// A glowing ball of `radius_mm` centred where the point light would be (path integrator
    /// only).
    Sphere,
    /// A rectangular softbox of `size_mm` centred where the point light would be, facing the
    /// opal's centre (path integrator only).
    Rect,
    /// No light of its own: the environment lights the stone (path integrator only).
    None,
}

/// A CIE standard illuminant used as the light's spectrum.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub enum Illuminant {
    /// CIE D65, average daylight (6504 K).
    D65,
    /// CIE A, incandescent tungsten (2856 K).
    A,
    /// CIE C, the white of the paper's NTSC matrix.
    C,
    /// The equal-energy spectrum.
    E,
}

/// The light source (paper fig. 10).
///
/// | field          | unit | default       | valid                                     |
/// |----------------|------|---------------|-------------------------------------------|
/// | `kind`         | –    | "directional" | "directional", "point", "sphere", "rect", "none" |
/// | `angle_deg`    | deg  | 30            | [−89, 89]                                 |
/// | `illuminant`   | –    | "D65"         | "D65", "A", "C", "E"                      |
/// | `intensity`    | –    | 1.0           | (0, 1e6]                                  |
/// | `distance_mm`  | mm   | 100           | (0, 1e6]; beyond the stone (and the ball) |
/// | `radius_mm`    | mm   | 10            | (0, 1e5]; "sphere"                        |
/// | `size_mm`      | mm   | [100, 100]    | each (0, 1e5]; "rect": width, height      |
/// | `rays`         | –    | 65536         | 1 ..= 1e9                                 |
/// | `cutoff`       | –    | 0.02          | [1e-4, 0.5]                               |
/// | `roulette`     | –    | false         | true, false                               |
///
/// Every light gives the irradiance `intensity` at the opal's centre on a plane facing it:
/// a sphere or rect light's radiance is set so (a small, far one looks like the point
/// light). The rect's width runs in the plane of the light angle (the camera's horizontal),
/// its height along the picture's up.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct LightConfig {
    /// Directional or point light.
    pub kind: LightKind,
    /// Angle θ between the view direction and the light-to-opal direction (fig. 10), rotated
    /// about the camera's up axis; the paper sweeps −60° … 60°.
    pub angle_deg: f64,
    /// Spectrum of the light.
    pub illuminant: Illuminant,
    /// Scale of the light's irradiance (1 = the illuminant normalised to unit luminance).
    pub intensity: f64,
    /// Distance of a point light, or of the centre of a sphere or rect light, from the opal's
    /// centre, mm.
    pub distance_mm: f64,
    /// Radius of a sphere light, mm.
    pub radius_mm: f64,
    /// Width and height of a rect light, mm.
    #[serde(deserialize_with = "super::shape::two")]
    pub size_mm: [f64; 2],
    /// Cells of the light pass's ray lattice: one ray each, 2 × 2 where the light is trapped.
    pub rays: u64,
    /// Light below this fraction of its ray's entering power is cut (or plays roulette).
    pub cutoff: f64,
    /// Russian roulette below the cutoff instead of a cut: unbiased, noisier, slower.
    pub roulette: bool,
}

impl Default for LightConfig {
    fn default() -> Self {
        LightConfig {
            kind: LightKind::Directional,
            angle_deg: 30.0,
            illuminant: Illuminant::D65,
            intensity: 1.0,
            distance_mm: 100.0,
            radius_mm: 10.0,
            size_mm: [100.0, 100.0],
            rays: 65_536,
            cutoff: LightConfig::DEFAULT_CUTOFF,
            roulette: false,
        }
    }
}

impl LightConfig {
    /// The default `cutoff`: light under 2 % of its ray's power is cut.
    pub const DEFAULT_CUTOFF: f64 = 0.02;

    /// Check ranges.
    pub fn validate(&self) -> Result<()> {
        check_range("light.angle_deg", self.angle_deg, -89.0, 89.0, 30.0)?;
        check_positive("light.intensity", self.intensity, 1e6, 1.0)?;
        check_positive("light.distance_mm", self.distance_mm, 1e6, 100.0)?;
        check_positive("light.radius_mm", self.radius_mm, 1e5, 10.0)?;
        for s in self.size_mm {
            check_positive("light.size_mm", s, 1e5, 100.0)?;
        }
        // Below 10⁻⁴ the weak tail makes the light pass run for minutes (10⁻⁷: 1.2 G cells
        // crossed for 4096 rays).
        check_range(
            "light.cutoff",
            self.cutoff,
            1e-4,
            0.5,
            LightConfig::DEFAULT_CUTOFF,
        )?;
        check_count(
            "light.rays",
            self.rays,
            1..=1_000_000_000,
            "in 1..=1000000000",
            "65536",
        )
    }
}

/// The camera, looking at the opal's broad face from +z (paper fig. 10).
///
/// | field          | unit | default | valid       |
/// |----------------|------|---------|-------------|
/// | `distance_mm`  | mm   | 100     | (0, 1e6]    |
/// | `fov_deg`      | deg  | 13.5    | (0, 170]    |
/// | `tilt_deg`     | deg  | 0       | [−89, 89]   |
/// | `turn_deg`     | deg  | 0       | [−360, 360] |
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct CameraConfig {
    /// Distance from the camera to the opal's centre, mm.
    pub distance_mm: f64,
    /// Vertical field of view, degrees.
    pub fov_deg: f64,
    /// Tilt of the opal towards the camera about the x axis, degrees (0: face on).
    pub tilt_deg: f64,
    /// Turn of the opal about its face's normal (z), counter-clockwise seen from the camera,
    /// degrees, before the tilt; the camera and the lights stay where they are.
    pub turn_deg: f64,
}

impl Default for CameraConfig {
    fn default() -> Self {
        CameraConfig {
            distance_mm: 100.0,
            fov_deg: 13.5,
            tilt_deg: 0.0,
            turn_deg: 0.0,
        }
    }
}

impl CameraConfig {
    /// Check ranges.
    pub fn validate(&self) -> Result<()> {
        check_positive("camera.distance_mm", self.distance_mm, 1e6, 100.0)?;
        check_positive("camera.fov_deg", self.fov_deg, 170.0, 13.5)?;
        check_range("camera.tilt_deg", self.tilt_deg, -89.0, 89.0, 0.0)?;
        check_range("camera.turn_deg", self.turn_deg, -360.0, 360.0, 0.0)
    }
}

/// Image size and shading (paper §3.3, eq. 2).
///
/// | field              | unit | default | valid        |
/// |--------------------|------|---------|--------------|
/// | `width`            | px   | 640     | 1 ..= 16384  |
/// | `height`           | px   | 480     | 1 ..= 16384  |
/// | `phong_exponent`   | –    | 40      | [0, 10000]   |
/// | `body_tone`        | –    | 2       | 1 ..= 9      |
/// | `gloss`            | –    | 1.0     | [0, 10]      |
/// | `background`       | –    | 0.005   | [0, 1]       |
/// | `reflection_block` | px   | 2       | 1 ..= 8      |
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct RenderConfig {
    /// Image width, pixels.
    pub width: u32,
    /// Image height, pixels.
    pub height: u32,
    /// Exponent `n` of the specular term `cosⁿ θ'` in eq. (2).
    pub phong_exponent: f64,
    /// Body tone of the stone, the gem trade's scale N1 (black) … N9 (white).
    pub body_tone: u8,
    /// Scale of the surface's gloss reflection of the light (1 = Fresnel).
    pub gloss: f64,
    /// Grey level of the backdrop behind the stone, as a reflectance under the light
    /// (0 black velvet … 1 white card).
    pub background: f64,
    /// Pixels on a side of the blocks whose weak internal reflections (Fresnel fraction
    /// under 0.2 at the far surface) are shaded with one shared ray; 1 shades every pixel's
    /// own reflection.
    pub reflection_block: u32,
}

impl Default for RenderConfig {
    fn default() -> Self {
        RenderConfig {
            width: 640,
            height: 480,
            phong_exponent: 40.0,
            body_tone: 2,
            gloss: 1.0,
            background: 0.005,
            reflection_block: 2,
        }
    }
}

impl RenderConfig {
    /// Check ranges.
    pub fn validate(&self) -> Result<()> {
        for (field, v) in [("render.width", self.width), ("render.height", self.height)] {
            check_count(
                field,
                v.into(),
                1..=16_384,
                "in 1..=16384 pixels",
                "640 × 480",
            )?;
        }
        check_range(
            "render.phong_exponent",
            self.phong_exponent,
            0.0,
            10_000.0,
            40.0,
        )?;
        check_count(
            "render.body_tone",
            self.body_tone.into(),
            1..=9,
            "1 (N1, black) to 9 (N9, white)",
            "2",
        )?;
        check_range("render.gloss", self.gloss, 0.0, 10.0, 1.0)?;
        check_range("render.background", self.background, 0.0, 1.0, 0.005)?;
        check_count(
            "render.reflection_block",
            self.reflection_block.into(),
            1..=8,
            "in 1..=8 pixels",
            "2 (or 1 for every pixel's own)",
        )
    }

    /// Single-scattering albedo of the potch (common opal) filling the voids, from the body
    /// tone: N1 absorbs nearly everything (black opal), N9 scatters nearly everything (white
    /// opal). A look scale, evenly spaced in lightness between the two ends.
    pub fn body_albedo(&self) -> f32 {
        const ALBEDO: [f32; 9] = [0.02, 0.05, 0.1, 0.2, 0.32, 0.45, 0.6, 0.76, 0.92];
        ALBEDO[usize::from(self.body_tone.clamp(1, 9)) - 1]
    }
}

/// Extinction coefficient of the potch in void cells, per mm: a mean free path of 0.33 mm,
/// so a void of the paper's cell size (0.2 mm) hides about 45 % of what lies behind it.
pub const BODY_EXTINCTION_PER_MM: f32 = 3.0;

/// The RGB space images are written in.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum ColorSpaceChoice {
    /// sRGB (IEC 61966-2-1, D65): the default for files.
    Srgb,
    /// The paper's eq. (3): NTSC 1953 primaries, white C.
    Paper,
}

/// How colours outside the RGB gamut are brought inside.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum GamutMapping {
    /// Desaturate towards the colour's own luminance just enough to fit, keeping hue.
    HuePreserving,
    /// Clip each channel to [0, 1] (bleaches saturated colours; for comparison).
    Clip,
}

/// Spectrum → RGB (paper §3.4, DESIGN §7).
///
/// | field         | unit | default          | valid                     |
/// |---------------|------|------------------|---------------------------|
/// | `space`       | –    | "srgb"           | "srgb", "paper"           |
/// | `gamut`       | –    | "hue-preserving" | "hue-preserving", "clip"  |
/// | `exposure_ev` | EV   | 0                | [−20, 20]                 |
/// | `bit_depth`   | bits | 8                | 8, 16                     |
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct ColorConfig {
    /// RGB space of the output.
    pub space: ColorSpaceChoice,
    /// Gamut mapping of out-of-gamut colours.
    pub gamut: GamutMapping,
    /// Exposure compensation in stops (each +1 doubles the brightness).
    pub exposure_ev: f64,
    /// Bits per channel of PNG output.
    pub bit_depth: u8,
}

impl Default for ColorConfig {
    fn default() -> Self {
        ColorConfig {
            space: ColorSpaceChoice::Srgb,
            gamut: GamutMapping::HuePreserving,
            exposure_ev: 0.0,
            bit_depth: 8,
        }
    }
}

impl ColorConfig {
    /// Check ranges.
    pub fn validate(&self) -> Result<()> {
        check_range("color.exposure_ev", self.exposure_ev, -20.0, 20.0, 0.0)?;
        if !matches!(self.bit_depth, 8 | 16) {
            return Err(Error::field(
                "color.bit_depth",
                format!("must be 8 or 16, got {}; try 8", self.bit_depth),
            ));
        }
        Ok(())
    }
}
