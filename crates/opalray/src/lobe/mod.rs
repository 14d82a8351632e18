//! The lobe integrator: a deterministic renderer of the stone model that integrates every
//! Bragg lobe against the lights instead of sampling it (`integrator.method = "lobe"`).
//!
//! Input: a [`Stone`] and a [`LobeSetup`] → output: a [`LobeImage`] (XYZ per pixel and the
//! binned spectrum). No random numbers but the stratified sub-pixel positions (`spp`, keyed
//! by pixel): the same bytes at any thread count. Per camera ray ([`trace`]):
//!
//! - **Surface**: the gloss shows the environment (exact for a smooth surface) and the
//!   light's disc; `(1 − F)/n²` refracts in.
//! - **Domain crossing**, for every line met ([`Stone::lines`]): the mirror direction about
//!   the family normal is followed out of the stone (the domains on the way notch it, the
//!   potch and haze dim it; at the surface `(1 − F) n²` escapes, the rest is reflected
//!   inside and followed again, up to [`trace::MAX_SEGMENTS`] segments, through the
//!   domains after a total reflection and through the surface alone after a partial one),
//!   and the
//!   environment is read there through the lobe, its width the mosaic spread carried
//!   through the refraction ([`crate::lights::Environment::filtered`]). The line's colour is
//!   its equivalent width times the light × colour-matching functions over its profile
//!   ([`colour`]), spread over the wavelengths the lobe's normals reflect
//!   ([`LineColours::in_lobe`]), times what the notches of the lines crossed before leave of
//!   it, each read over the reflection's band as the mosaic spreads it ([`band`]).
//!   A point or directional light adds `π E R D(h)/(4 cos θ_h)`, the lobe's density at the
//!   half vector, as the path tracer's estimate does; a sphere or rect light is read
//!   through the lobe ([`crate::lights::AreaLight::lobe_share`]). The ray goes on through.
//! - **Body**: where the eye ray is scattered by the potch (or a milky domain's haze), with
//!   probability `1 − e^{−τ}` over a span, it sees the body as a layer of the stone's
//!   thickness ([`layer::BodyLayer`], its Munsell value when thick) lit by the
//!   environment's irradiance at the surface it entered ([`Irradiance`]), or, for the potch
//!   under a colour bar (and a milky domain's haze over it), by the light reaching its top
//!   through the bar, its own light returned by the bar and the dome in place of a polished
//!   surface's ([`potch::PotchLight`]), and by the irradiance beyond its far surface — the calibrated
//!   slab's reflectance as a Lambertian response, not its multiple scattering. Beside it, the
//!   potch's single scattering of the light reaching it unscattered (the softbox through the
//!   dome, the light through a clear stone): once per segment, a quadrature of directions
//!   drawn from its phase function, each followed out of the stone ([`trace`]'s `single`).
//! - **Exit**: the environment through the far surface (`(1 − F) n²`, the rest reflected
//!   inside, bounded); a backing shows its reflectance under the light that reaches it
//!   through the stone ([`BackingLight`]).
//!
//! Left out, and measured in `docs/model.md`: third and later Bragg reflections, the lobe's
//! colour change across its width where the light is uneven over it, the lensing of the dome on the lobe's
//! width, the notches of the lines on the body's and the environment's broadband light
//! except those of the eye ray, and the cap plane's reflection of a triplet.

mod band;
pub mod colour;
mod config;
#[cfg(test)]
mod fixture;
mod layer;
mod method;
mod pixels;
mod potch;
mod tables;
mod trace;
mod work;

use std::f32::consts::PI;

use glam::Vec3;

use crate::film::SpectralSampler;
use crate::geometry::Camera;
use crate::integrator::Passes;
use crate::lights::{AreaLight, Environment, Lamp};
use crate::spectrum::SpectralImage;
use crate::stone::Stone;

pub use colour::LineColours;
pub use config::LobeConfig;
pub use method::LobeMethod;
pub(crate) use tables::BackingLight;
pub use tables::Irradiance;
use tables::{bilinear, fill_table};
pub use work::lobe_factor;

