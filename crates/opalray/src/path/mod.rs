//! The spectral path tracer on the stone model: eye paths through the surface, the domains'
//! plane families and the potch, to the environment and the scene's light.
//!
//! Input: a [`Stone`] and a [`PathSetup`] → output: a [`PathImage`] (XYZ per pixel and the
//! binned spectral image). Per pixel, `spp` camera rays, each uniform over the pixel, rendered
//! in passes ([`passes`]); each path:
//!
//! - **Surface** (Fresnel, unpolarised): the gloss reflection is followed to the environment
//!   and the light's disc at once; the refracted part enters with `(1 − F)/n²` (radiance in a
//!   denser medium). From inside, the escaping part `1 − F` adds `n²` × the environment at
//!   once and the path goes on reflected with weight × F (all of it beyond the critical
//!   angle): no random choice, so the stone's internal reflections of the lights are smooth.
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
//!   potch scattering, through the one refracted path from the light ([`refracted_entry`]),
//!   with the surface's exact lensing, its spectrum filtered by every domain and potch on the
//!   way. A sphere or rect light is estimated at the same events and backings (`nee.rs`;
//!   at a crossing, only on a path not yet reflected), balanced against the escaping paths
//!   that meet it. A domain adds
//!   `π E R(λ, θ_h) D(h) / (4 cos θ_h)`, D the lobe's density over normals convolved with
//!   the lamp's disc ([`Stone::lamp_density`]), so that a mirror shows the lamp's disc.
//! - Russian roulette below a weight of 0.02; at most `max_depth` events.
//!
//! Spectra: see [`spectral`]. Every sample of every pixel draws its own numbers ([`sampler`]); rows are
//! rendered in parallel into pre-sized buffers, so the image does not depend on the number of
//! threads nor on how the passes fall ([`passes`]). Its noise: [`noise`]; its light
//! by class of path (Bragg events, the body, a backing): [`orders`].

mod method;
mod nee;
pub mod noise;
mod notches;
pub mod orders;
pub mod passes;
pub mod sampler;
pub mod spectral;

use std::f32::consts::PI;

use crate::geometry::refracted_entry;
use crate::geometry::LightSource;
use crate::geometry::{fresnel_dielectric, reflect, refract, Camera, Ray};
use crate::lights::emitters;
use crate::lights::{AreaLight, Environment};
use crate::optics::BraggLine;
use crate::scene::Backing;
use crate::spectrum::SpectralImage;
use crate::stone::body::{hg_cos, hg_phase};
use crate::stone::{ActiveLine, Boundary, Hint, Region, Span, Stone};
use glam::Vec3;

pub use method::PathTracer;
pub use noise::Noise;
pub use orders::BraggOrders;
pub use passes::{trace_passes, PassReport, Passes};
pub use sampler::Sampling;
pub use spectral::{Lines, PathSpectrum, SpectralSampler, MAX_DRAWS};

use nee::Drawn;
use orders::{SampleTally, BACKGROUND, CLASSES, GLOSS};
use sampler::PathSampler;

/// Paths whose weight falls below this play Russian roulette.
const ROULETTE_BELOW: f32 = 0.02;

/// A reflection at a domain crossing: the ray along `dir` meets `domain`'s face at `face`
/// (light was estimated at `x`, just inside), in the cells `cells`; the branch's weight, and
/// its probability where the area light was also estimated there (`None`: the branch's escape
/// is the only way there).
struct Reflection {
    face: Vec3,
    x: Vec3,
    dir: Vec3,
    domain: u32,
    cells: Hint,
    p_pick: Option<f64>,
    weight: f32,
}

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

/// A domain met by a path's segment `ray`: the domain from `t0` (mm along the ray) over
/// `chord` (mm, up to the segment's next event), the cells holding its start.
struct DomainSpan<'r> {
    ray: &'r Ray,
    t0: f32,
    chord: f32,
    domain: u32,
    cells: Hint,
}

/// What a domain crossing leaves of the path that met it.
enum Crossing {
    /// It goes on through, its weight times this.
    On(f32),
    /// It ends.
    Ended,
    /// It was reflected (a path already reflected reflects instead of going on): it goes on
    /// as this path.
    Reflected(Box<PathState>),
}
/// Offset of a new ray's origin along its direction, mm (0.1 µm).
const EPSILON_MM: f32 = 1e-4;
/// Most lines one domain crossing can have (one per family normal: 4 + 6 + 12 + 3).
const MAX_LINES_PER_CROSSING: usize = 25;
/// Most probability of a reflection branch at a domain crossing after the first segment.
const MAX_BRANCH_PROBABILITY: f64 = 0.25;
/// Most probability with which an already reflected path reflects at a crossing (the rest
/// goes on through, its weight over 1 − p).
const MAX_CHOICE_PROBABILITY: f64 = 0.95;
/// Least share of an already reflected path's light a line is drawn with, as a fraction of
/// its share of white light (keeps every branch possible, so the estimate unbiased).
const MIN_SHARE_OF_WHITE: f64 = 0.01;

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

