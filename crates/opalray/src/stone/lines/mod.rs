//! The Bragg lines a ray meets crossing a domain: input a domain, a direction and the chord's
//! length → output the [`ActiveLine`] of every family slot whose first-order line falls in the
//! spectral range (`docs/model.md`, the lines and their widths), or only those whose window
//! holds one wavelength.
//!
//! Every crossing of every domain by the eye ray and by the reflections the lobe integrator
//! follows comes here, 25 slots a domain for all families: the per-slot constants are read
//! from one flat array, and a wavelength's test rejects a slot before the line is built.

use glam::{Vec3, Vec4};

use super::{ActiveLine, Stone, LINE_REACH};
use crate::optics::{BraggLine, Families};

/// How much wider than at the constant index a line's window is taken in the first test of
/// [`Stone::lines_at`] with the dispersion: it moves a window's centre by under 4 % and its
/// half-width by under 5 %, and the wavelength's constant-index centre by its own shift
/// (`optics::dispersion`; under 10 % together, from 250 nm). The exact test follows.
const WINDOW_SLACK: f64 = 1.25;

/// Relative margin of the slots' first test ([`SlotTable::reach`]) below the exact bound:
/// far above the f32 roundings of the test (~10⁻⁷), so it never rejects a slot whose line's
/// centre reaches the range.
const REACH_MARGIN: f32 = 1e-4;

/// What [`Stone::lines`] reads of one family slot (a normal of one family kind), the same for
/// every domain.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(super) struct SlotOptics {
    /// The family kind (index into [`Families::kinds`]).
    pub kind: u8,
    /// The kind's plane spacing over the sphere diameter, `d / D`.
    pub spacing_over_diameter: f64,
    /// The kind's relative coupling `g`.
    pub coupling: f64,
    /// Coherent layers of the kind (the (111) `crystal.layers`, as a thickness).
    pub layer_cap: f64,
}

/// The family slots of every domain, four to a block: per slot its optics; per block the
/// first test of its four slots and which lanes hold one.
#[derive(Clone, Debug, PartialEq)]
pub(super) struct SlotTable {
    /// Per slot, in order (kind by kind, each kind's normals in turn).
    pub optics: Vec<SlotOptics>,
    /// Per block, per lane, a lower bound of `D · |cos θ|` (`D` the domain's sphere
    /// diameter, nm) for the line's centre `2 d n̄ |cos θ|` to reach [`LINE_REACH`] × the
    /// range's short end: a slot under it has no line.
    reach: Vec<Vec4>,
    /// Per block, the lanes holding a slot (bit `l` for lane `l`).
    lanes: Vec<u32>,
    /// Per block, per lane, the slot's `d / D`, coupling `g` and layer cap (`f32`; unused
    /// lanes 1, 0, 1): what [`WindowTest`] reads.
    lane_optics: Vec<[Vec4; 3]>,
}

impl SlotTable {
    /// The slots of `families` in a stone of index `n_eff`, keeping the lines whose centre at
    /// the constant index ([`crate::optics::CrystalIndex::constant_centre_nm`]) reaches
    /// `reach_nm`, for `layers_111` coherent (111) layers.
    pub fn new(families: &Families, n_eff: f32, reach_nm: f64, layers_111: f64) -> Self {
        let d111 = families.kinds[0].spacing_over_diameter;
        let optics: Vec<SlotOptics> = (families.kinds.iter().enumerate())
            .flat_map(|(k, f)| {
                let slot = SlotOptics {
                    kind: k as u8,
                    spacing_over_diameter: f.spacing_over_diameter,
                    coupling: f.coupling,
                    layer_cap: layers_111 * d111 / f.spacing_over_diameter,
                };
                std::iter::repeat(slot).take(f.normals.len())
            })
            .collect();
        let two_n = 2.0 * f64::from(n_eff);
        let reach_of = |slot: Option<&SlotOptics>| {
            slot.map_or(0.0, |s| {
                let exact = reach_nm / (two_n * s.spacing_over_diameter);
                exact as f32 * (1.0 - REACH_MARGIN)
            })
        };
        let blocks = optics.len().div_ceil(4);
        let reach = (0..blocks)
            .map(|b| Vec4::from_array(std::array::from_fn(|l| reach_of(optics.get(4 * b + l)))))
            .collect();
        let lanes = (0..blocks)
            .map(|b| {
                (0..4)
                    .filter(|l| 4 * b + l < optics.len())
                    .map(|l| 1u32 << l)
                    .sum()
            })
            .collect();
        let lane_optics = (0..blocks)
            .map(|b| {
                let lane = |l: usize, f: fn(&SlotOptics) -> f64, unused: f32| {
                    optics.get(4 * b + l).map_or(unused, |s| f(s) as f32)
                };
                let column = |f: fn(&SlotOptics) -> f64, unused: f32| {
                    Vec4::from_array(std::array::from_fn(|l| lane(l, f, unused)))
                };
                [
                    column(|s| s.spacing_over_diameter, 1.0),
                    column(|s| s.coupling, 0.0),
                    column(|s| s.layer_cap, 1.0),
                ]
            })
            .collect();
        SlotTable {
            optics,
            reach,
            lanes,
            lane_optics,
        }
    }

