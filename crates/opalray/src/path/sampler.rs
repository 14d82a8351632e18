//! The path integrator's random numbers: Owen-scrambled Sobol points (Burley 2020, "Practical
//! Hash-based Owen Scrambling", through `sobol_burley`) laid out by event, or independent
//! streams ([`Sampling`]).
//!
//! Sample `s` of pixel `p` is a pure function of `(seed, p, s)`, so the image is the same at
//! any thread count and however the passes fall. Under [`Sampling::Sobol`] it is point `s`
//! of the pixel's scrambled and shuffled sequence, its dimensions laid out in sets of four,
//! each set a Sobol sequence of its own seed (Burley's padding, §4):
//!
//! | dimensions | draws |
//! |---|---|
//! | 0, 1 (set 0) | the camera ray's place in the pixel, x then y |
//! | `4 + 8 e + k`, `k < 8` (sets `1 + 2e`, `2 + 2e`) | the `k`-th draw of event `e < SOBOL_EVENTS` |
//!
//! An event is one segment of the path and what ends it (the path's `Vertex::level`, `path/vertex.rs`): its
//! free flights, the estimates and choices at the domains it crosses, the draw of the next
//! direction, the roulette. Each draw takes the next slot of its event, so no two decisions
//! of one path read one dimension, and each event's first draws are the same dimensions in
//! every sample of the pixel (stratified over them). A branch (a reflection followed apart
//! from the path that found it) starts its next event at slot 0 as its parent's continuation
//! does: the two are separate terms of the sum, each with a dimension per decision. Draws past
//! slot 8 of an event, and every draw of events from `SOBOL_EVENTS` on, come from the
//! sample's independent stream `(seed, PATH, p · 2¹⁷ + s)`, which is all of the draws under
//! [`Sampling::Independent`] (the images of the PCG streams the Sobol points replaced).

use crate::sampling::{mix64, stage, Rng};
use crate::scatter::Draws;

/// Most samples per pixel a sequence holds (`sobol_burley`'s length).
pub const MAX_SAMPLES: u32 = 1 << 16;
/// Events whose first draws are Sobol dimensions; later events draw from the stream.
pub const SOBOL_EVENTS: u32 = 3;
/// Sobol dimensions of one event (two sets of four).
pub const EVENT_SLOTS: u32 = 8;
/// The first dimension of event 0 (set 1: set 0 holds the camera ray's two).
const FIRST_EVENT_DIMENSION: u32 = 4;
/// Bits of a stream index given to the sample number (`spp` ≤ 2¹⁶ < 2¹⁷).
const SAMPLE_BITS: u32 = 17;

/// Which points a render's samples are.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Sampling {
    /// Owen-scrambled Sobol points laid out by event (the module's table): less noise at
    /// the same samples per pixel.
    #[default]
    Sobol,
    /// An independent PCG stream per sample: the reference the Sobol points are tested
    /// against (`tests/sobol.rs`).
    Independent,
}

/// Where a path's draws stand: the event, and the next slot in it.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Mark {
    event: u32,
    slot: u32,
}

/// The draws of one sample of one pixel.
#[derive(Clone, Debug)]
pub struct PathSampler {
    /// Index of the sample in its pixel's sequence, `< MAX_SAMPLES`.
    sample: u32,
    /// The pixel's key, from the scene's seed and the pixel's index.
    key: u64,
    /// Whether the Sobol layout applies (else every draw is the stream's).
    sobol: bool,
    /// The camera ray's draws taken (0, 1 or 2).
    camera: u32,
    /// The event and slot of the next draw.
    at: Mark,
    /// The independent stream.
    stream: Rng,
}

impl Draws for PathSampler {
    fn uniform_f32(&mut self) -> f32 {
        PathSampler::uniform_f32(self)
    }

    fn uniform(&mut self) -> f64 {
        PathSampler::uniform(self)
    }
}

impl PathSampler {
    /// Sample `sample` (< [`MAX_SAMPLES`]) of pixel `pixel` under `seed`, its first draws
    /// the camera ray's.
    pub fn new(seed: u64, pixel: u64, sample: u32, sampling: Sampling) -> Self {
        debug_assert!(sample < MAX_SAMPLES);
        PathSampler {
            sample,
            key: mix64(seed ^ mix64(stage::PATH.wrapping_mul(0xA076_1D64_78BD_642F) ^ pixel)),
            sobol: sampling == Sampling::Sobol,
            camera: 0,
            at: Mark { event: 0, slot: 0 },
            stream: Rng::new(
                seed,
                stage::PATH,
                (pixel << SAMPLE_BITS) | u64::from(sample),
            ),
        }
    }

    /// Start event `event` of the path: its draws take its slots from the first.
    pub fn begin_event(&mut self, event: u32) {
        self.camera = 2;
        self.at = Mark { event, slot: 0 };
    }

    /// Where the draws stand, to go back to after a branch ([`PathSampler::reset`]).
    pub fn mark(&self) -> Mark {
        self.at
    }

    /// Go back to `mark`: the path that made the branch goes on with its own next slot.
    pub fn reset(&mut self, mark: Mark) {
        self.at = mark;
    }

