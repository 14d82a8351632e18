//! A pixel's reflections followed out once, as multisample anti-aliasing shades once per
//! pixel and primitive: every further ray through a pixel at an edge finds its own domains,
//! lines, notches and body (what resolves the edge), and a line's reflection that the pixel's
//! centre ray, or an earlier further ray, followed out of the stone ([`Tracer::reflected`]: the
//! cull and the walk out, about half of a ray's time) is read back instead of walked again.
//! So is the light the body scatters once on that segment ([`Tracer::single`]'s quadrature),
//! found by the first of the pixel's rays that had potch to scatter it.
//!
//! On the eye ray's first segment, from the surface in, the reflected ray's way out moves by
//! under a pixel's footprint and turns by under a pixel's angle (the same planes), and what
//! it sees, the lights through a lobe of a degree or more, is smooth over that. After a
//! reflection off the curved dome a pixel's rays spread more (a reflection turns a ray by
//! twice its normal's turn), and their later segments are read back too, where the eye ray
//! goes the same way as the ray that walked it within 1° ([`SAME_WAY`]): the same domain's
//! planes met on the same segment, the same way. Rays of a pixel that took different surface
//! events at the rim, or left the dome's curve apart, walk their own. Against 16 rays walked
//! in full at an edge, the clear crystal's image reads 1.784 codes RMS (1.789 read back on
//! the first segment alone) for a fifth less time (`BENCHMARKS.md`, 2026-12-07, seventh
//! session). What is lost is the variation within the pixel of the notches on the way out
//! and, after the dome's reflections, of the reflection's direction.
//!
//! A reflection is the same where it is the same domain's planes (its slot) at the same
//! crossing of that domain along the same segment of the eye ray (a ragged or ball-shaped
//! domain can be crossed twice). What was walked depends on the ray's weight (the cull, the
//! second reflections taken): a value is read back only by a ray whose weights would have
//! walked no more — no more than the ray that walked it where the walk was culled or went
//! through the body alone, at most twice as much where it went through the domains (whose
//! second reflections under the cut then stay under twice the cut).

use glam::Vec3;

/// What the centre ray's walk may stand in for, relative to its own weights, where it went
/// through the domains.
const THOROUGH_REACH: f32 = 2.0;

/// The cosine of the largest angle between two rays' segments for one to read back the
/// other's reflections there (1°): rays of a pixel that left the dome's curve apart, or took
/// different surface events at the rim, walk their own.
const SAME_WAY: f32 = 0.999_85;

/// One reflection followed out: the domain, its crossing along the segment, the planes'
/// slot, the ray's weights that decided the walk, whether it went through the domains, and
/// what it saw.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Followed {
    domain: u32,
    segment: u8,
    /// The eye ray's direction on that segment.
    way: Vec3,
    seen: f32,
    luminance: f32,
    vivid: f32,
    slot: u16,
    crossing: u8,
    thorough: bool,
}

/// A reflection as a ray meets it: its key and the weights that decide its walk.
#[derive(Clone, Copy, Debug)]
pub(super) struct Meeting {
    pub segment: u8,
    /// The eye ray's direction on its segment.
    pub way: Vec3,
    pub domain: u32,
    pub crossing: u8,
    pub slot: u16,
    /// The eye ray's weight times the line's luminance.
    pub luminance: f32,
    /// The eye ray's weight times the line's largest tristimulus value.
    pub vivid: f32,
}

impl Followed {
    /// Whether it is the reflection `at` meets: the same segment, domain, crossing and
    /// planes, the eye ray on that segment going the same way within 1° ([`SAME_WAY`]).
    fn same(&self, at: &Meeting) -> bool {
        self.domain == at.domain
            && self.segment == at.segment
            && self.slot == at.slot
            && self.crossing == at.crossing
            && self.way.dot(at.way) >= SAME_WAY
    }
}

/// What a pixel's rays do with the reflections they follow.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub(crate) enum Mode {
    /// Nothing kept, nothing read back.
    #[default]
    Off,
    /// Every reflection followed is kept (the centre's ray).
    Record,
    /// Reflections are read back where they may be, and the others kept.
    Read,
}

/// The reflections a pixel's rays have followed so far.
#[derive(Default)]
pub(crate) struct Reuse {
    mode: Mode,
    followed: Vec<Followed>,
    /// The light the body scatters once at the median depth of a segment of the eye ray
    /// ([`super::single`]), by segment, as the first ray with potch there found it: smooth
    /// over a pixel, it is read back as the reflections are.
    single: Vec<Scattered>,
}

/// The body's single scattering found on a segment of the eye ray along `way`.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Scattered {
    segment: u8,
    way: Vec3,
    light: f32,
}

impl Reuse {
    /// Start a pixel: forget every reflection; `mode` says what its rays do.
    pub(crate) fn start(&mut self, mode: Mode) {
        self.mode = mode;
        self.followed.clear();
        self.single.clear();
    }