/// Everything the lobe integrator needs besides the stone.
pub struct LobeSetup<'a> {
    /// The camera.
    pub camera: Camera,
    /// Image width, pixels.
    pub width: usize,
    /// Image height, pixels.
    pub height: usize,
    /// Camera rays per pixel, at stratified positions (anti-aliasing only).
    pub spp: u32,
    /// The scene's point or directional light, if any.
    pub light: Option<Lamp>,
    /// The scene's sphere or rect light, if any, read through every lobe
    /// ([`AreaLight::lobe_share`]).
    pub area_light: Option<AreaLight>,
    /// The light's irradiance at the stone's centre on a plane facing it (`light.intensity`).
    pub light_intensity: f32,
    /// The environment.
    pub environment: &'a Environment,
    /// Scale of the surface's gloss.
    pub gloss: f32,
    /// Seed of the sub-pixel positions.
    pub seed: u64,
    /// Luminous reflectance of the body (its tone's Munsell value, `munsell_y`).
    pub body_reflectance: f32,
    /// Wavelength range, the light's spectrum and the colour-matching functions.
    pub spectral: &'a SpectralSampler,
    /// Walk the reflections the dome traps for their second Bragg reflections
    /// (`integrator.trapped`).
    pub trapped: bool,
    /// A pixel's further rays read back the reflections its centre ray followed out, and the
    /// light its body scatters once, instead of finding them again (`pixels`; about a third
    /// of the default render's time): true in every render, false to measure what that
    /// changes.
    pub reuse: bool,
}

/// The lobe integrator's image.
pub struct LobeImage {
    /// CIE XYZ per pixel, row-major (Y = 1: a white diffuser under the light).
    pub xyz: Vec<[f32; 3]>,
    /// The spectral image (bin averages).
    pub spectral: SpectralImage,
}

/// Render `stone` as `setup` says: one camera ray through every pixel's centre, then
/// `setup.spp − 1` more, stratified, through each pixel whose first ray differs from a
/// neighbour's (domain edges, the silhouette, the gloss's rim; [`pixels`]).
pub fn render_lobes(stone: &Stone, setup: &LobeSetup) -> LobeImage {
    render_lobes_reporting(stone, setup, &Passes::default())
}

/// [`render_lobes`], telling `passes.on_rows` of every row done: band by band, its centres'
/// rows, then (for `spp` > 1) the band before's edges' rows (the same image).
pub fn render_lobes_reporting(stone: &Stone, setup: &LobeSetup, passes: &Passes) -> LobeImage {
    let colours = LineColours::new(setup.spectral);
    let irradiance = Irradiance::new(setup.environment);
    let backing_light = BackingLight::new(stone, setup, &colours, &irradiance);
    let potch_light = potch::PotchLight::new(stone, setup, &colours, &irradiance);
    let tables = pixels::Tables {
        colours: &colours,
        irradiance: &irradiance,
        lit: trace::Lit {
            backing: backing_light.as_ref(),
            potch: potch_light.as_ref(),
        },
    };
    pixels::render(stone, setup, &tables, passes)
}

#[cfg(test)]
mod tests {
    use super::tables::{read_points, BACKING_GRID, READ_RADIUS};
    use super::*;
    use crate::scene::{preset, EnvironmentConfig, EnvironmentKind};

