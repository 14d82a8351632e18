//! The path tracer's loop inside the stone: a path's state between events ([`Vertex`]), its
//! segment walked through the domains to the first event, and that event (a potch
//! scattering, the surface, a backing, a triplet's cap plane: [`super::events`]; a domain
//! crossing met on the way: [`super::crossing`]).
//!
//! A branch (a reflection at a crossing followed apart from the path that found it, or one of
//! the camera path's first scattering's directions) is followed at once, to its end, before
//! its parent goes on: the parent waits on a small stack ([`Tracer::inside`]), with where its
//! walk, its crossing or its scattering stood and where its draws stood, so that the draws and
//! the sums come in the order of a depth-first recursion. A walk that waits keeps the spans
//! past the crossing (the walk is a function of the segment alone) and goes on over them.

use glam::Vec3;

use super::area::Drawn;
use super::crossing::{Crossing, DomainSpan, OpenCrossing};
use super::events::Scattering;
use super::sampler::Mark;
use super::spectral::PathSpectrum;
use super::{CameraSample, Tracer};
use crate::geometry::Ray;
use crate::stone::{Boundary, Hint, Region, Span};

/// A path inside the stone at the start of its next event: the loop's state.
pub(super) struct Vertex {
    pub pos: Vec3,
    pub dir: Vec3,
    pub weight: f32,
    /// Its spectrum: the lines met so far.
    pub lines: PathSpectrum,
    /// The domain whose face reflected it (left through that face).
    pub skip: Option<u32>,
    pub region: Region,
    /// How its segment's direction was drawn, where light was also estimated there (the
    /// balance heuristic of its escape).
    pub drawn: Option<Drawn>,
    /// The cells likely to hold `pos` ([`crate::stone::Stone::walk`]).
    pub hint: Hint,
    /// Whether every reflection at the crossings of its segment is followed (the camera
    /// ray's first segment in the opal).
    pub split: bool,
    /// Whether its next scattering splits ([`super::scattering_split`]): the camera path's first.
    pub splits_scattering: bool,
    /// Whether it is in a triplet's cap on its way to the opal (its first segment in the
    /// opal still splits).
    pub first_in_cap: bool,
    /// Its event, counted from 0 (the sampler's event, [`super::sampler`]).
    pub level: u32,
    /// How many of its events were scatterings in the body or a domain's haze, and
    /// reflections at the surface of segments drawn at one: not counted against `max_depth`
    /// ([`Tracer::goes_deeper`]).
    pub scatterings: u32,
    /// Whether its segment was drawn at a scattering: a reflection at the surface that ends
    /// it is a step of the body's walk, counted with the scatterings.
    pub walking: bool,
}

/// The segment of a path from its vertex to the boundary of its region.
pub(super) struct Segment {
    pub ray: Ray,
    /// Where it meets the boundary, mm along the ray.
    pub t_end: f32,
    pub boundary: Boundary,
    /// The domain the path left through its face: not crossed at the segment's first span.
    pub skip_first: Option<u32>,
}

/// Where a segment's walk ended.
pub(super) enum Reached {
    /// The boundary of its region, the walk's cells there.
    Boundary(Hint),
    /// A scattering at `t` (the potch, or the haze of a milky domain), keeping `albedo`.
    Scattered { t: f32, albedo: f32, cells: Hint },
    /// A crossing ended the path.
    Ended,
    /// A crossing reflected it (a path already reflected): it goes on as this path.
    Reflected(Box<Vertex>),
    /// A crossing branched: the branch first, then the rest of the crossing and the walk.
    Branched(Box<Branched>),
}

/// A crossing that branched: the branch, and what its path goes on with after it.
pub(super) struct Branched {
    /// The branch to follow first.
    pub child: Vertex,
    pub after: AfterBranch,
}

/// What a path whose crossing branched goes on with once the branch is followed.
pub(super) struct AfterBranch {
    /// The crossing, its other branches not yet followed.
    pub crossing: OpenCrossing,
    /// Where a milky domain scatters the path after the crossing, and its cells.
    pub scatter_at: Option<(f32, Hint)>,
    /// The walk's spans past the crossing, in order (filled once the walk has found them).
    pub rest: Vec<Span>,
    /// The walk's cells at its end.
    pub end_hint: Hint,
}

/// What a span's visit leaves of the walk.
pub(super) enum SpanStep {
    /// It goes on to the next span.
    On,
    /// It ends there.
    Stop(Reached),
}

/// A path that waits while a branch of it is followed, and where it waits.
pub(super) struct Waiting {
    pub vertex: Vertex,
    pub at: WaitingAt,
}

