//! The eye-independent half of eq. (2), computed once per light: for each cluster and stored
//! lobe, where its Bragg reflection goes and how wide its Phong lobe is; for each cell, its
//! diffuse glow.

use glam::Vec3;
use rayon::prelude::*;

use crate::light_pass::{ClusterOptics, LightField, VoxelLayout, LOBES, NO_PATCH, NO_SLOT};
use crate::structure::{Cell, Structure};

mod slot;

use slot::{shade_slot, ShadeSources, Slot};

/// Phong lobes below this fraction of their peak are skipped.
pub const LOBE_CUTOFF: f32 = 1e-3;
/// Diffuse spectra whose largest value is below this are skipped: 10⁻⁶ per bin is a
/// luminance under 10⁻⁴ of a white diffuser's, below one step of an 8-bit sRGB image even in
/// the darkest tones (the light's spectrum at unit irradiance is about 10⁻² per bin).
const GLOW_FLOOR: f32 = 1e-6;
/// Stored light meeting the planes more obliquely than this (|cos θ| below it, θ > 80°) adds
/// no specular term: near grazing incidence the stack's reflection turns the light by under
/// 20°, a near-forward deflection that a Phong lobe about the mirror direction cannot
/// represent (and the evanescent regime past 85.6° would show as white specks).
const MIN_SPECULAR_COS: f32 = 0.173_648_18; // cos 80°

/// The specular lobe of one stored light at one cluster.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Lobe {
    /// Direction of the Bragg-reflected light (zero: no specular term).
    pub mirror: Vec3,
    /// Cosine below which the lobe is under [`LOBE_CUTOFF`] of its peak (above 1: never
    /// seen), a cheap test before `powf`.
    pub cos_min: f32,
    /// Phong exponent, widened from `n` by the spread of the stored light's directions
    /// (Toksvig 2005): `n' = ρ n / (ρ + n (1 − ρ))`, ρ the mean resultant length. Light
    /// stored from one direction keeps `n`; light mixed from many directions reflects into a
    /// broad, dim lobe instead of a spurious sharp one.
    pub exponent: f32,
}

impl Lobe {
    /// Whether the lobe has a specular term (and a packed spectrum in [`Shading::specular`]).
    #[inline(always)]
    pub fn has_spectrum(&self) -> bool {
        self.cos_min <= 1.0
    }
}

const NO_LOBE: Lobe = Lobe {
    mirror: Vec3::ZERO,
    cos_min: 2.0,
    exponent: 1.0,
};

/// What a camera ray reads first about a cell it crosses, in one word: the cell's storage
/// slot and kind, and whether its diffuse spectrum holds anything visible.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct CellTag(u32);

impl CellTag {
    const CLUSTER: u32 = 1 << 31;
    const GLOWS: u32 = 1 << 30;
    const OUTSIDE: CellTag = CellTag(u32::MAX);

    fn new(cell: Cell, slot: u32, glows: bool) -> Self {
        assert!(
            cell == Cell::Outside || slot < CellTag::GLOWS,
            "slots stay below 2³⁰ (the grid's size is checked)"
        );
        let glow = if glows { CellTag::GLOWS } else { 0 };
        match cell {
            Cell::Outside => CellTag::OUTSIDE,
            Cell::Void => CellTag(slot | glow),
            Cell::Cluster => CellTag(slot | glow | CellTag::CLUSTER),
        }
    }

    /// The cell's kind.
    #[inline(always)]
    pub fn cell(self) -> Cell {
        if self == CellTag::OUTSIDE {
            Cell::Outside
        } else if self.0 & CellTag::CLUSTER != 0 {
            Cell::Cluster
        } else {
            Cell::Void
        }
    }

    /// The cell's storage slot (meaningless outside).
    #[inline(always)]
    pub fn slot(self) -> usize {
        (self.0 & !(CellTag::CLUSTER | CellTag::GLOWS)) as usize
    }

    /// Whether the cell's diffuse spectrum holds anything visible.
    #[inline(always)]
    pub fn glows(self) -> bool {
        self.0 & CellTag::GLOWS != 0
    }
}

/// What a camera ray reads about a cluster it crosses, in one record (one or two cache lines
/// instead of one per array): its patch (whose (111) normal is in [`Shading::patch_normals`])
/// and the specular lobe of each stored light.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ClusterShade {
    /// The cluster's patch ([`NO_PATCH`] for voids).
    pub patch: u32,
    /// The specular lobe of each stored light.
    pub lobes: [Lobe; LOBES],
    /// Index in [`Shading::specular`] of the spectrum of its first lobe that has one; the
    /// others that have one follow, in lobe order.
    pub first: u32,
}

const NO_SHADE: ClusterShade = ClusterShade {
    patch: NO_PATCH,
    lobes: [NO_LOBE; LOBES],
    first: 0,
};