/// The scene's light for the path integrator.
#[derive(Clone, Copy, Debug)]
pub struct PathLight {
    /// Where it is.
    pub source: LightSource,
    /// Irradiance scale (`light.intensity`).
    pub intensity: f32,
    /// Angular radius of its disc as seen in the gloss, radians (0: no disc).
    pub disc_radius_rad: f32,
}

impl PathLight {
    /// Its disc seen along `dir` from outside (the gloss's image of the lamp), in image
    /// units: the irradiance over the disc's solid angle π r², times π; 0 off the disc.
    pub fn disc(&self, dir: Vec3) -> f32 {
        let r = self.disc_radius_rad;
        let to_light = self.source.direction_to_light(Vec3::ZERO);
        if r > 0.0 && dir.dot(to_light) >= r.cos() {
            self.intensity / (r * r)
        } else {
            0.0
        }
    }
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
    /// The scene's light, if any.
    pub light: Option<PathLight>,
    /// The environment.
    pub environment: Environment,
    /// The scene's sphere or rect light, if any (seen by the rays that leave the stone).
    pub area_light: Option<AreaLight>,
    /// Scale of the surface's gloss.
    pub gloss: f32,
    /// Seed of the sample streams.
    pub seed: u64,
    /// Wavelength sampling and colour matching.
    pub spectral: &'a SpectralSampler,
}

/// The path integrator's image.
pub struct PathImage {
    /// CIE XYZ per pixel, row-major (Y = 1: a white diffuser under the light): the mean of
    /// its samples.
    pub xyz: Vec<[f32; 3]>,
    /// The spectral image (bin averages).
    pub spectral: SpectralImage,
    /// Samples per pixel rendered.
    pub spp: u32,
    /// Passes rendered.
    pub passes: u32,
    /// Per pixel, the XYZ mean of its even samples minus that of its odd ones ([`noise`]);
    /// empty below two samples per pixel.
    pub half_difference: Vec<[f32; 3]>,
    /// Per pixel, the variance of its XYZ mean: the samples' variance over `spp` (infinite
    /// with one sample).
    pub variance: Vec<[f32; 3]>,
    /// Per pixel, whether its centre sees the stone.
    pub on_stone: Vec<bool>,
    /// The share of the stone's luminance per class of path ([`orders`]); `None` where the
    /// image was not traced.
    pub bragg_orders: Option<BraggOrders>,
}

/// Render `stone` as `setup` says: all `setup.spp` samples per pixel, no report
/// ([`trace_passes`] with [`Passes::default`]).
pub fn trace_paths(stone: &Stone, setup: &PathSetup) -> PathImage {
    trace_passes(stone, setup, &Passes::default())
}

/// What happens next on a path inside the stone.
enum Event {
    /// Scattered at `t` (by the potch, or the haze of a milky domain), keeping `albedo`.
    Scattered { t: f32, albedo: f32 },
    /// Reached the boundary of its region.
    Boundary(Boundary),
}

/// Where a path inside the stone is.
#[derive(Clone)]
struct PathState {
    pos: Vec3,
    dir: Vec3,
    weight: f32,
    /// Its spectrum: the lines met so far.
    lines: PathSpectrum,
    /// The domain whose face reflected it (left through that face).
    skip: Option<u32>,
    region: Region,
    /// How its first segment was drawn, where light was also estimated there.
    drawn: Option<Drawn>,
    /// Whether its first scattering splits ([`scattering_split`]): the camera path's.
    splits_scattering: bool,
    /// The cells likely to hold `pos` ([`Stone::walk`]).
    hint: Hint,
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
        let fresnel = fresnel_dielectric(cos_i, 1.0, n);
        let mirror = reflect(ray.direction, normal);
        let gloss = fresnel * self.setup.gloss * (self.escaped(p, mirror) + self.disc(mirror));
        self.add_as(GLOSS, &plain, gloss, s);
        let Some(dir) = refract(ray.direction, normal, 1.0, n) else {
            return;
        };
        let weight = (1.0 - fresnel) / (n * n);
        let start = PathState {
            pos: p,
            dir,
            weight,
            lines: PathSpectrum::default(),
            skip: None,
            region,
            drawn: None,
            splits_scattering: true,
            hint: Hint::default(),
        };
        self.inside(start, true, 0, s);
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