    /// The Sobol dimension of the next draw, `None` where the stream draws; advances.
    fn next_dimension(&mut self) -> Option<u32> {
        if self.camera < 2 {
            self.camera += 1;
            return Some(self.camera - 1);
        }
        let Mark { event, slot } = self.at;
        self.at.slot = slot.saturating_add(1);
        (event < SOBOL_EVENTS && slot < EVENT_SLOTS)
            .then(|| FIRST_EVENT_DIMENSION + event * EVENT_SLOTS + slot)
    }

    /// The next draw, uniform in [0, 1) (24 bits).
    pub fn uniform_f32(&mut self) -> f32 {
        match self.next_dimension().filter(|_| self.sobol) {
            Some(d) => self.sobol_at(d),
            None => self.stream.uniform_f32(),
        }
    }

    /// The next draw, uniform in [0, 1): 24 bits from a Sobol dimension, 53 from the stream.
    pub fn uniform(&mut self) -> f64 {
        match self.next_dimension().filter(|_| self.sobol) {
            Some(d) => f64::from(self.sobol_at(d)),
            None => self.stream.uniform(),
        }
    }

    /// Dimension `d` of this sample's point: dimension `d mod 4` of the sequence seeded by
    /// the pixel and the set `d / 4`.
    fn sobol_at(&self, d: u32) -> f32 {
        let set = (mix64(self.key ^ u64::from(d / 4)) >> 32) as u32;
        sobol_burley::sample(self.sample, d % 4, set)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The first two draws of 16 samples put one sample in each cell of a 4 × 4 grid (a
    /// (0, 4, 2)-net in base 2 stays one under Owen scrambling), for any pixel.
    #[test]
    fn sixteen_samples_stratify_the_pixel() {
        for pixel in [0, 1, 12_345] {
            let mut cells = [0u32; 16];
            for s in 0..16 {
                let mut sampler = PathSampler::new(7, pixel, s, Sampling::Sobol);
                let (x, y) = (sampler.uniform_f32(), sampler.uniform_f32());
                cells[(4.0 * y) as usize * 4 + (4.0 * x) as usize] += 1;
            }
            assert_eq!(cells, [1; 16], "pixel {pixel}");
        }
    }

    /// Every draw of a path takes a dimension no other draw of it takes: the camera's two,
    /// then each event's slots, past them the stream.
    #[test]
    fn each_draw_of_a_path_has_its_own_dimension() {
        let mut sampler = PathSampler::new(1, 2, 3, Sampling::Sobol);
        let mut seen = Vec::new();
        for _ in 0..2 {
            seen.push(sampler.next_dimension());
        }
        for event in 0..SOBOL_EVENTS + 1 {
            sampler.begin_event(event);
            for _ in 0..EVENT_SLOTS + 2 {
                seen.push(sampler.next_dimension());
            }
        }
        let sobol: Vec<u32> = seen.iter().flatten().copied().collect();
        let mut unique = sobol.clone();
        unique.sort_unstable();
        unique.dedup();
        assert_eq!(unique.len(), sobol.len(), "{sobol:?}");
        assert_eq!(sobol.len() as u32, 2 + SOBOL_EVENTS * EVENT_SLOTS);
        assert_eq!(
            seen.len() - sobol.len(),
            (SOBOL_EVENTS as usize + 1) * 10 - 24
        );
        // A branch's events reuse its parent's later events' slots; the parent goes on with
        // its own next slot.
        sampler.begin_event(0);
        sampler.next_dimension();
        let mark = sampler.mark();
        sampler.begin_event(1);
        assert_eq!(
            sampler.next_dimension(),
            Some(FIRST_EVENT_DIMENSION + EVENT_SLOTS)
        );
        sampler.reset(mark);
        assert_eq!(sampler.next_dimension(), Some(FIRST_EVENT_DIMENSION + 1));
    }

    /// Under [`Sampling::Independent`] every draw is the sample's PCG stream, as the
    /// integrator drew before the Sobol points.
    #[test]
    fn independent_sampling_is_the_stream() {
        let mut sampler = PathSampler::new(5, 9, 4, Sampling::Independent);
        let mut rng = Rng::new(5, stage::PATH, (9 << SAMPLE_BITS) | 4);
        assert_eq!(sampler.uniform_f32(), rng.uniform_f32());
        sampler.begin_event(0);
        assert_eq!(sampler.uniform(), rng.uniform());
    }

    #[test]
    fn draws_are_uniform_and_pixels_independent() {
        // The mean of 4096 samples × 8 draws is 1/2 within a few standard errors
        // (σ = 1/√12 per value, 32 768 values: 0.0016).
        let mut sum = 0.0f64;
        for s in 0..4096 {
            let mut sampler = PathSampler::new(3, 99, s, Sampling::Sobol);
            sampler.begin_event(0);
            for _ in 0..8 {
                let u = sampler.uniform();
                assert!((0.0..1.0).contains(&u));
                sum += u;
            }
        }
        assert!((sum / 32_768.0 - 0.5).abs() < 0.006, "{}", sum / 32_768.0);
        // Two pixels, or two seeds, draw different points.
        let first = |seed, pixel| PathSampler::new(seed, pixel, 0, Sampling::Sobol).uniform_f32();
        assert_ne!(first(0, 1), first(0, 2));
        assert_ne!(first(0, 1), first(1, 1));
    }
}