/// Per-slot shading terms, in units where a white Lambertian diffuser under unit irradiance
/// has the light's spectrum (π × radiance). The specular term of a lobe,
/// `E · R(θ) · peak · cosⁿ' θ'`, is its spectrum `E · R(θ) · peak` (formed here, once per
/// light) times `cosⁿ' θ'` (formed in the view pass where a camera ray meets the lobe).
#[derive(Clone, Debug)]
pub struct Shading {
    /// Bins per spectrum.
    pub bins: usize,
    /// Per cell of the grid, its slot, kind and whether it glows.
    pub tags: Vec<CellTag>,
    /// Per slot, the cluster's patch and specular lobes.
    pub clusters: Vec<ClusterShade>,
    /// The (111) normal of each patch (see [`VoxelLayout::patch_normals`]).
    pub patch_normals: Vec<Vec3>,
    /// Specular spectra `E · R(θ) · peak` of the lobes that have a specular term (61 % of the
    /// default render's), packed: `bins` values each, in slot and lobe order (see
    /// [`ClusterShade::first`]); the peak of the normalised Phong lobe times π is
    /// `(n' + 2) / 2`.
    pub specular: Vec<f32>,
    /// Diffuse spectra `slots × bins`: clusters Σ E · D(θ) · cos θ (eq. 2's first sum);
    /// voids the potch's single scattering a · Σ E / 4, to be weighted by the fraction of
    /// the view ray the void intercepts.
    pub diffuse: Vec<f32>,
}

impl Shading {
    /// Shade every stored slot of `light`, stored in the voxels `voxels` lays out of `structure`.
    pub fn new(
        structure: &Structure,
        voxels: &VoxelLayout,
        optics: &ClusterOptics,
        light: &LightField,
        phong_exponent: f32,
        body_albedo: f32,
    ) -> Self {
        let bins = light.grid.bins;
        // Where each cluster's stored light reflects, and how wide: no spectra yet.
        let mut clusters = place_lobes(structure, voxels, light, phong_exponent);
        // The specular spectra of the lobes that have one, packed in slot and lobe order.
        let mut packed = 0u32;
        for shade in &mut clusters {
            shade.first = packed;
            packed += shade.lobes.iter().filter(|l| l.has_spectrum()).count() as u32;
        }
        let mut specular = crate::spectrum::zeroed(packed as usize * bins);
        let mut diffuse = crate::spectrum::zeroed(clusters.len() * bins);
        let stored = ShadeSources {
            optics,
            light,
            body_albedo,
        };
        let grid = Grid { structure, voxels };
        shade_runs(grid, &clusters, &stored, &mut specular, &mut diffuse);
        let tags = structure
            .cells
            .par_iter()
            .zip(&voxels.slot_of_cell)
            .map(|(&cell, &slot)| {
                let glows = slot != NO_SLOT && {
                    let g = &diffuse[slot as usize * bins..(slot as usize + 1) * bins];
                    g.iter().any(|&v| v > GLOW_FLOOR)
                };
                CellTag::new(cell, slot, glows)
            })
            .collect();
        Shading {
            bins,
            tags,
            clusters,
            patch_normals: voxels.patch_normals.clone(),
            specular,
            diffuse,
        }
    }
}

/// Each cluster slot's patch and specular lobes (where its stored light reflects, and how
/// wide: the Phong exponent `n'` from the stored light's concentration ρ and `n`); voids
/// and outside cells keep [`NO_SHADE`].
fn place_lobes(
    structure: &Structure,
    voxels: &VoxelLayout,
    light: &LightField,
    phong_exponent: f32,
) -> Vec<ClusterShade> {
    let slots = light.directions.len() / LOBES;
    let cell_of_slot = &voxels.cell_of_slot;
    let mut clusters = vec![NO_SHADE; slots];
    clusters
        .par_iter_mut()
        .enumerate()
        .for_each(|(slot, shade)| {
            let cell = cell_of_slot[slot];
            if structure.cells[cell] != Cell::Cluster {
                return;
            }
            let normal = voxels.normal(cell);
            shade.patch = voxels.patch(cell);
            for (lobe, out) in shade.lobes.iter_mut().enumerate() {
                let w = light.directions[slot * LOBES + lobe];
                if w == Vec3::ZERO || w.dot(normal).abs() < MIN_SPECULAR_COS {
                    continue;
                }
                let rho = light.concentration[slot * LOBES + lobe];
                let n = phong_exponent;
                let exponent = (rho * n / (rho + n * (1.0 - rho)).max(f32::MIN_POSITIVE)).max(1e-3);
                *out = Lobe {
                    mirror: crate::geometry::reflect(w, normal),
                    cos_min: LOBE_CUTOFF.powf(1.0 / exponent),
                    exponent,
                };
            }
        });
    clusters
}

/// Slots shaded together, each run with its share of the packed specular spectra.
const RUN: usize = 256;