    /// Blocks of four slots per domain.
    pub fn blocks(&self) -> usize {
        self.reach.len()
    }
}

/// Four slots' unit normals of one domain (stone frame), by coordinate; unused lanes 0.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(super) struct NormalBlock {
    x: Vec4,
    y: Vec4,
    z: Vec4,
}

/// `normals` (`slots` per domain, domain by domain) in blocks of four per domain.
pub(super) fn normal_blocks(normals: &[Vec3], slots: usize) -> Vec<NormalBlock> {
    normals
        .chunks(slots)
        .flat_map(|domain| {
            domain.chunks(4).map(|four| {
                let lane = |k: usize, f: fn(Vec3) -> f32| four.get(k).map_or(0.0, |&n| f(n));
                let column =
                    |f: fn(Vec3) -> f32| Vec4::new(lane(0, f), lane(1, f), lane(2, f), lane(3, f));
                NormalBlock {
                    x: column(|n| n.x),
                    y: column(|n| n.y),
                    z: column(|n| n.z),
                }
            })
        })
        .collect()
}

impl Stone {
    /// The lines of domain `domain` that a ray along `dir` (unit) crossing it over `chord_mm`
    /// meets within the spectral range, pushed onto `out` in slot order.
    pub fn lines(&self, domain: u32, dir: Vec3, chord_mm: f32, out: &mut Vec<ActiveLine>) {
        self.push_lines(domain, dir, chord_mm, None, out);
    }

    /// The lines of [`Stone::lines`] whose window ([`BraggLine::window_nm`]) holds
    /// `wavelength_nm` (strictly inside it), pushed onto `out`: the same lines in the same
    /// order as filtering `lines`' output, at a fraction of its cost (most slots are rejected
    /// before their line is built).
    pub fn lines_at(
        &self,
        domain: u32,
        dir: Vec3,
        chord_mm: f32,
        wavelength_nm: f64,
        out: &mut Vec<ActiveLine>,
    ) {
        let at = self.line_wavelength(wavelength_nm);
        self.push_lines(domain, dir, chord_mm, Some(at), out);
    }

    /// `wavelength_nm` as [`Stone::lines_at_wavelength`] tests it (with the dispersion, its
    /// centre at the constant index, solved once for every crossing of one ray).
    pub fn line_wavelength(&self, wavelength_nm: f64) -> LineWavelength {
        let index = &self.families.index;
        LineWavelength {
            wavelength_nm,
            constant_wavelength_nm: (!index.is_constant())
                .then(|| index.constant_centre_nm(wavelength_nm)),
        }
    }

    /// [`Stone::lines_at`] at a wavelength prepared by [`Stone::line_wavelength`]: the same
    /// lines, for a ray that crosses many domains at one wavelength.
    pub fn lines_at_wavelength(
        &self,
        domain: u32,
        dir: Vec3,
        chord_mm: f32,
        at: LineWavelength,
        out: &mut Vec<ActiveLine>,
    ) {
        self.push_lines(domain, dir, chord_mm, Some(at), out);
    }