    /// Start a pixel's further rays from the reflections its centre ray followed and the
    /// body's single scattering it found on each segment.
    pub(crate) fn start_from(&mut self, followed: &[Followed], single: &[Scattered]) {
        self.mode = Mode::Read;
        self.followed.clear();
        self.followed.extend_from_slice(followed);
        self.single.clear();
        self.single.extend_from_slice(single);
    }

    /// The reflections followed since the pixel started.
    pub(crate) fn followed(&self) -> &[Followed] {
        &self.followed
    }

    /// The body's single scattering the pixel's rays found, by segment.
    pub(crate) fn single(&self) -> &[Scattered] {
        &self.single
    }

    /// The body's single scattering an earlier ray of the pixel found on `segment`, to read
    /// back.
    pub(super) fn find_single(&self, segment: u8, way: Vec3) -> Option<f32> {
        if self.mode != Mode::Read {
            return None;
        }
        self.single
            .iter()
            .find(|s| s.segment == segment && s.way.dot(way) >= SAME_WAY)
            .map(|s| s.light)
    }

    /// Keep the body's single scattering a ray found on `segment` along `way`, unless an
    /// earlier ray's is kept there.
    pub(super) fn keep_single(&mut self, segment: u8, way: Vec3, light: f32) {
        if self.mode != Mode::Off && self.single.iter().all(|s| s.segment != segment) {
            self.single.push(Scattered {
                segment,
                way,
                light,
            });
        }
    }

    /// Whether reflections are kept or read at all.
    pub(super) fn on(&self) -> bool {
        self.mode != Mode::Off
    }

    /// What the reflection `at` saw, if a ray of this pixel followed it with weights that
    /// stand in for `at`'s.
    pub(super) fn find(&self, at: &Meeting) -> Option<f32> {
        if self.mode != Mode::Read {
            return None;
        }
        let f = self.followed.iter().find(|f| f.same(at))?;
        let reach = if f.thorough { THOROUGH_REACH } else { 1.0 };
        (at.luminance <= reach * f.luminance && at.vivid <= reach * f.vivid).then_some(f.seen)
    }

    /// Keep what the reflection `at` saw (walked through the domains if `thorough`), in
    /// place of what another ray saw of it.
    pub(super) fn keep(&mut self, at: &Meeting, seen: f32, thorough: bool) {
        if self.mode == Mode::Off {
            return;
        }
        let new = Followed {
            domain: at.domain,
            segment: at.segment,
            way: at.way,
            seen,
            luminance: at.luminance,
            vivid: at.vivid,
            slot: at.slot,
            crossing: at.crossing,
            thorough,
        };
        match self.followed.iter_mut().find(|f| f.same(at)) {
            Some(f) => *f = new,
            None => self.followed.push(new),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn meeting(segment: u8, crossing: u8) -> Meeting {
        Meeting {
            segment,
            way: Vec3::NEG_Z,
            domain: 7,
            crossing,
            slot: 2,
            luminance: 0.5,
            vivid: 0.5,
        }
    }

    #[test]
    fn a_reflection_is_read_back_on_its_own_segment_alone() {
        let mut centre = Reuse::default();
        centre.start(Mode::Record);
        centre.keep(&meeting(1, 0), 0.25, true);
        centre.keep_single(1, Vec3::NEG_Z, 0.125);
        let mut further = Reuse::default();
        further.start_from(centre.followed(), centre.single());
        // The same domain's planes at the same crossing of the same segment, the eye ray
        // going the same way within 1°.
        assert_eq!(further.find(&meeting(1, 0)), Some(0.25));
        assert_eq!(further.find_single(1, Vec3::NEG_Z), Some(0.125));
        let near = Vec3::new(0.0, 0.9f32.to_radians().sin(), -1.0).normalize();
        assert_eq!(
            further.find(&Meeting {
                way: near,
                ..meeting(1, 0)
            }),
            Some(0.25)
        );
        assert_eq!(further.find_single(1, near), Some(0.125));
        // Another segment, another crossing, or a segment turned by more than 1°, is walked
        // again.
        assert_eq!(further.find(&meeting(0, 0)), None);
        assert_eq!(further.find(&meeting(2, 0)), None);
        assert_eq!(further.find(&meeting(1, 1)), None);
        assert_eq!(further.find_single(0, Vec3::NEG_Z), None);
        let turned = Vec3::new(0.0, 1.1f32.to_radians().sin(), -1.0).normalize();
        assert_eq!(
            further.find(&Meeting {
                way: turned,
                ..meeting(1, 0)
            }),
            None
        );
        assert_eq!(further.find_single(1, turned), None);
        // A brighter ray than the walk stood in for walks its own.
        let brighter = Meeting {
            luminance: 1.5,
            ..meeting(1, 0)
        };
        assert_eq!(further.find(&brighter), None);
        // The centre ray itself reads nothing back.
        assert_eq!(centre.find(&meeting(1, 0)), None);
    }
}