/// The grid the slots lie in: the cells' kinds and their layout.
#[derive(Clone, Copy)]
struct Grid<'a> {
    structure: &'a Structure,
    voxels: &'a VoxelLayout,
}

/// Every slot's glow into `diffuse` and its lobes' specular spectra into `specular` (packed
/// as [`ClusterShade::first`] says), in runs of [`RUN`] slots in parallel: each run writes
/// only its own slices, so the values do not depend on the thread count.
fn shade_runs(
    grid: Grid,
    clusters: &[ClusterShade],
    stored: &ShadeSources,
    specular: &mut [f32],
    diffuse: &mut [f32],
) {
    let Grid { structure, voxels } = grid;
    let bins = stored.light.grid.bins;
    let packed = (specular.len() / bins.max(1)) as u32;
    let cell_of_slot = &voxels.cell_of_slot;
    let mut runs = Vec::with_capacity(clusters.len().div_ceil(RUN));
    let mut rest = specular;
    for (k, run) in clusters.chunks(RUN).enumerate() {
        let end = clusters
            .get((k + 1) * RUN)
            .map_or(packed, |next| next.first);
        let (head, tail) = rest.split_at_mut((end - run[0].first) as usize * bins);
        runs.push(head);
        rest = tail;
    }
    runs.into_par_iter()
        .zip(diffuse.par_chunks_mut(RUN * bins))
        .enumerate()
        .for_each_init(
            || vec![0.0f32; bins],
            // Each run's spectral loops in the copy compiled for the processor's vector
            // level (`simd`).
            |d, (k, (spec, glows))| {
                crate::simd::widest(
                    #[inline(always)]
                    || {
                        let mut spec = spec.chunks_exact_mut(bins);
                        for (j, glow) in glows.chunks_exact_mut(bins).enumerate() {
                            let slot = k * RUN + j;
                            let shade = &clusters[slot];
                            let cell = cell_of_slot[slot];
                            let at = Slot {
                                index: slot,
                                cell: structure.cells[cell],
                                normal: voxels.normal(cell),
                            };
                            shade_slot(at, shade, stored, glow, &mut spec, d);
                        }
                    },
                )
            },
        );
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::light_pass::{trace_light, LightSetup, Termination};

    #[test]
    fn packed_specular_spectra_belong_to_their_lobes() {
        // A small stone lit by the default light: every lobe with a specular term has its own
        // spectrum, in slot and lobe order, equal to E · R(θ) · (n' + 2) / 2 formed here
        // lobe by lobe; lobes without one are never seen.
        let (prepared, voxels) = VoxelLayout::of_default_scene([40, 30, 10]);
        let spectrum = prepared.light_spectrum();
        let (_, source) = prepared.placement(30.0);
        let light = trace_light(
            prepared.structure().unwrap(),
            &voxels,
            prepared.optics().unwrap(),
            &LightSetup {
                source,
                spectrum: &spectrum,
                rays: 4096,
                seed: 1,
                body_albedo: 0.5,
                body_extinction_per_mm: 3.0,
                termination: Termination::DEFAULT,
            },
        );
        let optics = ClusterOptics::new(prepared.optics().unwrap());
        let shading = Shading::new(
            prepared.structure().unwrap(),
            &voxels,
            &optics,
            &light,
            40.0,
            0.5,
        );
        let bins = shading.bins;
        let mut r = vec![0.0f32; bins];
        let (mut packed, mut with_light) = (0usize, 0usize);
        for (slot, shade) in shading.clusters.iter().enumerate() {
            assert_eq!(shade.first as usize, packed, "slot {slot}");
            for (lobe, l) in shade.lobes.iter().enumerate() {
                if !l.has_spectrum() {
                    assert!(l.cos_min > 1.0, "a lobe without a spectrum is never seen");
                    continue;
                }
                let w = light.directions[slot * LOBES + lobe];
                let cos = w.dot(shading.patch_normals[shade.patch as usize]).abs();
                let reflectance: Vec<f32> = match optics.reflectance(cos, &mut r) {
                    Some(flat) => vec![flat; bins],
                    None => r.clone(),
                };
                let peak = 0.5 * (l.exponent + 2.0);
                let expected: Vec<f32> = light
                    .fluence(slot, lobe)
                    .iter()
                    .zip(&reflectance)
                    .map(|(&e, &r)| e * r * peak)
                    .collect();
                let got = &shading.specular[packed * bins..(packed + 1) * bins];
                assert_eq!(got, &expected[..], "slot {slot}, lobe {lobe}");
                with_light += usize::from(got.iter().any(|&v| v > 0.0));
                packed += 1;
            }
        }
        assert_eq!(shading.specular.len(), packed * bins);
        assert!(
            with_light > shading.clusters.len() / 4,
            "{with_light} lit lobes of {} slots",
            shading.clusters.len()
        );
    }
}
