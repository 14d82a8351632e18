//! A path's crossing of a domain: the light estimated there, the reflections drawn or all
//! followed as branches, and the lines the path carries on through (the module outline in
//! [`super`]).

use glam::Vec3;

use super::sampler::PathSampler;
use super::spectral::{PathSpectrum, MAX_DRAWS};
use super::vertex::{AfterBranch, Branched, Vertex};
use super::{CameraSample, Estimate, Tracer, EPSILON_MM, MIN_FOLLOW};
use crate::geometry::{reflect, refract, Ray};
use crate::optics::BraggLine;
use crate::scatter::{Mosaic, Scatter};
use crate::stone::{ActiveLine, Boundary, Hint, Region};

use super::shares::{line_shares, Reflectances, MAX_LINES_PER_CROSSING};
/// Most probability of a reflection branch at a domain crossing after the first segment.
const MAX_BRANCH_PROBABILITY: f64 = 0.25;
/// Most probability with which an already reflected path reflects at a crossing (the rest
/// goes on through, its weight over 1 − p).
const MAX_CHOICE_PROBABILITY: f64 = 0.95;

/// A domain met by a path's segment `ray`: the domain from `t0` (mm along the ray) over
/// `chord` (mm, up to the segment's next event), the cells holding its start.
pub(super) struct DomainSpan<'r> {
    pub ray: &'r Ray,
    pub t0: f32,
    pub chord: f32,
    pub domain: u32,
    pub cells: Hint,
}

/// A reflection at a domain crossing: the ray along `dir` meets `domain`'s face at `face`
/// (light was estimated at `x`, just inside), in the cells `cells`; the branch's weight, and
/// its probability where the area light was also estimated there (`None`: the branch's escape
/// is the only way there); the event its path goes on at.
#[derive(Clone, Copy)]
struct Reflection {
    face: Vec3,
    x: Vec3,
    dir: Vec3,
    domain: u32,
    cells: Hint,
    p_pick: Option<f64>,
    weight: f32,
    level: u32,
    scatterings: u32,
}

/// What a domain crossing leaves of the path that met it.
pub(super) enum Crossing {
    /// It goes on through, its weight times this.
    On(f32),
    /// It ends.
    Ended,
    /// It was reflected (a path already reflected reflects instead of going on): it goes on
    /// as this path.
    Reflected(Box<Vertex>),
    /// A reflection branched off: followed first, then the crossing's rest.
    Branched(Box<Branched>),
}

/// A crossing whose reflections are being followed as branches.
pub(super) struct OpenCrossing {
    /// The domain's lines met.
    here: Vec<ActiveLine>,
    /// A reflected path's reflectances by them, where it has them.
    at_path: Option<Box<Reflectances>>,
    /// Every line's reflection (a crossing that follows them all).
    reflection: Reflection,
    /// The next line whose reflection is followed; `here.len()` when none is left.
    next_line: usize,
    /// The ray goes on through, its weight times this (`None`: it does not).
    goes_on: Option<f32>,
}

/// How a crossing's reflection is drawn: each line's share (of white light, or of a path
/// already reflected its own light), their sum, and the probability of a reflection.
struct Shares<'e> {
    energy: &'e [f64],
    total: f64,
    p_branch: f64,
    /// Whether the path chooses between its reflection and going on (a path already
    /// reflected) rather than branching.
    chooses: bool,
}

