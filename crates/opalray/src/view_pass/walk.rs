//! One camera ray through the stone (paper §3.3, fig. 7): cell by cell it adds eq. (2)'s
//! terms, each filtered by what the ray has crossed, while the clusters' transmittance and
//! the voids' potch filter its throughput; at the far surface it sees the backdrop and
//! reflects internally.

use glam::Vec3;

use super::{CellTag, ClusterShade};
use super::{Deferred, Path, View, SHARED_REFLECTION};
use crate::geometry::{fresnel_dielectric, reflect, Ray};
use crate::light_pass::{Transmission, NO_PATCH};
use crate::structure::Cell;

/// Internal reflections followed per camera ray.
const MAX_VIEW_BOUNCES: u32 = 4;
/// The camera ray stops once its throughput falls below this at every wavelength: what lies
/// behind would change the default image by 0.45 % RMS (measured against 10⁻³).
const MIN_THROUGHPUT: f32 = 4e-3;

/// Where a camera ray's walk inside the stone starts, and its throughput's scale there.
#[derive(Clone, Copy, Debug)]
pub(super) struct WalkStart {
    /// A point on or inside the surface, mm.
    pub origin: Vec3,
    /// The ray's direction (unit).
    pub direction: Vec3,
    /// The throughput's flat factor (its shape is [`RayBuffers::shape_thr`]).
    pub scale: f32,
}

/// The buffers one camera ray writes: the pixel's spectrum it adds to, the shape of its
/// throughput and the transmittance scratch.
pub(super) struct RayBuffers<'a> {
    /// The spectrum seen, per bin.
    pub pixel: &'a mut [f32],
    /// The throughput's shape, at most 1 in every bin.
    pub shape_thr: &'a mut [f32],
    /// Scratch for a cluster's transmittance.
    pub transmission: &'a mut Transmission,
}

impl View<'_> {
    /// Walk a ray inside the stone from `start` (on or inside the surface) with throughput
    /// `start.scale × buffers.shape_thr`, adding what it sees to `buffers.pixel`, through
    /// internal reflections until [`MAX_VIEW_BOUNCES`] segments (counting from `path.first`)
    /// are walked or it fades; `peak` is the bin of the throughput shape's maximum.
    pub(super) fn walk(
        &self,
        start: WalkStart,
        peak: &mut usize,
        path: Path,
        mut buffers: RayBuffers<'_>,
    ) -> Option<Deferred> {
        let WalkStart {
            mut origin,
            direction: mut dir,
            mut scale,
        } = start;
        // The whole walk runs in the copy compiled for the processor's vector level.
        crate::simd::widest(
            #[inline(always)]
            move || {
                for bounce in path.first..MAX_VIEW_BOUNCES {
                    let inner = Ray {
                        origin,
                        direction: dir,
                    };
                    let (t0, t1) = self.ellipsoid.intersect(&inner)?;
                    scale = self.walk_cells(&inner, (t0.max(0.0), t1), scale, peak, &mut buffers);
                    if scale <= MIN_THROUGHPUT {
                        return None;
                    }
                    // Far surface: the backdrop through the stone, and internal reflection.
                    let q = inner.at(t1);
                    let seen = (&mut *buffers.pixel, &*buffers.shape_thr);
                    let (f_out, n_q) = self.far_surface(q, dir, seen, scale);
                    scale *= f_out;
                    dir = reflect(dir, n_q);
                    origin = q;
                    if scale <= MIN_THROUGHPUT {
                        return None;
                    }
                    if path.defer && bounce == 0 && f_out < SHARED_REFLECTION {
                        return Some(Deferred {
                            origin,
                            direction: dir,
                            scale,
                            peak: *peak,
                        });
                    }
                }
                None
            },
        )
    }

    /// Walk the cells along `inner` from `t0` to `t1` with throughput `scale ×
    /// buffers.shape_thr`: each void's glow and each cluster's eq. (2) terms added to
    /// `buffers.pixel`, the throughput filtered by each; returns the throughput's scale where
    /// the walk stopped (at `t1`, or where it fell to [`MIN_THROUGHPUT`]).
    #[inline(always)]
    fn walk_cells(
        &self,
        inner: &Ray,
        (t0, t1): (f32, f32),
        mut scale: f32,
        peak: &mut usize,
        buffers: &mut RayBuffers<'_>,
    ) -> f32 {
        let pixel = &mut *buffers.pixel;
        let shape_thr = &mut *buffers.shape_thr;
        let transmission = &mut *buffers.transmission;
        let dir = inner.direction;
        let to_eye = -dir;
        // Along one segment, cells of one patch meet the ray at the same angle and share
        // their transmittance.
        let mut last_patch = NO_PATCH;
        self.grid.traverse(
            inner,
            t0,
            t1,
            #[inline(always)]
            |seg| {
                let tag = self.shading.tags[seg.index];
                let slot = tag.slot();
                match tag.cell() {
                    Cell::Outside => return true,
                    Cell::Void => {
                        let kept =
                            (-self.setup.body_extinction_per_mm * (seg.t_exit - seg.t_enter)).exp();
                        let glow = &self.shading.diffuse[slot * self.bins..(slot + 1) * self.bins];
                        add_filtered(pixel, shape_thr, glow, scale * (1.0 - kept));
                        scale *= kept;
                    }
                    Cell::Cluster => {
                        let shade = &self.shading.clusters[slot];
                        let seen = (&mut *pixel, &*shape_thr);
                        self.add_cluster((tag, shade), to_eye, seen, scale);
                        if shade.patch != last_patch {
                            last_patch = shade.patch;
                            let normal = self.shading.patch_normals[last_patch as usize];
                            self.optics
                                .transmission(dir.dot(normal).abs(), transmission);
                        }
                        scale *= transmission.apply(shape_thr, peak);
                    }
                }
                scale > MIN_THROUGHPUT
            },
        );
        scale
    }
}

