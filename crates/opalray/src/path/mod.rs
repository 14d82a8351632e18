//! The spectral path tracer on the stone model: eye paths through the surface, the domains'
//! plane families and the potch, to the environment and the scene's light.
//!
//! Input: a [`Stone`] and a [`PathSetup`] → output: a [`PathImage`] (XYZ per pixel and the
//! binned spectral image). Per pixel, `spp` camera rays, each uniform over the pixel, rendered
//! in passes ([`passes`]); each path:
//!
//! - **Surface** (Fresnel, s and p apart: [`polar`]): the gloss reflection goes to the lights
//!   (the environment and the disc) at once; the refracted part enters with `(1 − F)/n²`
//!   (radiance in a denser medium). From inside, the escaping part `1 − F` adds `n²` × the
//!   environment at once and the path goes on reflected with weight × F (all of it beyond the
//!   critical angle): no random choice, so the stone's internal reflections of the lights are
//!   smooth.
//! - **Potch** (between domains, and the haze of milky domains): free flights; at a scattering
//!   event the weight takes the albedo, the scene's light and the environment are estimated
//!   (`Tracer::environment_at`: importance-sampled, refracted in with the surface's lensing,
//!   balanced against the scattering's own draw), and the direction is drawn from the
//!   Henyey–Greenstein phase. The camera path's first scattering goes on in up to
//!   [`MAX_SCATTERING_SPLIT`] directions ([`scattering_split`]), averaging the rare
//!   continuations that reach a bright light along paths no estimate finds (reflected
//!   inside the dome).
//! - **Regions** ([`Stone::exit`]): a backing reflects diffusely (Lambert); a triplet's cap
//!   plane reflects with probability F, else refracts.
//! - **Domain crossing**: the families whose line can fall in the range at the ray's angle
//!   ([`Stone::lines`], the layers set by the chord) reflect or pass it. The ray always goes
//!   on through, carrying `1 − R` of each line (a path not yet reflected too: its notches,
//!   `notches`, so that a crossing creates no light); the reflections are branches: at every
//!   crossing of the camera ray's first segment every one (each followed with a probability
//!   set by what its first escape sees, `Tracer::follow_probability`: most look into the
//!   dark room), later one drawn with twice the lines' share of white light (at most ¼),
//!   its weight divided by that probability. A path already reflected does not fork: it
//!   reflects, with each line's share of its own light (what the line reflects at the
//!   wavelengths it carries, [`PathSpectrum::reflectances`]; at most 0.95 in all), or
//!   goes on through, its weight over `1 − p` (its cost grows linearly with depth, its
//!   weight stays about 1). A reflection draws the lobe's normal `h` about the
//!   family normal (Gaussian, the mosaic spread and the diffraction of the domain's width,
//!   [`Stone::lobe_sigma`]: a perfect domain is a mirror; the rocking width is in R(λ, θ)) and
//!   mirrors the ray about `h`; its line is evaluated at the angle to `h` — the half-vector
//!   law `λ = 2 d n̄ cos θ_h`. The reflection happens at the domain's entry face (the stack
//!   reflects within its penetration depth, tens of µm).
//! - **The light** (directional or point): next-event estimation at every domain crossing and
//!   potch scattering, through the one refracted path from the light
//!   ([`refracted_entry`](crate::geometry::refracted_entry)), with the surface's exact
//!   lensing, its spectrum filtered by every domain and potch on the way (`lamp.rs`; the
//!   environment's estimate: `nee.rs`). A sphere or rect light is estimated at the same
//!   events and backings (`area.rs`; at a crossing, only on a path not yet reflected),
//!   balanced against the escaping paths that meet it. A domain adds
//!   `π E R(λ, θ_h) D(h) / (4 cos θ_h)`, D the lobe's density over normals convolved with
//!   the lamp's disc ([`Stone::lamp_density`]), so that a mirror shows the lamp's disc.
//! - Russian roulette below a weight of 0.02; at most `max_depth` events besides the
//!   scatterings in the body and the reflections at the surface between them, and
//!   `max_scatterings` of those (0: they count among `max_depth`'s).
//!
//! The loop over a path's events, its branches waiting on a small stack rather than recursing:
//! `vertex.rs`; one method per event: `events.rs`, `crossing/` (a reflection's branch:
//! `crossing/branch.rs`).
//!
//! Spectra: see [`spectral`]. Every sample of every pixel draws its own numbers ([`sampler`]); rows are
//! rendered in parallel into pre-sized buffers, so the image does not depend on the number of
//! threads nor on how the passes fall ([`passes`]). Its noise: [`noise`]; its light
//! by class of path (Bragg events, the body, a backing): [`orders`].