impl Tracer<'_> {
    /// A domain crossing `at` of the path `v`: light estimation, the reflection branches
    /// (every one if `v.split`), and the lines the ray carries on through (added to
    /// `v.lines`). Returns what goes on: the ray through, its weight scaled; or, for a path
    /// already reflected, which either reflects or goes on (see [`Tracer::draw_reflection`]),
    /// its reflection; or nothing; or a branch to follow before the rest of the crossing.
    pub(super) fn cross_domain(
        &mut self,
        at: &DomainSpan,
        v: &mut Vertex,
        s: &mut CameraSample,
    ) -> Crossing {
        let DomainSpan {
            ray,
            t0,
            chord,
            domain,
            cells,
        } = *at;
        self.nee_hint = cells;
        let dir = ray.direction;
        self.lines.clear();
        self.stone.lines(domain, dir, chord, &mut self.lines);
        if self.lines.is_empty() {
            return Crossing::On(1.0);
        }
        let x = ray.at(t0 + EPSILON_MM);
        let estimate = Estimate {
            x,
            path: &v.lines,
            weight: v.weight,
        };
        self.light_at_domain(&estimate, dir, domain, s);
        // The branches below refill `self.lines`: this crossing keeps its own.
        let here = std::mem::take(&mut self.lines);
        let reflected = v.lines.reflects();
        let mut energy = [0.0f64; MAX_LINES_PER_CROSSING];
        // A reflected path's reflectances here, at its wavelengths: for its choice, and for
        // its pass on through (the table zeroed only for such a path).
        let mut at_path = reflected.then_some([[[0.0f32; 2]; MAX_DRAWS]; MAX_LINES_PER_CROSSING]);
        line_shares(&here, &v.lines, &mut energy, &mut at_path);
        let energy = &energy[..here.len().min(MAX_LINES_PER_CROSSING)];
        let total: f64 = energy.iter().sum();
        let chooses = !v.split && reflected;
        let p_branch = if chooses {
            total.min(MAX_CHOICE_PROBABILITY)
        } else {
            (2.0 * total).min(MAX_BRANCH_PROBABILITY)
        };
        let shares = Shares {
            energy,
            total,
            p_branch,
            chooses,
        };
        self.area_at_crossing(&estimate, at, &here, &shares, v.split, s);
        let mut open = OpenCrossing::new(here, at, x, v);
        // Every reflection as a branch of its own, or one drawn.
        let next = if v.split {
            self.next_branch(&mut open, &v.lines, s.draws)
        } else {
            self.draw_reflection(&mut open, &shares, &v.lines, s.draws)
        };
        match next {
            Some(child) if !chooses => {
                open.at_path = at_path.map(Box::new);
                Crossing::Branched(Box::new(Branched {
                    child,
                    after: AfterBranch::new(open),
                }))
            }
            reflected_to => self.close_crossing(open, at_path.as_ref(), reflected_to, &mut v.lines),
        }
    }

    /// The area light's estimate at the crossing `at` (the point and path of `estimate`) of
    /// the lines `here`, balanced against each line's branch: drawn by `shares`, or every one
    /// followed if `split`.
    fn area_at_crossing(
        &mut self,
        estimate: &Estimate,
        at: &DomainSpan,
        here: &[ActiveLine],
        shares: &Shares,
        split: bool,
        s: &mut CameraSample,
    ) {
        // A path already reflected chooses ([`Tracer::draw_reflection`]); it finds the area
        // light by its branches' escapes alone: estimated at its every crossing, with the
        // weight its choices give it, the estimate would add more noise than it takes away
        // (twice the variance, measured).
        if shares.chooses || self.estimated_area_light().is_none() {
            return;
        }
        // Each line's probability of its branch, for the balance against the area light.
        let mut pick = [1.0f64; MAX_LINES_PER_CROSSING];
        if !split {
            for (p, e) in pick.iter_mut().zip(shares.energy) {
                *p = shares.p_branch * e / shares.total;
            }
        }
        let n = shares.energy.len();
        let dir = at.ray.direction;
        self.area_at_domain(estimate, dir, at.domain, &here[..n], &pick[..n], s);
    }

    /// Unless split, one reflection, drawn with twice the lines' share of white light (at
    /// most ¼), as a branch: its weight is about 1/(2 × its share), never large against what
    /// its line passes. A path already reflected chooses with each line's share of its own
    /// light, what the line reflects at the wavelengths it carries (exact: the branches'
    /// weights are then about 1 at each wavelength; the floor keeps every branch possible):
    /// it reflects, or goes on through with its weight over 1 − p. Forking it too would make
    /// a tree: its light lies in its line, alike plates reflect that line again at about
    /// p = ¼ each, and a fork per plate over many plates and events grows without bound. One
    /// path on, its cost grows with depth only linearly. Returns the branch, or the path a
    /// path that chooses goes on as.
    fn draw_reflection(
        &mut self,
        open: &mut OpenCrossing,
        shares: &Shares,
        lines: &PathSpectrum,
        draws: &mut PathSampler,
    ) -> Option<Vertex> {
        let Shares {
            energy,
            total,
            p_branch,
            chooses,
        } = *shares;
        let reflects = draws.uniform() < p_branch;
        if chooses {
            open.goes_on = (!reflects).then_some((1.0 / (1.0 - p_branch)) as f32);
        }
        if !reflects {
            return None;
        }
        let mut u = draws.uniform() * total;
        let mut pick = open.here.len() - 1;
        for (i, e) in energy.iter().enumerate() {
            if u < *e {
                pick = i;
                break;
            }
            u -= e;
        }
        let p_pick = p_branch * energy[pick] / total;
        let path = Reflection {
            p_pick: (!chooses).then_some(p_pick),
            weight: open.reflection.weight / p_pick as f32,
            ..open.reflection
        };
        let line = open.here[pick];
        if chooses {
            self.reflected_path(&path, &line, lines, draws)
        } else {
            self.branch(&path, &line, false, lines, draws)
        }
    }

    /// The next of an open crossing's reflections to follow as a branch (each followed with
    /// the probability [`Tracer::follow_probability`] gives it); `None` when none is left.
    pub(super) fn next_branch(
        &mut self,
        open: &mut OpenCrossing,
        lines: &PathSpectrum,
        draws: &mut PathSampler,
    ) -> Option<Vertex> {
        while let Some(&line) = open.here.get(open.next_line) {
            open.next_line += 1;
            let path = open.reflection;
            if let Some(child) = self.branch(&path, &line, true, lines, draws) {
                return Some(child);
            }
        }
        None
    }

    /// The end of a crossing `open` of a path of spectrum `lines`, its reflections followed:
    /// the ray goes on through the planes, carrying 1 − R of each line (a reflected path's
    /// own reflectances `at_path`); or it goes on as `reflected_to`; or it ends.
    pub(super) fn close_crossing(
        &mut self,
        open: OpenCrossing,
        at_path: Option<&Reflectances>,
        reflected_to: Option<Vertex>,
        lines: &mut PathSpectrum,
    ) -> Crossing {
        if open.goes_on.is_some() {
            for (i, l) in open.here.iter().enumerate() {
                let axis = self.plane(open.reflection.dir, l.normal);
                match at_path.and_then(|r| r.get(i)) {
                    Some(r) => lines.pass(r, axis),
                    None => lines.transmit_in(l.line, self.setup.spectral, axis),
                }
            }
        }
        self.lines = open.here;
        match (open.goes_on, reflected_to) {
            (Some(scale), _) => Crossing::On(scale),
            (None, Some(next)) => Crossing::Reflected(Box::new(next)),
            (None, None) => Crossing::Ended,
        }
    }

    /// [`Tracer::close_crossing`] of a crossing that branched, its branches all followed.
    pub(super) fn close_open_crossing(
        &mut self,
        mut open: OpenCrossing,
        lines: &mut PathSpectrum,
    ) -> Crossing {
        let at_path = open.at_path.take();
        self.close_crossing(open, at_path.as_deref(), None, lines)
    }

    /// The reflection `path` by `line` as a path of its own; if `cull`, followed with the
    /// probability [`Tracer::follow_probability`] gives it (its weight over that).
    fn branch(
        &mut self,
        path: &Reflection,
        line: &ActiveLine,
        cull: bool,
        lines: &PathSpectrum,
        draws: &mut PathSampler,
    ) -> Option<Vertex> {
        let mut child = self.reflected_path(path, line, lines, draws)?;
        if cull {
            // Russian roulette on what the branch's first escape will see.
            let p = self.follow_probability(path.face, child.dir);
            if p < 1.0 {
                if draws.uniform_f32() >= p {
                    return None;
                }
                child.weight /= p;
            }
        }
        Some(child)
    }

    /// The path that the reflection `path` by `line` of a path of spectrum `lines` starts: the
    /// lobe's normal drawn ([`Tracer::reflection`]); `None` where it faces away or the path's
    /// light is all gone.
    fn reflected_path(
        &mut self,
        path: &Reflection,
        line: &ActiveLine,
        lines: &PathSpectrum,
        draws: &mut PathSampler,
    ) -> Option<Vertex> {
        let (d, l, axis) = self.reflection(path.domain, line, path.dir, draws)?;
        let branch = lines.reflected(l, self.setup.spectral, draws.uniform(), axis);
        if branch.is_dark() {
            return None;
        }
        Some(Vertex {
            pos: path.face,
            dir: d,
            weight: path.weight,
            lines: branch,
            skip: Some(path.domain),
            region: Region::Opal,
            drawn: path
                .p_pick
                .and_then(|p| self.drawn_branch(path.x, path.dir, d, line, p)),
            hint: path.cells,
            split: false,
            splits_scattering: false,
            first_in_cap: false,
            level: path.level,
            scatterings: path.scatterings,
            walking: false,
        })
    }

    /// The probability with which a reflection of the camera ray's first segment, leaving
    /// `from` along `dir`, is followed: what the room shows where it first meets the surface
    /// and refracts out, over [`super::FOLLOW_FROM`] of the room's brightest, at least
    /// [`MIN_FOLLOW`]; 1 where it meets an area light, is reflected whole (beyond the
    /// critical angle) or meets anything but the surface first. Most reflections look into
    /// the dark room; the bright ones, which hold the picture's colour, are all followed.
    pub(super) fn follow_probability(&self, from: Vec3, dir: Vec3) -> f32 {
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
    /// mirrored direction, the line at the half-vector angle and the s axis of the plane of
    /// incidence; `None` if the drawn normal faces away.
    fn reflection(
        &self,
        domain: u32,
        line: &ActiveLine,
        dir: Vec3,
        draws: &mut PathSampler,
    ) -> Option<(Vec3, BraggLine, Vec3)> {
        let sigma = self.stone.lobe_sigma(line.kind, -dir.dot(line.normal));
        let h = Mosaic {
            normal: line.normal,
            sigma,
        }
        .sample(draws);
        let cos_h = -dir.dot(h);
        (cos_h > 0.0).then(|| {
            let l = self.line_at(domain, line, cos_h);
            (reflect(dir, h), l, self.plane(dir, h))
        })
    }
}

impl OpenCrossing {
    /// The crossing `at` of the lines `here` by the path `v`, light estimated at `x`, before
    /// its reflections: the ray goes on through unless it chooses otherwise.
    fn new(here: Vec<ActiveLine>, at: &DomainSpan, x: Vec3, v: &Vertex) -> Self {
        OpenCrossing {
            next_line: if v.split { 0 } else { here.len() },
            here,
            at_path: None,
            reflection: Reflection {
                face: at.ray.at(at.t0),
                x,
                dir: at.ray.direction,
                domain: at.domain,
                cells: at.cells,
                p_pick: Some(1.0),
                weight: v.weight,
                level: v.level + 1,
                scatterings: v.scatterings,
            },
            goes_on: Some(1.0),
        }
    }
}

impl AfterBranch {
    /// What a path goes on with after the branch of its crossing `crossing`: the rest of the
    /// crossing, then (filled by the walk) its other spans.
    fn new(crossing: OpenCrossing) -> Self {
        AfterBranch {
            crossing,
            scatter_at: None,
            rest: Vec::new(),
            end_hint: Hint::default(),
        }
    }
}
