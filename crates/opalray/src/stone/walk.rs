//! What a ray segment meets inside the stone: its spans, each in one domain or in potch, in
//! order ([`Stone::walk`]), the layout's own walk (balls, grains, ragged outlines) split at the
//! colour bar's inner surface and adjacent spans of one domain merged.

use glam::Vec3;

use super::{Layout, Stone};
use crate::geometry::Ray;

/// A piece of a ray inside the stone: `[t0, t1]` along it, in one domain (or potch: `None`).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Span {
    /// Start, mm along the ray.
    pub t0: f32,
    /// End, mm along the ray.
    pub t1: f32,
    /// The domain, or `None` in potch.
    pub domain: Option<u32>,
    /// The cells holding its start: a walk starting there tries them first.
    pub hint: Hint,
}

/// Cells of the grains that likely hold a point, tried first by a walk starting there
/// ([`Stone::walk`]): the column of the ragged outlines and the grain (in that column's shift).
/// A walk finds the same spans with any hint or none, but where a hinted grain claims a sliver
/// beyond a face its rays missed (as a walk from grain to grain does,
/// [`Grains::at_with`](super::grains::Grains::at_with)).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Hint {
    /// The outlines' column.
    pub column: Option<u32>,
    /// The grain.
    pub grain: Option<u32>,
}

impl Stone {
    /// Call `visit` for the spans of `[t0, t1]` along `origin + t·dir` (mm; `dir` unit), in
    /// order, each in one domain or in potch, until it returns false (a path's event: the
    /// rest of the segment is not walked). The caller keeps the segment inside the stone.
    ///
    /// `hint` holds the cells of the start, if known (a walk's return value, where it ended,
    /// or a span's); it returns the cells of the end (of a walk that reached `t1`).
    pub fn walk(
        &self,
        origin: Vec3,
        dir: Vec3,
        t0: f32,
        t1: f32,
        hint: Hint,
        visit: &mut dyn FnMut(Span) -> bool,
    ) -> Hint {
        if self.domains.is_empty() {
            // Potch only.
            visit(Span {
                t0,
                t1,
                domain: None,
                hint: Hint::default(),
            });
            return Hint::default();
        }
        let Some(inner) = &self.bar_inner else {
            return self.walk_domains(origin, dir, t0, t1, hint, visit);
        };
        // Under the colour bar the domains are potch: split the spans at the inner surface.
        let ray = Ray {
            origin: origin - self.bar_centre,
            direction: dir,
        };
        let Some((a, b)) = inner.intersect(&ray).filter(|&(a, b)| b > t0 && a < t1) else {
            return self.walk_domains(origin, dir, t0, t1, hint, visit);
        };
        // Walk the domains only outside the inner surface: under it is one span of potch.
        let (a, b) = (a.max(t0), b.min(t1));
        let mut merged = Merge::default();
        if a > t0 {
            self.walk_domains(origin, dir, t0, a, hint, &mut |span| {
                merged.push(span, visit)
            });
        }
        let under = Span {
            t0: a,
            t1: b,
            domain: None,
            hint: Hint::default(),
        };
        // The hint is of the walk that ends at `t1`.
        let mut end = Hint::default();
        if merged.push(under, visit) && t1 > b {
            end = self.walk_domains(origin, dir, b, t1, Hint::default(), &mut |span| {
                merged.push(span, visit)
            });
        }
        merged.finish(visit);
        end
    }

    /// [`Stone::walk`] without the colour bar.
    fn walk_domains(
        &self,
        origin: Vec3,
        dir: Vec3,
        t0: f32,
        t1: f32,
        hint: Hint,
        visit: &mut dyn FnMut(Span) -> bool,
    ) -> Hint {
        match &self.layout {
            Layout::Single => {
                visit(Span {
                    t0,
                    t1,
                    domain: Some(0),
                    hint: Hint::default(),
                });
                Hint::default()
            }
            Layout::Balls(b) => {
                b.walk(origin, dir, t0, t1, visit);
                Hint::default()
            }
            Layout::Grains {
                grains,
                domain_of,
                outlines,
            } => {
                let mut merged = Merge::default();
                let mut last = hint;
                // A span of a domain starts in its first grain's cells.
                let mut merge = |span: Span, grain: u32| {
                    last = span.hint;
                    let domain = domain_of[grain as usize];
                    merged.push(Span { domain, ..span }, visit)
                };
                match outlines {
                    Some(o) => {
                        let ray = Ray {
                            origin,
                            direction: dir,
                        };
                        o.walk(grains, &ray, t0, t1, hint, &mut merge)
                    }
                    None => grains.walk(origin, dir, t0, t1, hint.grain, &mut merge),
                };
                merged.finish(visit);
                last
            }
        }
    }
}

/// Adjacent spans of one domain merged into one before they are visited; once `visit` has
/// said stop, nothing more is visited.
#[derive(Default)]
pub(super) struct Merge {
    pending: Option<Span>,
    stopped: bool,
}

impl Merge {
    /// Take the next span in order; false once the walk should stop.
    pub(super) fn push(&mut self, span: Span, visit: &mut dyn FnMut(Span) -> bool) -> bool {
        if self.stopped {
            return false;
        }
        match self.pending.as_mut() {
            Some(p) if p.domain == span.domain => p.t1 = span.t1,
            _ => {
                if let Some(p) = self.pending.replace(span) {
                    self.stopped = !visit(p);
                }
            }
        }
        !self.stopped
    }

    /// Visit the last span, unless the walk was stopped.
    pub(super) fn finish(self, visit: &mut dyn FnMut(Span) -> bool) {
        if let (Some(p), false) = (self.pending, self.stopped) {
            visit(p);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_walk_told_to_stop_visits_what_a_full_walk_visits_first_and_no_more() {
        // The default stone: a colour bar of ragged plates over potch, so spans are merged
        // from columns and grains and split at the bar's inner surface.
        let stone = Stone::new(&crate::scene::preset("black-opal").unwrap()).unwrap();
        let origin = Vec3::new(-3.0, 1.0, 3.9);
        let dir = Vec3::new(0.3, -0.1, -1.0).normalize();
        let Some((_, t1)) = stone.shape.intersect(&Ray {
            origin: origin - dir * 10.0,
            direction: dir,
        }) else {
            panic!("the ray misses the stone")
        };
        let t1 = t1 - 10.0;
        let mut full = Vec::new();
        stone.walk(origin, dir, 0.0, t1, Hint::default(), &mut |s| {
            full.push(s);
            true
        });
        assert!(full.len() > 5, "{} spans", full.len());
        assert!(full.iter().any(|s| s.domain.is_none()), "no potch met");
        for k in 1..=full.len() {
            let mut seen = Vec::new();
            stone.walk(origin, dir, 0.0, t1, Hint::default(), &mut |s| {
                seen.push(s);
                seen.len() < k
            });
            assert_eq!(seen, full[..k], "stopped after {k}");
        }
    }
}