mod area;
mod config;
mod crossing;
mod events;
mod image;
mod lamp;
mod method;
mod nee;
mod notches;
pub mod orders;
pub mod passes;
pub mod polar;
pub mod sampler;
mod shares;
pub mod spectral;
mod stats;
mod vertex;

use crate::geometry::{fresnel_dielectric_sp, reflect, refract, Camera, Ray};
use crate::integrator::Passes;
use crate::lights::emitters;
use crate::lights::{AreaLight, Environment, Lamp};
use crate::optics::BraggLine;
use crate::stone::{ActiveLine, Hint, Region, Span, Stone};
use glam::Vec3;

pub use crate::film::noise;
pub use crate::film::Noise;
pub use crate::film::DEFAULT_WAVELENGTHS;
pub use config::{PathConfig, DEFAULT_MAX_SCATTERINGS};
pub use image::PathImage;

pub use method::PathTracer;
pub use orders::BraggOrders;
pub use passes::trace_passes;
pub use sampler::Sampling;
pub use spectral::{PathSpectrum, SpectralSampler, MAX_DRAWS};
pub use stats::{DenoiseBias, PathStats};

use orders::{SampleTally, BACKGROUND, CLASSES, GLOSS};
use sampler::{Mark, PathSampler};
use vertex::{Vertex, Waiting};

/// Paths whose weight falls below this play Russian roulette.
const ROULETTE_BELOW: f32 = 0.02;

/// One camera sample in flight: the draws of its path and the light it adds to its pixel.
struct CameraSample<'s> {
    /// Its random numbers ([`sampler`]).
    draws: &'s mut PathSampler,
    /// Its XYZ so far.
    xyz: &'s mut [f64; 3],
    /// Its pixel's spectral bins (bin averages), which every sample of the pixel adds to.
    bins: &'s mut [f32],
}

/// Where light is estimated on a path: the point `x` inside the stone, the path's spectrum
/// and its weight there.
struct Estimate<'p> {
    x: Vec3,
    path: &'p PathSpectrum,
    weight: f32,
}

/// Offset of a new ray's origin along its direction, mm (0.1 µm).
const EPSILON_MM: f32 = 1e-4;
/// Least bound of the share of outside light that can reach a scattering point
/// ([`Stone::reach_bound`]) for the environment and an area light to be estimated there.
/// Below it the estimate would cost a refracted solve and a walk to add almost nothing; the
/// scattering's draw then carries the whole weight of its escape (still unbiased).
const MIN_REACH: f32 = 0.01;

/// A reflection of the camera ray's first segment whose first escape sees at least this share
/// of the environment's brightest value is always followed ([`Tracer::follow_probability`]).
const FOLLOW_FROM: f32 = 0.05;
/// Least probability with which such a reflection is followed.
const MIN_FOLLOW: f32 = 0.25;

/// Most directions the camera path's first scattering goes on in.
const MAX_SCATTERING_SPLIT: u32 = 16;

/// How many directions the camera path's first scattering goes on in, each with `weight`
/// over that many: [`MAX_SCATTERING_SPLIT`], or fewer so that none falls below
/// [`ROULETTE_BELOW`] (where roulette would undo the split).
fn scattering_split(weight: f32) -> u32 {
    ((weight / ROULETTE_BELOW) as u32).clamp(1, MAX_SCATTERING_SPLIT)
}