    /// The light on the black opal's backing at its centre and near its rim, in a uniform
    /// environment of 1, with the stone's potch and haze as `extinction_per_mm`.
    fn backing_light(extinction_per_mm: f32) -> (f32, f32, f32) {
        let scene = preset("black-opal").unwrap();
        let mut stone = Stone::new(&scene).unwrap();
        stone.potch.extinction_per_mm = extinction_per_mm;
        stone.potch.domain_scattering_per_mm = extinction_per_mm;
        let env = Environment::uniform();
        let sampler = SpectralSampler::new(scene.light.illuminant, &scene.spectrum, 4);
        let setup = fixture::eight_by_eight(&env, &sampler);
        let colours = LineColours::new(&sampler);
        let irradiance = Irradiance::new(&env);
        let table = BackingLight::new(&stone, &setup, &colours, &irradiance).unwrap();
        let axes = stone.shape.semi_axes();
        let z = -1e3;
        let back = |x: f32, y: f32| {
            let up = crate::geometry::Ray {
                origin: Vec3::new(x, y, z),
                direction: Vec3::Z,
            };
            let (t0, _) = stone.shape.intersect(&up).unwrap();
            table.at(up.at(t0))
        };
        (back(0.0, 0.0), back(0.9 * axes.x, 0.0), stone.n_eff)
    }

    #[test]
    fn a_table_read_inside_its_footprint_reads_only_computed_points() {
        // The points left out hold NaN: a read whose cell has one as a corner returns NaN.
        for grid in [BACKING_GRID, (32, 24), (96, 72)] {
            let read = read_points(grid, READ_RADIUS);
            let values: Vec<f32> = read
                .iter()
                .map(|&r| if r { 1.0 } else { f32::NAN })
                .collect();
            let skipped = read.iter().filter(|&&r| !r).count();
            assert!(skipped > 0, "{grid:?}: nothing left out");
            let n = 400;
            for a in 0..=n {
                for b in 0..=n {
                    let (u, v) = (
                        2.0 * a as f32 / n as f32 - 1.0,
                        2.0 * b as f32 / n as f32 - 1.0,
                    );
                    if u * u + v * v <= 1.001 {
                        let x = bilinear(&values, grid, u, v);
                        assert!((x - 1.0).abs() < 1e-6, "{grid:?} at ({u}, {v}): {x}");
                    }
                }
            }
        }
    }

    #[test]
    fn the_backing_is_lit_through_the_stone() {
        // Lossless: inside a clear dielectric in a furnace the radiance is n² in every
        // direction that leads out (the furnace through the surface); what the dome
        // reflects back down sees the backing itself, which this light leaves out. So at
        // most n², and at least what escapes through the dome at once, (1 − F) n² over the
        // directions that meet it within the critical angle: most of them at the centre of
        // a dome, fewer under its steep rim.
        let (centre, rim, n) = backing_light(0.0);
        for (v, least) in [(centre, 0.75), (rim, 0.25)] {
            assert!(
                v <= 1.0001 * n * n && v > least * n * n,
                "{v} against {}",
                n * n
            );
        }
        // Under the black opal's opaque potch (3 mm⁻¹ over 2–4 mm), e^{−6} at most reaches
        // the backing's centre: it must not be lit by the room as if the stone were not there.
        let (centre, _, n) = backing_light(3.0);
        assert!(centre < 0.01 * n * n, "{centre}");
    }

    #[test]
    fn irradiance_of_a_uniform_environment_is_its_value_and_of_a_half_space_half() {
        let uniform = Environment::uniform();
        let table = Irradiance::new(&uniform);
        for n in [Vec3::Z, Vec3::X, Vec3::new(0.3, -0.5, 0.8).normalize()] {
            assert!((table.at(n) - 1.0).abs() < 0.01, "{n}: {}", table.at(n));
        }
        // `none` with a backdrop of 1 below the horizon: a normal along +x sees half of it
        // (π/2 of the cosine-weighted π), one facing down all of it.
        let backdrop = Environment::new(
            &EnvironmentConfig {
                kind: EnvironmentKind::None,
                ..EnvironmentConfig::default()
            },
            1.0,
        )
        .unwrap();
        let table = Irradiance::new(&backdrop);
        assert!(
            (table.at(Vec3::X) - 0.5).abs() < 0.01,
            "{}",
            table.at(Vec3::X)
        );
        assert!((table.at(-Vec3::Z) - 1.0).abs() < 0.01);
        assert!(table.at(Vec3::Z) < 0.01);
    }
}