    /// The path `state` inside the stone. If `split`, every reflection at the domain crossings
    /// of its first segment in the opal is followed (a branch each) and the ray goes on through
    /// as well; elsewhere a reflection branch is drawn at random.
    fn inside(&mut self, state: PathState, mut split: bool, depth: u32, s: &mut CameraSample) {
        let stone = self.stone;
        let shape = stone.shape;
        let potch = stone.potch;
        let PathState {
            mut pos,
            mut dir,
            mut weight,
            mut lines,
            mut skip,
            mut region,
            drawn,
            splits_scattering,
            mut hint,
        } = state;
        let mut first_scattering = splits_scattering;
        let mut first_in_cap = region == Region::Cap;
        // How a scattering or a branch drew this segment's direction, when light was also
        // sampled there: the MIS weight of its escape.
        let mut drawn_with = drawn;
        let sample_env = stone.cap.is_none();
        let mut level = depth;
        loop {
            if !self.goes_deeper(level) {
                return;
            }
            s.draws.begin_event(level);
            let ray = Ray {
                origin: pos,
                direction: dir,
            };
            let Some((t_end, boundary)) = stone.exit(&ray, region) else {
                return;
            };
            let mut event = Event::Boundary(boundary);
            let skip_first = skip.take();
            let mut end_hint = Hint::default();
            // The cells of a scattering in the potch.
            let mut scattered_in = Hint::default();
            // Where a path already reflected reflects again, it goes on as that reflection.
            let mut reflected_to = None;
            if region == Region::Opal {
                // The domains are crossed as the walk finds them; an event ends the walk.
                let mut first = true;
                let mut ended = false;
                end_hint = stone.walk(pos, dir, 0.0, t_end, hint, &mut |span| {
                    let at_start = std::mem::replace(&mut first, false);
                    let mut chord = span.t1 - span.t0;
                    let Some(domain) = span.domain else {
                        let flight = -(1.0 - s.draws.uniform_f32()).ln() / potch.extinction_per_mm;
                        if flight < chord {
                            event = Event::Scattered {
                                t: span.t0 + flight,
                                albedo: potch.albedo,
                            };
                            scattered_in = span.hint;
                            return false;
                        }
                        return true;
                    };
                    // Milky domains scatter too (without absorbing).
                    let mut scatter_at = None;
                    if potch.domain_scattering_per_mm > 0.0 {
                        let flight =
                            -(1.0 - s.draws.uniform_f32()).ln() / potch.domain_scattering_per_mm;
                        if flight < chord {
                            chord = flight;
                            scatter_at = Some(span.t0 + flight);
                            scattered_in = span.hint;
                        }
                    }
                    // A ray reflected at a domain's face leaves through that face.
                    if !(at_start && skip_first == Some(domain)) {
                        let at = DomainSpan {
                            ray: &ray,
                            t0: span.t0,
                            chord,
                            domain,
                            cells: span.hint,
                        };
                        match self.cross_domain(&at, weight, &mut lines, split, level, s) {
                            Crossing::On(scale) => weight *= scale,
                            Crossing::Ended => {
                                ended = true;
                                return false;
                            }
                            Crossing::Reflected(next) => {
                                reflected_to = Some(next);
                                ended = true;
                                return false;
                            }
                        }
                    }
                    if let Some(t) = scatter_at {
                        event = Event::Scattered { t, albedo: 1.0 };
                        return false;
                    }
                    true
                });
                if ended {
                    let Some(next) = reflected_to else {
                        return;
                    };
                    PathState {
                        pos,
                        dir,
                        weight,
                        lines,
                        skip,
                        region,
                        drawn: drawn_with,
                        hint,
                        ..
                    } = *next;
                    split = false;
                    first_in_cap = false;
                    first_scattering = false;
                    level += 1;
                    continue;
                }
            }
            hint = end_hint;
            // The density a scattering drew the next segment with (see `drawn_with`).
            drawn_with = match event {
                Event::Scattered { t, albedo } => {
                    pos = ray.at(t);
                    weight *= albedo;
                    lines.history.scattered();
                    hint = scattered_in;
                    self.nee_hint = hint;
                    let at = Estimate {
                        x: pos,
                        path: &lines,
                        weight,
                    };
                    self.light_at_potch(&at, dir, s);
                    let g = potch.anisotropy;
                    let incoming = dir;
                    // Deep in a milky body no light from outside reaches this point: the
                    // estimate is skipped and the scattering's own draw weighs alone.
                    let sample_env = sample_env && stone.reach_bound(pos) >= MIN_REACH;
                    if sample_env {
                        let phase = |to: Vec3| hg_phase(g, to.dot(incoming));
                        self.environment_at(&at, &phase, s);
                        self.area_at(&at, &phase, s);
                    }
                    // The camera path's first scattering goes on in several directions.
                    let k = if first_scattering {
                        scattering_split(weight)
                    } else {
                        1
                    };
                    first_scattering = false;
                    weight /= k as f32;
                    let phase_drawn = |d: Vec3| {
                        sample_env.then(|| Drawn {
                            density: hg_phase(g, d.dot(incoming)),
                            from: pos,
                            environment: true,
                        })
                    };
                    for _ in 1..k {
                        let d = sample_hg(incoming, g, s.draws);
                        let state = PathState {
                            pos,
                            dir: d,
                            weight,
                            lines: lines.clone(),
                            skip: None,
                            region,
                            drawn: phase_drawn(d),
                            splits_scattering: false,
                            hint,
                        };
                        let mark = s.draws.mark();
                        self.inside(state, false, level + 1, s);
                        s.draws.reset(mark);
                    }
                    dir = sample_hg(dir, g, s.draws);
                    phase_drawn(dir)
                }
                Event::Boundary(Boundary::Surface) => {
                    // Both ways at once: what escapes is added now (its share 1 − F), the
                    // path goes on reflected with weight × F.
                    let n = stone.index_of(region);
                    let exit = ray.at(t_end);
                    let normal = shape.normal(exit);
                    let cos = dir.dot(normal).max(0.0);
                    let f = fresnel_dielectric(cos, n, 1.0);
                    if f < 1.0 {
                        if let Some(out) = refract(dir, normal, n, 1.0) {
                            let (mut v, light) = self.escaped_to(exit, out);
                            if let Some(drawn) = drawn_with.filter(|_| v > 0.0) {
                                // Drawn where light was also sampled: the balance heuristic
                                // over external solid angle, against the draws that would
                                // have found this same path.
                                v *= self.escape_weight(&drawn, dir, out, exit, light);
                            }
                            if v > 0.0 {
                                let value = weight * (1.0 - f) * n * n * v;
                                self.add(&lines, value, s);
                            }
                        }
                    }
                    weight *= f;
                    lines.history.reflected_inside();
                    dir = reflect(dir, normal);
                    pos = exit - normal * EPSILON_MM;
                    None
                }
                Event::Boundary(Boundary::Back) => {
                    // The backing reflects diffusely (Lambert): cosine-weighted about +z.
                    let Some(back) = stone.back else {
                        return;
                    };
                    pos = ray.at(t_end) + Vec3::Z * EPSILON_MM;
                    lines.history.backed();
                    weight *= match back.kind {
                        Backing::Ironstone => {
                            lines.tint();
                            1.0
                        }
                        _ => back.reflectance(550.0) as f32,
                    };
                    if weight <= 0.0 {
                        return;
                    }
                    self.nee_hint = hint;
                    let at = Estimate {
                        x: pos,
                        path: &lines,
                        weight,
                    };
                    self.light_at_back(&at, s);
                    if sample_env {
                        let lambert = |to: Vec3| to.z.max(0.0) / PI;
                        self.environment_at(&at, &lambert, s);
                        self.area_at(&at, &lambert, s);
                    }
                    dir = cosine_about_z(s.draws);
                    sample_env.then(|| Drawn {
                        density: dir.z / PI,
                        from: pos,
                        environment: true,
                    })
                }
                Event::Boundary(Boundary::CapPlane) => {
                    // Between the opal slice and the cap: reflected with probability F,
                    // else refracted into the other region.
                    let other = match region {
                        Region::Opal => Region::Cap,
                        Region::Cap => Region::Opal,
                    };
                    let (n1, n2) = (stone.index_of(region), stone.index_of(other));
                    let facing = if dir.z > 0.0 { -Vec3::Z } else { Vec3::Z };
                    let f = fresnel_dielectric(-dir.dot(facing), n1, n2);
                    let at = ray.at(t_end);
                    match refract(dir, facing, n1, n2).filter(|_| s.draws.uniform_f32() >= f) {
                        Some(d) => {
                            dir = d;
                            weight *= (n1 / n2) * (n1 / n2);
                            region = other;
                            pos = at - facing * EPSILON_MM;
                        }
                        None => {
                            dir = reflect(dir, facing);
                            pos = at + facing * EPSILON_MM;
                        }
                    }
                    hint = Hint::default();
                    None
                }
            };
            // The camera ray's first segment in the opal splits (after a triplet's cap).
            if !(region == Region::Opal && first_in_cap) {
                split = false;
            }
            first_in_cap = false;
            if !self.roulette(&mut weight, s.draws) {
                return;
            }
            level += 1;
        }
    }