    /// [`Stone::lines`], keeping only the lines whose window holds `at`'s wavelength if
    /// given. Four slots at a time are tested against their reach ([`SlotTable`]); the few
    /// left are built one by one.
    #[inline(always)]
    fn push_lines(
        &self,
        domain: u32,
        dir: Vec3,
        chord_mm: f32,
        at: Option<LineWavelength>,
        out: &mut Vec<ActiveLine>,
    ) {
        let table = &self.slots;
        let blocks = &self.normals[domain as usize * table.blocks()..][..table.blocks()];
        let diameter = self.domains[domain as usize].sphere_diameter_nm;
        let per_diameter = Vec4::splat(1.0 / diameter);
        let (dx, dy, dz) = (Vec4::splat(dir.x), Vec4::splat(dir.y), Vec4::splat(dir.z));
        let lines = LineArgs {
            diameter_nm: f64::from(diameter),
            two_n: 2.0 * f64::from(self.n_eff) * f64::from(diameter),
            chord_nm: f64::from(chord_mm) * 1e6,
            wavelength_nm: at.map(|a| a.wavelength_nm),
            constant_wavelength_nm: at.and_then(|a| a.constant_wavelength_nm),
        };
        let window = at.map(|at| WindowTest::new(at, &lines, diameter));
        let per_block = blocks.iter().zip(&table.reach).zip(&table.lanes);
        for (b, ((n, &reach), &lanes)) in per_block.enumerate() {
            // `n · dir` lane by lane, summed as `Vec3::dot` sums.
            let dot = n.x * dx + n.y * dy + n.z * dz;
            // Short of its reach (NaN is not), a slot has no line.
            let short = dot.abs().cmplt(reach * per_diameter).bitmask();
            let mut left = !short & lanes;
            if let (Some(window), true) = (&window, left != 0) {
                left &= window.may_hold(&table.lane_optics[b], dot.abs());
            }
            let dots = dot.to_array();
            while left != 0 {
                let l = left.trailing_zeros() as usize;
                left &= left - 1;
                let normal = Vec3::new(n.x[l], n.y[l], n.z[l]);
                let slot = 4 * b + l;
                self.push_line(
                    &table.optics[slot],
                    slot as u16,
                    normal,
                    dots[l],
                    &lines,
                    out,
                );
            }
        }
    }

    /// The line of one slot of normal `normal` met at `dot = normal · dir`, pushed onto `out`
    /// if it falls in the range (and its window holds `args.wavelength_nm`, if given).
    #[inline(always)]
    fn push_line(
        &self,
        optics: &SlotOptics,
        slot: u16,
        normal: Vec3,
        dot: f32,
        args: &LineArgs,
        out: &mut Vec<ActiveLine>,
    ) {
        let (range_lo, range_hi) = self.range_nm;
        let c = f64::from(dot.abs());
        // 2 d n̄: the line's centre face-on at the d line's index. Past the range's long end
        // the dispersion moves a centre by under 4 %: beyond 1.1 × that end, no line.
        let normal_center_nm = args.two_n * optics.spacing_over_diameter;
        if normal_center_nm * c > 1.1 * range_hi {
            return;
        }
        let spacing_nm = optics.spacing_over_diameter * args.diameter_nm;
        let layers = (args.chord_nm * c / spacing_nm)
            .min(optics.layer_cap)
            .max(1.0);
        if let Some(x_w) = args.constant_wavelength_nm {
            // With the dispersion, first the window at the constant index, widened by
            // WINDOW_SLACK, about the wavelength's constant-index centre: a line whose window
            // holds the wavelength passes.
            let (g, n) = (WINDOW_SLACK * optics.coupling, layers / WINDOW_SLACK);
            if !BraggLine::window_may_hold(g, normal_center_nm, c, n, x_w) {
                return;
            }
        }
        // With the dispersion, the coupling and the centre at the line's own wavelength, and
        // the layers scaled by the group ratio k (`optics::dispersion`).
        let (coupling, normal_center_nm, group) =
            self.families
                .index
                .line_args(optics.coupling, normal_center_nm, c);
        let center = normal_center_nm * c;
        if center < LINE_REACH * range_lo || center > 1.05 * range_hi {
            return;
        }
        let layers = layers * group;
        if let Some(w) = args.wavelength_nm {
            if !BraggLine::window_may_hold(coupling, normal_center_nm, c, layers, w) {
                return;
            }
        }
        let line = BraggLine::new(coupling, normal_center_nm, c, layers);
        let (lo, hi) = line.window_nm();
        if hi < range_lo || lo > range_hi {
            return;
        }
        if let Some(w) = args.wavelength_nm {
            if w <= lo || w >= hi {
                return;
            }
        }
        out.push(ActiveLine {
            normal: if dot > 0.0 { -normal } else { normal },
            kind: optics.kind,
            slot,
            line,
        });
    }
}