/// Everything the path integrator needs besides the stone.
pub struct PathSetup<'a> {
    /// The camera.
    pub camera: Camera,
    /// Image width, pixels.
    pub width: usize,
    /// Image height, pixels.
    pub height: usize,
    /// Samples per pixel (1 ..= [`crate::scene::MAX_SPP`]); with a time limit, the most.
    pub spp: u32,
    /// Most events per path.
    pub max_depth: u32,
    /// Most scatterings in the body or a domain's haze on one path, counted apart from
    /// `max_depth`; 0: counted among its events.
    pub max_scatterings: u32,
    /// The scene's light, if any.
    pub light: Option<Lamp>,
    /// The environment.
    pub environment: Environment,
    /// The scene's sphere or rect light, if any (seen by the rays that leave the stone).
    pub area_light: Option<AreaLight>,
    /// Scale of the surface's gloss.
    pub gloss: f32,
    /// Seed of the sample streams.
    pub seed: u64,
    /// Which points the samples are: Owen-scrambled Sobol (the default) or independent
    /// streams ([`Sampling`]).
    pub sampling: Sampling,
    /// Wavelength sampling and colour matching.
    pub spectral: &'a SpectralSampler,
}

/// Render `stone` as `setup` says: all `setup.spp` samples per pixel, no report
/// ([`trace_passes`] with [`Passes::default`]).
pub fn trace_paths(stone: &Stone, setup: &PathSetup) -> PathImage {
    trace_passes(stone, setup, &Passes::default())
}

struct Tracer<'a> {
    stone: &'a Stone,
    setup: &'a PathSetup<'a>,
    n_eff: f32,
    lines: Vec<ActiveLine>,
    light_spans: Vec<Span>,
    light_lines: Vec<ActiveLine>,
    /// Whether the area light is estimated at events (else found only by escaping paths).
    area_estimation: bool,
    /// The cells likely to hold the point light is next estimated at.
    nee_hint: Hint,
    /// The value seen from which a reflection of the camera ray's first segment is always
    /// followed ([`Tracer::follow_probability`]); 0: every one is.
    follow_from: f32,
    /// The current camera sample's luminance per class of path ([`orders`]).
    tally: SampleTally,
    /// The paths waiting on their branches ([`Tracer::inside`]), kept between samples for
    /// its room.
    waiting: Vec<(Box<Waiting>, Mark)>,
    /// Whether events act on s and p apart ([`polar`]; else on their mean, as tests compare).
    polarised: bool,
}

impl<'a> Tracer<'a> {
    fn new(stone: &'a Stone, setup: &'a PathSetup<'a>) -> Self {
        Tracer {
            stone,
            setup,
            n_eff: stone.n_eff,
            lines: Vec::with_capacity(16),
            light_spans: Vec::with_capacity(64),
            light_lines: Vec::with_capacity(16),
            area_estimation: true,
            nee_hint: Hint::default(),
            // With a point or directional light, a reflection's worth lies in the estimates
            // of that light along its path, which its first escape does not foretell.
            follow_from: if setup.light.is_none() {
                FOLLOW_FROM * setup.environment.peak()
            } else {
                0.0
            },
            tally: [0.0; CLASSES],
            waiting: Vec::with_capacity(setup.max_depth as usize),
            polarised: true,
        }
    }

    /// Add `weight` of the path's spectrum `lines` to the sample, tallied in the path's class.
    fn add(&mut self, lines: &PathSpectrum, weight: f32, s: &mut CameraSample) {
        self.add_as(lines.history.class(), lines, weight, s);
    }

    /// [`Tracer::add`], tallied in `class` ([`orders`]): the luminance it adds.
    fn add_as(&mut self, class: usize, lines: &PathSpectrum, weight: f32, s: &mut CameraSample) {
        let y = s.xyz[1];
        self.setup
            .spectral
            .add_path(lines, f64::from(weight), s.xyz, s.bins);
        self.tally[class] += s.xyz[1] - y;
    }