    /// Whether a path goes on to its event `level` (counted from 0): within `max_depth`
    /// events.
    fn goes_deeper(&self, level: u32) -> bool {
        level < self.setup.max_depth
    }

    /// Whether the environment's draw of `out` at `from` finds the refracted path that leaves
    /// the stone at `exit` ([`Tracer::environment_at`]'s solve).
    fn entry_found(&self, from: Vec3, out: Vec3, exit: Vec3) -> bool {
        let source = LightSource::Directional { direction: -out };
        refracted_entry(&self.stone.shape, &source, self.n_eff, from, None).is_some_and(
            |(entry, _, _)| {
                (entry - exit).length_squared() < 1e-4
                    && !self.stone.back.is_some_and(|b| entry.z <= b.z + EPSILON_MM)
            },
        )
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

    /// Next-event estimation of the environment (and an area light in front of it) at a
    /// scattering point `x` in the opal whose scattering density towards a direction (per
    /// steradian, inside) is `density`: one direction drawn from the environment's
    /// distribution, refracted in through the surface ([`refracted_entry`]), weighted by the
    /// balance heuristic against the scattering's own draw (see the escape in
    /// [`Tracer::inside`]).
    fn environment_at(
        &mut self,
        at: &Estimate,
        density: &dyn Fn(Vec3) -> f32,
        s: &mut CameraSample,
    ) {
        let Estimate { x, weight, .. } = *at;
        let u = [s.draws.uniform_f32(), s.draws.uniform_f32()];
        let sample = self.setup.environment.sample(u);
        if sample.pdf <= 0.0 {
            return;
        }
        let Some(inbound) = self.refracted_in(x, sample.direction) else {
            return;
        };
        let f = density(inbound.to_light);
        if f <= 0.0 {
            return;
        }
        let (value, light) = self.escaped_to(inbound.entry, sample.direction);
        if value <= 0.0 {
            return;
        }
        let p_b = f / inbound.spread;
        // Where it meets the area light, that light's own draw finds the same path.
        let p_area = if light {
            self.area_pdf(x, sample.direction)
        } else {
            0.0
        };
        let mis = sample.pdf / (sample.pdf + p_b + p_area);
        let irradiance = inbound.gain;
        self.add_towards(
            at,
            inbound.to_light,
            inbound.distance,
            None,
            |transmitted| weight * f * value * irradiance * transmitted * mis / sample.pdf,
            s,
        );
    }

    /// A domain crossing `at` of a path of `weight` and spectrum `lines` at event `level`:
    /// light estimation, the reflection branches (every one if `split`), and the lines the
    /// ray carries on through (added to `lines`). Returns what goes on: the ray through, its
    /// weight scaled; or, for a path already reflected, which either reflects or goes on (see
    /// the comment below), its reflection; or nothing.
    fn cross_domain(
        &mut self,
        at: &DomainSpan,
        weight: f32,
        lines: &mut PathSpectrum,
        split: bool,
        level: u32,
        s: &mut CameraSample,
    ) -> Crossing {
        let DomainSpan {
            ray,
            t0,
            chord,
            domain,
            cells,
        } = *at;
        let stone = self.stone;
        self.nee_hint = cells;
        let dir = ray.direction;
        self.lines.clear();
        stone.lines(domain, dir, chord, &mut self.lines);
        if self.lines.is_empty() {
            return Crossing::On(1.0);
        }
        let x = ray.at(t0 + EPSILON_MM);
        let estimate = Estimate {
            x,
            path: lines,
            weight,
        };
        self.light_at_domain(&estimate, dir, domain, s);
        // The branches below refill `self.lines`: this crossing keeps its own.
        let here = std::mem::take(&mut self.lines);
        let face = ray.at(t0);
        // Unless split, one reflection, drawn with twice the lines' share of white light (at
        // most ¼), as a branch: its weight is about 1/(2 × its share), never large against
        // what its line passes. A path already reflected chooses (below) with each line's
        // share of its own light, what the line reflects at the wavelengths it carries
        // (exact: the branches' weights are then about 1 at each wavelength; the floor keeps
        // every branch possible).
        let reflected = lines.reflects();
        let mut energy = [0.0f64; MAX_LINES_PER_CROSSING];
        // A reflected path's reflectances here, at its wavelengths: for its choice, and for
        // its pass on through (the table zeroed only for such a path).
        let mut at_path = if reflected {
            Some([[0.0f32; MAX_DRAWS]; MAX_LINES_PER_CROSSING])
        } else {
            None
        };
        for (i, (e, l)) in energy.iter_mut().zip(&here).enumerate() {
            let white = line_energy(&l.line);
            *e = match &mut at_path {
                Some(r) => lines
                    .reflectances(&l.line, &mut r[i])
                    .max(MIN_SHARE_OF_WHITE * white),
                None => white,
            };
        }
        let energy = &energy[..here.len().min(MAX_LINES_PER_CROSSING)];
        let total: f64 = energy.iter().sum();
        let chooses = !split && reflected;
        let p_branch = if chooses {
            total.min(MAX_CHOICE_PROBABILITY)
        } else {
            (2.0 * total).min(MAX_BRANCH_PROBABILITY)
        };
        // A path already reflected chooses (below); it finds the area light by its branches'
        // escapes alone: estimated at its every crossing, with the weight its choices give it,
        // the estimate would add more noise than it takes away (twice the variance, measured).
        if !chooses && self.estimated_area_light().is_some() {
            // Each line's probability of its branch, for the balance against the area light.
            let mut pick = [1.0f64; MAX_LINES_PER_CROSSING];
            if !split {
                for (p, e) in pick.iter_mut().zip(energy) {
                    *p = p_branch * e / total;
                }
            }
            let n = energy.len();
            let estimate = Estimate {
                x,
                path: lines,
                weight,
            };
            self.area_at_domain(&estimate, dir, domain, &here[..n], &pick[..n], s);
        }
        // A path already reflected chooses: it reflects (as above) or goes on through with
        // its weight over 1 − p. Forking it too would make a tree: its light lies in its line,
        // alike plates reflect that line again at about p = ¼ each, and a fork per plate over
        // many plates and events grows without bound. One path on, its cost grows with depth
        // only linearly.
        let mut goes_on = Some(1.0);
        let mut reflected_to = None;
        if split {
            // Every reflection as a branch of its own.
            let path = Reflection {
                face,
                x,
                dir,
                domain,
                cells,
                p_pick: Some(1.0),
                weight,
            };
            for line in &here {
                self.branch(&path, line, true, lines, level, s);
            }
        } else {
            let reflects = s.draws.uniform() < p_branch;
            if chooses {
                goes_on = (!reflects).then_some((1.0 / (1.0 - p_branch)) as f32);
            }
            if reflects {
                let mut u = s.draws.uniform() * total;
                let mut pick = here.len() - 1;
                for (i, e) in energy.iter().enumerate() {
                    if u < *e {
                        pick = i;
                        break;
                    }
                    u -= e;
                }
                let p_pick = p_branch * energy[pick] / total;
                let w = weight / p_pick as f32;
                let path = Reflection {
                    face,
                    x,
                    dir,
                    domain,
                    cells,
                    p_pick: (!chooses).then_some(p_pick),
                    weight: w,
                };
                if chooses {
                    reflected_to = self.reflected_path(&path, &here[pick], lines, s.draws);
                } else {
                    self.branch(&path, &here[pick], false, lines, level, s);
                }
            }
        }
        // The ray goes on through the planes, carrying 1 − R of each line.
        if goes_on.is_some() {
            for (i, l) in here.iter().enumerate() {
                match at_path.as_ref().and_then(|r| r.get(i)) {
                    Some(r) => lines.pass(r),
                    None => lines.transmit(l.line, self.setup.spectral),
                }
            }
        }
        self.lines = here;
        match (goes_on, reflected_to) {
            (Some(scale), _) => Crossing::On(scale),
            (None, Some(next)) => Crossing::Reflected(Box::new(next)),
            (None, None) => Crossing::Ended,
        }
    }

    /// Follow the reflection `path` by `line` as a path of its own; if `cull`, followed with
    /// the probability [`Tracer::follow_probability`] gives it (its weight over that).
    fn branch(
        &mut self,
        path: &Reflection,
        line: &ActiveLine,
        cull: bool,
        lines: &PathSpectrum,
        level: u32,
        s: &mut CameraSample,
    ) {
        let Some(mut state) = self.reflected_path(path, line, lines, s.draws) else {
            return;
        };
        if cull {
            // Russian roulette on what the branch's first escape will see.
            let p = self.follow_probability(path.face, state.dir);
            if p < 1.0 {
                if s.draws.uniform_f32() >= p {
                    return;
                }
                state.weight /= p;
            }
        }
        let mark = s.draws.mark();
        self.inside(state, false, level + 1, s);
        s.draws.reset(mark);
    }

    /// The path that the reflection `path` by `line` of a path of spectrum `lines` starts: the
    /// lobe's normal drawn ([`Tracer::reflection`]); `None` where it faces away or the path's
    /// light is all gone.
    fn reflected_path(
        &mut self,
        path: &Reflection,
        line: &ActiveLine,
        lines: &PathSpectrum,
        sampler: &mut PathSampler,
    ) -> Option<PathState> {
        let (d, l) = self.reflection(path.domain, line, path.dir, sampler)?;
        let branch = lines.reflected(l, self.setup.spectral, sampler.uniform());
        if branch.is_dark() {
            return None;
        }
        Some(PathState {
            pos: path.face,
            dir: d,
            weight: path.weight,
            lines: branch,
            skip: Some(path.domain),
            region: Region::Opal,
            drawn: path
                .p_pick
                .and_then(|p| self.drawn_branch(path.x, path.dir, d, line, p)),
            splits_scattering: false,
            hint: path.cells,
        })
    }

    /// The probability with which a reflection of the camera ray's first segment, leaving
    /// `from` along `dir`, is followed: what the room shows where it first meets the surface
    /// and refracts out, over [`FOLLOW_FROM`] of the room's brightest, at least [`MIN_FOLLOW`];
    /// 1 where it meets an area light, is reflected whole (beyond the critical angle) or
    /// meets anything but the surface first. Most reflections look into the dark room; the
    /// bright ones, which hold the picture's colour, are all followed.
    fn follow_probability(&self, from: Vec3, dir: Vec3) -> f32 {
        if self.follow_from <= 0.0 {
            return 1.0;
        }
        let stone = self.stone;
        let ray = Ray {
            origin: from,
            direction: dir,
        };
        let Some((t, Boundary::Surface)) = stone.exit(&ray, Region::Opal) else {
            return 1.0;
        };
        let exit = ray.at(t);
        let Some(out) = refract(dir, stone.shape.normal(exit), stone.n_eff, 1.0) else {
            return 1.0;
        };
        let (value, light) = self.escaped_to(exit, out);
        if light {
            return 1.0;
        }
        (value / self.follow_from).clamp(MIN_FOLLOW, 1.0)
    }

    /// A reflection of the ray along `dir` by `line` of `domain`: the lobe's normal drawn, the
    /// mirrored direction and the line at the half-vector angle; `None` if the drawn normal
    /// faces away.
    fn reflection(
        &self,
        domain: u32,
        line: &ActiveLine,
        dir: Vec3,
        sampler: &mut PathSampler,
    ) -> Option<(Vec3, BraggLine)> {
        let sigma = self.stone.lobe_sigma(line.kind, -dir.dot(line.normal));
        let h = sample_lobe(line.normal, sigma, sampler);
        let cos_h = -dir.dot(h);
        (cos_h > 0.0).then(|| (reflect(dir, h), self.line_at(domain, line, cos_h)))
    }

    /// `line`'s family in `domain` met at `cos_theta` ([`Stone::line_at`]).
    fn line_at(&self, domain: u32, line: &ActiveLine, cos_theta: f32) -> BraggLine {
        self.stone.line_at(domain, line, cos_theta)
    }

    /// The light reaching `x` straight ([`Stone::light_entry`], the surface's exact
    /// lensing), its irradiance scaled by the light's intensity.
    fn light_inside(&self, x: Vec3) -> Option<(Vec3, f32, f32)> {
        let light = self.setup.light?;
        let (to_light, irradiance, distance) = self.stone.light_entry(&light.source, x)?;
        Some((to_light, irradiance * light.intensity, distance))
    }

    /// Next-event estimation of the light at a crossing `at` of `domain` by a path along
    /// `dir`: each of the domain's lines (in `self.lines`) whose lobe holds the half vector.
    fn light_at_domain(&mut self, at: &Estimate, dir: Vec3, domain: u32, s: &mut CameraSample) {
        let Estimate { x, path, weight } = *at;
        let Some((to_light, irradiance, distance)) = self.light_inside(x) else {
            return;
        };
        let to_eye = -dir;
        let h = (to_light + to_eye).normalize_or_zero();
        let cos_h = h.dot(to_eye);
        if cos_h <= 0.0 {
            return;
        }
        let mut hits: [(ActiveLine, f32); 4] = [(self.lines[0], 0.0); 4];
        let mut count = 0;
        let lamp = self.setup.light.map_or(0.0, |l| l.disc_radius_rad);
        for line in &self.lines {
            let density = self.stone.lamp_density(line, h, cos_h, lamp);
            if density > 0.0 && count < hits.len() {
                hits[count] = (*line, density);
                count += 1;
            }
        }
        if count == 0 {
            return;
        }
        let Some((transmitted, notches)) = self.towards_light(x, to_light, distance, Some(domain))
        else {
            return;
        };
        for &(line, density) in &hits[..count] {
            let mut lines = path.reflected(
                self.line_at(domain, &line, cos_h),
                self.setup.spectral,
                s.draws.uniform(),
            );
            for n in &notches {
                lines.transmit(*n, self.setup.spectral);
            }
            let value = weight * PI * irradiance * transmitted * density / (4.0 * cos_h);
            self.add(&lines, value, s);
        }
    }

    /// Next-event estimation of the light at a scattering event `at` of a path travelling
    /// along `dir` (Henyey–Greenstein phase).
    fn light_at_potch(&mut self, at: &Estimate, dir: Vec3, s: &mut CameraSample) {
        let Estimate { x, weight, .. } = *at;
        let Some((to_light, irradiance, distance)) = self.light_inside(x) else {
            return;
        };
        // π × E × phase: light travelling along −to_light turned into −dir.
        let phase = hg_phase(self.stone.potch.anisotropy, to_light.dot(dir));
        self.add_towards(
            at,
            to_light,
            distance,
            None,
            |transmitted| weight * PI * irradiance * transmitted * phase,
            s,
        );
    }

    /// Next-event estimation of the light at the backing, at `at` (Lambert, facing +z).
    fn light_at_back(&mut self, at: &Estimate, s: &mut CameraSample) {
        let Estimate { x, weight, .. } = *at;
        let Some((to_light, irradiance, distance)) = self.light_inside(x) else {
            return;
        };
        let cos = to_light.z;
        if cos <= 0.0 {
            return;
        }
        // π × ρ E cos / π (ρ is in the weight or the path's tint).
        self.add_towards(
            at,
            to_light,
            distance,
            None,
            |transmitted| weight * irradiance * transmitted * cos,
            s,
        );
    }

    /// What lies between `x` and the light's entry point ([`Stone::towards_light`]): the
    /// transmittance and the lines of the domains crossed (except `skip`); `None` where under
    /// 10⁻⁶ of the light passes.
    fn towards_light(
        &mut self,
        x: Vec3,
        to_light: Vec3,
        distance: f32,
        skip: Option<u32>,
    ) -> Option<(f32, Vec<BraggLine>)> {
        let mut notches = Vec::new();
        let t = self.stone.towards_light(
            x,
            to_light,
            distance,
            self.nee_hint,
            skip,
            &mut self.light_spans,
            &mut self.light_lines,
            &mut |_, line| notches.push(line),
        );
        (t > 1e-6).then_some((t, notches))
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

/// A new direction after scattering a path travelling along `dir` by the Henyey–Greenstein
/// phase of anisotropy `g`.
fn sample_hg(dir: Vec3, g: f32, sampler: &mut PathSampler) -> Vec3 {
    let cos = hg_cos(f64::from(g), sampler.uniform()) as f32;
    let sin = (1.0 - cos * cos).max(0.0).sqrt();
    let phi = 2.0 * PI * sampler.uniform_f32();
    let (t, b) = dir.any_orthonormal_pair();
    (dir * cos + (t * phi.cos() + b * phi.sin()) * sin).normalize()
}

/// A direction drawn with density `cos θ / π` about +z.
fn cosine_about_z(sampler: &mut PathSampler) -> Vec3 {
    let r = sampler.uniform_f32().sqrt();
    let phi = 2.0 * PI * sampler.uniform_f32();
    Vec3::new(r * phi.cos(), r * phi.sin(), (1.0 - r * r).max(0.0).sqrt())
}

/// A normal drawn about `n` with a Gaussian tilt of standard deviation `sigma` (radians).
fn sample_lobe(n: Vec3, sigma: f32, sampler: &mut PathSampler) -> Vec3 {
    let u = (1.0 - sampler.uniform_f32()).max(1e-12);
    let alpha = sigma * (-2.0 * u.ln()).sqrt();
    let phi = 2.0 * PI * sampler.uniform_f32();
    let (t, b) = n.any_orthonormal_pair();
    (n * alpha.cos() + (t * phi.cos() + b * phi.sin()) * alpha.sin()).normalize()
}

#[cfg(test)]
mod tests {
    use super::nee::tests::{mean_y_with, studio_8x8};
    use super::*;

    #[test]
    fn the_roulette_on_first_reflections_keeps_the_mean() {
        // The harlequin's cabochon under the studio, seen whole: with every reflection of the
        // camera ray's first segment followed, and with each followed at random (the bar
        // raised over the room's brightest, so that nearly every one is followed with
        // probability ¼, its weight over that), the mean is the same (4 standard errors).
        let mut scene = crate::scene::preset("harlequin").unwrap();
        scene.structure.seed = 1;
        let stone = Stone::new(&scene).unwrap();
        let sampler = SpectralSampler::new(scene.light.illuminant, &scene.spectrum, 4);
        let setup = studio_8x8(&sampler, 1.0, None, 12.0, 3);
        let tracer = Tracer::new(&stone, &setup);
        assert!(tracer.follow_from > 0.0);
        // A reflection straight up from the centre looks out through the camera's dark side
        // of the room: followed with the least probability.
        let p = tracer.follow_probability(Vec3::ZERO, Vec3::Z);
        assert_eq!(p, MIN_FOLLOW);
        let spp = 400;
        let [all, se_all, _] = mean_y_with(&stone, &setup, 0, spp, |t| t.follow_from = 0.0);
        let bar = 4.0 * setup.environment.peak();
        let [some, se_some, _] = mean_y_with(&stone, &setup, 1, spp, |t| t.follow_from = bar);
        let se = (se_all * se_all + se_some * se_some).sqrt();
        assert!(
            (some - all).abs() <= 4.0 * se,
            "roulette {some} vs all {all} ± {se}"
        );
    }
}