/// A wavelength that [`Stone::lines_at_wavelength`] keeps the lines of (whose window holds
/// it), made by [`Stone::line_wavelength`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LineWavelength {
    /// The wavelength, nm.
    wavelength_nm: f64,
    /// With the dispersion, its centre at the constant index
    /// ([`crate::optics::CrystalIndex::constant_centre_nm`]).
    constant_wavelength_nm: Option<f64>,
}

/// [`BraggLine::window_may_hold`] for four slots at once in `f32`, made looser by
/// [`WindowTest::MARGIN`] and [`WindowTest::SLACK_NM`] than the `f64` tests of
/// [`Stone::push_line`] it stands for (the constant-index window widened by [`WINDOW_SLACK`]
/// with the dispersion, the line's own window without it), so that it turns away only slots
/// those turn away: most of the slots left after the reach, before any is built.
struct WindowTest {
    /// The wavelength the window must hold (with the dispersion, its constant-index centre).
    x_nm: Vec4,
    /// `2 n̄ D`, nm.
    two_n: Vec4,
    /// The chord over `D`.
    chord_over_diameter: Vec4,
    /// What the coupling is multiplied by and the layers divided by in the test.
    slack: f32,
}

impl WindowTest {
    /// Relative margin on the bounds: far above the `f32` roundings of either side (~10⁻⁶).
    const MARGIN: f32 = 1e-3;
    /// What the distance to the centre is taken short by, nm: above its `f32` rounding at the
    /// range's wavelengths (~10⁻⁴ nm).
    const SLACK_NM: f32 = 1e-2;

    fn new(at: LineWavelength, args: &LineArgs, diameter_nm: f32) -> Self {
        let (x, slack) = match at.constant_wavelength_nm {
            Some(x) => (x, WINDOW_SLACK as f32),
            None => (at.wavelength_nm, 1.0),
        };
        WindowTest {
            x_nm: Vec4::splat(x as f32),
            two_n: Vec4::splat(args.two_n as f32),
            chord_over_diameter: Vec4::splat((args.chord_nm / f64::from(diameter_nm)) as f32),
            slack,
        }
    }

    /// The lanes whose window may hold the wavelength, for slots of `(d / D, g, layer cap)`
    /// `optics` met at `|cos θ|` `cos`.
    #[inline(always)]
    fn may_hold(&self, [spacing, coupling, cap]: &[Vec4; 3], cos: Vec4) -> u32 {
        let c = cos.clamp(Vec4::splat(1e-3), Vec4::ONE);
        let center = self.two_n * *spacing * c;
        let off = (self.x_nm - center).abs() - Vec4::splat(Self::SLACK_NM);
        let layers = (self.chord_over_diameter * c / *spacing)
            .min(*cap)
            .max(Vec4::ONE)
            / self.slack;
        let reach = center * (1.0 + Self::MARGIN);
        let beyond_band = (off * c * c).cmpge(20.0 * self.slack * *coupling * reach);
        let beyond_lobes = (off * layers.max(Vec4::ONE)).cmpge(8.0 * reach);
        !(beyond_band & beyond_lobes).bitmask()
    }
}

/// What every slot's line of one crossing shares.
struct LineArgs {
    /// The domain's sphere diameter, nm.
    diameter_nm: f64,
    /// `2 n̄ D`, nm.
    two_n: f64,
    /// The chord's length, nm.
    chord_nm: f64,
    /// The wavelength the windows must hold, if any.
    wavelength_nm: Option<f64>,
    /// With the dispersion, that wavelength's centre at the constant index
    /// ([`crate::optics::CrystalIndex::constant_centre_nm`]).
    constant_wavelength_nm: Option<f64>,
}

#[cfg(test)]
mod tests;
