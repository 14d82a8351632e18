//! A pixel's reflections followed out once, as multisample anti-aliasing shades once per
//! pixel and primitive: every ray through a pixel at an edge finds its own domains, lines,
//! notches and body (what resolves the edge), and a line's reflection that the pixel's centre
//! ray (or an earlier ray of the pixel) followed out of the stone ([`Tracer::reflected`]: the
//! cull and the walk out, about half of a ray's time) is read back instead of walked again.
//! Within a pixel the reflected ray's way out moves by under a pixel's footprint and its
//! direction by under a pixel's angle (the same planes); what it sees, the lights through a
//! lobe of a degree or more, is smooth over that. What it does not carry over is the
//! variation of the notches on the way out within the pixel (`BENCHMARKS.md`: the image
//! against 16 rays an edge pixel).

/// One reflection followed out: the eye ray's segment (surface events before it), the
/// domain, the planes' slot, and what the way out saw.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Followed {
    domain: u32,
    seen: f32,
    slot: u16,
    segment: u8,
}

/// The reflections a pixel's rays have followed so far, read and added to while `on`.
#[derive(Default)]
pub(crate) struct Reuse {
    on: bool,
    followed: Vec<Followed>,
}

impl Reuse {
    /// Start a pixel: forget every reflection, and keep the new ones (`on`) or not.
    pub(crate) fn start(&mut self, on: bool) {
        self.on = on;
        self.followed.clear();
    }

    /// Start a pixel from the reflections its centre ray followed.
    pub(crate) fn start_from(&mut self, followed: &[Followed]) {
        self.on = true;
        self.followed.clear();
        self.followed.extend_from_slice(followed);
    }

    /// The reflections followed since the pixel started.
    pub(crate) fn followed(&self) -> &[Followed] {
        &self.followed
    }

    /// What the reflection off `domain`'s planes in `slot` on the eye ray's `segment` saw,
    /// if a ray of this pixel followed it.
    pub(super) fn find(&self, segment: u8, domain: u32, slot: u16) -> Option<f32> {
        if !self.on {
            return None;
        }
        self.followed
            .iter()
            .find(|f| f.segment == segment && f.domain == domain && f.slot == slot)
            .map(|f| f.seen)
    }

    /// Keep what a reflection saw, while on.
    pub(super) fn keep(&mut self, segment: u8, domain: u32, slot: u16, seen: f32) {
        if self.on {
            self.followed.push(Followed {
                domain,
                seen,
                slot,
                segment,
            });
        }
    }
}