/// Where a path waits on its branch. Its variants differ in size, but it lives boxed
/// ([`Step::Fork`]) and at most `max_depth + 1` wait at once.
#[allow(clippy::large_enum_variant)]
pub(super) enum WaitingAt {
    /// At a crossing of its segment: the crossing's other branches, then the walk's spans.
    Crossing {
        segment: Segment,
        after: AfterBranch,
    },
    /// At a scattering that goes on in several directions.
    Scattering(Scattering),
}

/// What the loop does next.
pub(super) enum Step {
    /// Go on with the current path's next event.
    Go,
    /// The current path is a branch of this one, which waits until the branch ends.
    Fork(Box<Waiting>),
    /// The current path ends: the last one waiting goes on.
    End,
}

impl Tracer<'_> {
    /// The path `start` inside the stone and every branch of it, depth first: one loop over
    /// the current path's events, the paths waiting on their branches on a stack (at most
    /// one per event level, so at most `max_depth`), each going on where its draws stood.
    pub(super) fn inside(&mut self, start: Vertex, s: &mut CameraSample) {
        let mut stack = std::mem::take(&mut self.waiting);
        // One waiting path per counted level, and the camera path's first scattering.
        let bound = self.setup.max_depth as usize + 1;
        let mut v = start;
        let mut step = Step::Go;
        loop {
            step = match step {
                Step::Go => self.event(&mut v, s),
                Step::Fork(parent) => {
                    debug_assert!(stack.len() < bound, "a branch beyond max_depth");
                    stack.push((parent, s.draws.mark()));
                    Step::Go
                }
                Step::End => match stack.pop() {
                    Some((parent, mark)) => {
                        let Waiting { vertex, at } = *parent;
                        v = vertex;
                        self.resume(&mut v, at, mark, s)
                    }
                    None => break,
                },
            };
        }
        self.waiting = stack;
    }

    /// Go on with the path `v` where it waited, its draws back at `mark`.
    fn resume(&mut self, v: &mut Vertex, at: WaitingAt, mark: Mark, s: &mut CameraSample) -> Step {
        s.draws.reset(mark);
        match at {
            WaitingAt::Crossing { segment, after } => self.resume_walk(v, segment, after, s),
            WaitingAt::Scattering(sc) => self.scatter_on(v, sc, s),
        }
    }

    /// The next event of `v`: its segment walked to the first event, then that event.
    fn event(&mut self, v: &mut Vertex, s: &mut CameraSample) -> Step {
        if !self.goes_deeper(v) {
            return Step::End;
        }
        s.draws.begin_event(v.level);
        let ray = Ray {
            origin: v.pos,
            direction: v.dir,
        };
        let Some((t_end, boundary)) = self.stone.exit(&ray, v.region) else {
            return Step::End;
        };
        let segment = Segment {
            ray,
            t_end,
            boundary,
            skip_first: v.skip.take(),
        };
        let reached = if v.region == Region::Opal {
            self.walk(v, &segment, s)
        } else {
            Reached::Boundary(Hint::default())
        };
        self.reached(v, segment, reached, s)
    }

    /// The segment's walk through the domains, each span visited as the walk finds it until
    /// an event. Past a crossing that branches, the walk's other spans are kept for the path
    /// to go on over once the branch is followed.
    fn walk(&mut self, v: &mut Vertex, segment: &Segment, s: &mut CameraSample) -> Reached {
        let stone = self.stone;
        let mut at_start = true;
        let mut stop = None;
        let mut branched: Option<Box<Branched>> = None;
        let mut rest = Vec::new();
        let end_hint = stone.walk(v.pos, v.dir, 0.0, segment.t_end, v.hint, &mut |span| {
            if branched.is_some() {
                rest.push(span);
                return true;
            }
            let first = std::mem::replace(&mut at_start, false);
            match self.visit_span(v, segment, span, first, s) {
                Ok(SpanStep::On) => true,
                Ok(SpanStep::Stop(reached)) => {
                    stop = Some(reached);
                    false
                }
                Err(b) => {
                    branched = Some(b);
                    true
                }
            }
        });
        if let Some(mut b) = branched {
            b.after.rest = rest;
            b.after.end_hint = end_hint;
            return Reached::Branched(b);
        }
        stop.unwrap_or(Reached::Boundary(end_hint))
    }

    /// One span of the segment (its first if `at_start`): a free flight in the potch or a
    /// milky domain's haze, and the domain's crossing. `Err`: the crossing branched.
    fn visit_span(
        &mut self,
        v: &mut Vertex,
        segment: &Segment,
        span: Span,
        at_start: bool,
        s: &mut CameraSample,
    ) -> Result<SpanStep, Box<Branched>> {
        let potch = self.stone.potch;
        let mut chord = span.t1 - span.t0;
        let Some(domain) = span.domain else {
            let flight = -(1.0 - s.draws.uniform_f32()).ln() / potch.extinction_per_mm;
            if flight < chord {
                return Ok(SpanStep::Stop(Reached::Scattered {
                    t: span.t0 + flight,
                    albedo: potch.albedo,
                    cells: span.hint,
                }));
            }
            return Ok(SpanStep::On);
        };
        // Milky domains scatter too (without absorbing).
        let mut scatter_at = None;
        if potch.domain_scattering_per_mm > 0.0 {
            let flight = -(1.0 - s.draws.uniform_f32()).ln() / potch.domain_scattering_per_mm;
            if flight < chord {
                chord = flight;
                scatter_at = Some((span.t0 + flight, span.hint));
            }
        }
        // A ray reflected at a domain's face leaves through that face.
        if at_start && segment.skip_first == Some(domain) {
            return Ok(scattered_after(scatter_at));
        }
        let at = DomainSpan {
            ray: &segment.ray,
            t0: span.t0,
            chord,
            domain,
            cells: span.hint,
        };
        let crossing = self.cross_domain(&at, v, s);
        crossed(v, crossing, scatter_at)
    }

    /// Where the walk ended: the event there, or the path it goes on as.
    fn reached(
        &mut self,
        v: &mut Vertex,
        segment: Segment,
        reached: Reached,
        s: &mut CameraSample,
    ) -> Step {
        match reached {
            Reached::Boundary(hint) => {
                v.hint = hint;
                match segment.boundary {
                    Boundary::Surface => self.surface(v, &segment, s),
                    Boundary::Back => self.backing(v, &segment, s),
                    Boundary::CapPlane => self.cap_plane(v, &segment, s),
                }
            }
            Reached::Scattered { t, albedo, cells } => {
                v.hint = cells;
                self.scatter(v, &segment.ray, t, albedo, s)
            }
            Reached::Ended => Step::End,
            Reached::Reflected(next) => {
                *v = *next;
                Step::Go
            }
            Reached::Branched(b) => {
                let Branched { child, after } = *b;
                Step::Fork(Box::new(Waiting {
                    vertex: std::mem::replace(v, child),
                    at: WaitingAt::Crossing { segment, after },
                }))
            }
        }
    }

    /// A path waiting at a crossing goes on: the crossing's next branch, or the crossing's
    /// end and the walk's spans past it.
    fn resume_walk(
        &mut self,
        v: &mut Vertex,
        segment: Segment,
        mut after: AfterBranch,
        s: &mut CameraSample,
    ) -> Step {
        if let Some(child) = self.next_branch(&mut after.crossing, &v.lines, s.draws) {
            return Step::Fork(Box::new(Waiting {
                vertex: std::mem::replace(v, child),
                at: WaitingAt::Crossing { segment, after },
            }));
        }
        let on = self.close_open_crossing(after.crossing, &mut v.lines);
        let mut step = crossed(v, on, after.scatter_at);
        let mut rest = after.rest.into_iter();
        while let Ok(SpanStep::On) = step {
            let Some(span) = rest.next() else {
                let reached = Reached::Boundary(after.end_hint);
                return self.reached(v, segment, reached, s);
            };
            step = self.visit_span(v, &segment, span, false, s);
        }
        let reached = match step {
            Ok(SpanStep::Stop(reached)) => reached,
            Ok(SpanStep::On) => unreachable!("the walk above goes on while it can"),
            Err(mut b) => {
                b.after.rest = rest.collect();
                b.after.end_hint = after.end_hint;
                Reached::Branched(b)
            }
        };
        self.reached(v, segment, reached, s)
    }
}

/// What a crossing leaves of the walk: its weight scaled and on (to a milky domain's
/// scattering `scatter_at` where there is one), ended, reflected, or branched.
fn crossed(
    v: &mut Vertex,
    crossing: Crossing,
    scatter_at: Option<(f32, Hint)>,
) -> Result<SpanStep, Box<Branched>> {
    match crossing {
        Crossing::On(scale) => v.weight *= scale,
        Crossing::Ended => return Ok(SpanStep::Stop(Reached::Ended)),
        Crossing::Reflected(next) => return Ok(SpanStep::Stop(Reached::Reflected(next))),
        Crossing::Branched(mut b) => {
            b.after.scatter_at = scatter_at;
            return Err(b);
        }
    }
    Ok(scattered_after(scatter_at))
}

/// The walk after a domain: on, or stopped at a milky domain's scattering.
fn scattered_after(scatter_at: Option<(f32, Hint)>) -> SpanStep {
    match scatter_at {
        Some((t, cells)) => SpanStep::Stop(Reached::Scattered {
            t,
            albedo: 1.0,
            cells,
        }),
        None => SpanStep::On,
    }
}