impl View<'_> {
    /// Add to `seen`'s pixel what the cluster cell of `tag` (shaded as `shade`) shows towards
    /// the eye (`to_eye`), filtered by `seen`'s throughput shape times `scale`: eq. (2)'s
    /// specular term `E · R(θ) · peak · cosⁿ' θ'` of each lobe within its cut-off, and its
    /// glow where it glows.
    #[inline(always)]
    fn add_cluster(
        &self,
        (tag, shade): (CellTag, &ClusterShade),
        to_eye: Vec3,
        (pixel, shape_thr): (&mut [f32], &[f32]),
        scale: f32,
    ) {
        let slot = tag.slot();
        // The packed spectrum of the next lobe that has one.
        let mut entry = shade.first as usize;
        for l in &shade.lobes {
            let c = l.mirror.dot(to_eye);
            if c > l.cos_min {
                let at = entry * self.bins;
                let spectrum = &self.shading.specular[at..at + self.bins];
                add_filtered(pixel, shape_thr, spectrum, scale * c.powf(l.exponent));
            }
            entry += usize::from(l.has_spectrum());
        }
        if tag.glows() {
            let glow = &self.shading.diffuse[slot * self.bins..(slot + 1) * self.bins];
            add_filtered(pixel, shape_thr, glow, scale);
        }
    }

    /// At the far surface point `q` of a ray travelling along `dir` with throughput `scale ×`
    /// `seen`'s shape: add to `seen`'s pixel the backdrop seen through the surface; return the
    /// surface's internal reflectance and its normal at `q`.
    #[inline(always)]
    fn far_surface(
        &self,
        q: Vec3,
        dir: Vec3,
        (pixel, shape_thr): (&mut [f32], &[f32]),
        scale: f32,
    ) -> (f32, Vec3) {
        let n_q = self.ellipsoid.normal(q);
        let f_out = fresnel_dielectric(dir.dot(n_q), self.n_eff, 1.0);
        let seen = (1.0 - f_out) * self.n_eff * self.n_eff * self.setup.background;
        add_filtered(pixel, shape_thr, self.setup.light_spectrum, scale * seen);
        (f_out, n_q)
    }
}

/// `pixel += k · shape ⊙ spectrum`.
#[inline(always)]
pub(super) fn add_filtered(pixel: &mut [f32], shape: &[f32], spectrum: &[f32], k: f32) {
    crate::spectrum::add_product(pixel, shape, spectrum, k);
}