    /// One camera ray's path: its draws from `sampler`, its XYZ added to `acc`, its spectrum
    /// to its pixel's `bins`.
    fn sample(
        &mut self,
        ray: Ray,
        sampler: &mut PathSampler,
        acc: &mut [f64; 3],
        bins: &mut [f32],
    ) {
        let s = &mut CameraSample {
            draws: sampler,
            xyz: acc,
            bins,
        };
        self.tally = [0.0; CLASSES];
        let plain = PathSpectrum::default();
        let stone = self.stone;
        let shape = stone.shape;
        let Some((t0, _)) = shape.intersect(&ray).filter(|&(t0, _)| t0 > 0.0) else {
            let v = self.escaped(ray.origin, ray.direction);
            self.add_as(BACKGROUND, &plain, v, s);
            return;
        };
        // The surface: gloss to the environment and the light's disc, the rest refracts in.
        let p = ray.at(t0);
        let normal = shape.normal(p);
        let region = stone.region_at(p - normal * EPSILON_MM);
        let n = stone.index_of(region);
        let cos_i = -ray.direction.dot(normal);
        let (fs, fp) = fresnel_dielectric_sp(cos_i, 1.0, n);
        let fresnel = 0.5 * (fs + fp);
        let mirror = reflect(ray.direction, normal);
        let gloss = fresnel * self.setup.gloss * (self.escaped(p, mirror) + self.disc(mirror));
        self.add_as(GLOSS, &plain, gloss, s);
        let Some(dir) = refract(ray.direction, normal, 1.0, n) else {
            return;
        };
        let mut lines = PathSpectrum::default();
        let weight = lines.event(self.plane(ray.direction, normal), 1.0 - fs, 1.0 - fp) / (n * n);
        let start = Vertex {
            pos: p,
            dir,
            weight,
            lines,
            skip: None,
            region,
            drawn: None,
            hint: Hint::default(),
            split: true,
            splits_scattering: true,
            first_in_cap: region == Region::Cap,
            level: 0,
            scatterings: 0,
            walking: false,
        };
        self.inside(start, s);
    }

    /// What a ray leaving the stone at `origin` along `dir` sees: the environment, or the area
    /// light where it meets it.
    fn escaped(&self, origin: Vec3, dir: Vec3) -> f32 {
        self.escaped_to(origin, dir).0
    }

    /// [`Tracer::escaped`], and whether it is the area light.
    fn escaped_to(&self, origin: Vec3, dir: Vec3) -> (f32, bool) {
        emitters::seen(
            &self.setup.environment,
            self.setup.area_light.as_ref(),
            origin,
            dir,
        )
    }

    /// The light's disc seen along `dir` from outside, in image units.
    fn disc(&self, dir: Vec3) -> f32 {
        self.setup.light.map_or(0.0, |light| light.disc(dir))
    }

    /// Whether the path `v` goes on to its next event: within `max_depth` events besides its
    /// scatterings in the body and the surface's reflections of the segments drawn at them
    /// (a light body's light comes back after hundreds of them: the weight's roulette ends
    /// those paths, not a count) and within `max_scatterings` of those; with
    /// `max_scatterings` 0, within `max_depth` events of any kind.
    fn goes_deeper(&self, v: &vertex::Vertex) -> bool {
        match self.setup.max_scatterings {
            0 => v.level < self.setup.max_depth,
            most => v.level - v.scatterings < self.setup.max_depth && v.scatterings < most,
        }
    }

    /// Russian roulette below [`ROULETTE_BELOW`]: `false` if the path ends.
    fn roulette(&self, weight: &mut f32, sampler: &mut PathSampler) -> bool {
        if *weight < ROULETTE_BELOW {
            if sampler.uniform_f32() >= *weight / ROULETTE_BELOW {
                return false;
            }
            *weight = ROULETTE_BELOW;
        }
        true
    }

    /// `line`'s family in `domain` met at `cos_theta` ([`Stone::line_at`]).
    fn line_at(&self, domain: u32, line: &ActiveLine, cos_theta: f32) -> BraggLine {
        self.stone.line_at(domain, line, cos_theta)
    }
}

#[cfg(test)]
mod tests;
