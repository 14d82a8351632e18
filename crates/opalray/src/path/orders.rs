//! The path tracer's light by Bragg order: input what each camera path met before each
//! light it adds ([`History`], two bytes carried with its spectrum) → output the share of
//! the stone's luminance per class of path ([`BraggOrders`], the `--stats` JSON's
//! `path.bragg_orders`). The image is the same bytes with or without it: the tally only
//! reads what the tracer adds.
//!
//! A class is the number of Bragg events on the path (a reflection by a domain's line: a
//! reflection branch, the choice of an already reflected path, or the light estimated at a
//! domain crossing, which reflects the light once more): 0, 1, 2 or 3 and more; whether one of
//! them came after an internal reflection at the stone's surface (the dome, its sides, its
//! base; a triplet's cap plane is not counted); whether the path was scattered by the body
//! (the potch, or a milky domain's haze) and whether it met a backing. Two classes lie apart:
//! the gloss (the camera ray's reflection off the surface) and the background (a camera ray
//! that misses the stone at the silhouette). A light estimate at a scattering or a backing
//! takes the class of the path there.
//!
//! Each sample's luminance Y per class is summed per row in fixed point (integers: the sums
//! are exact, so the same in any order, at any thread count and however the passes fall),
//! over the pixels whose centre sees the stone, in [`BATCHES`] batches by sample number:
//! each batch is an independent estimate of the whole image, and the standard error of a
//! share is the jackknife's over the batches (Efron & Tibshirani 1993, §11.2).

use serde::{Serialize, Serializer};

/// Batches of samples (sample `s` in batch `s mod BATCHES`) the standard errors are taken
/// over.
pub const BATCHES: usize = 8;
/// Classes of path: 4 Bragg counts × 2 × 2 × 2 flags, then the gloss and the background.
pub const CLASSES: usize = 34;
/// The gloss's class.
pub const GLOSS: usize = 32;
/// The background's class.
pub const BACKGROUND: usize = 33;
/// Fixed-point units per unit of luminance (2³²): a sample adds at most ~10⁶ (2²⁰), and a
/// render at most 2¹⁶ samples of 2²⁰ pixels, far within an `i128`.
const FIXED_PER_UNIT: f64 = 4_294_967_296.0;

/// Flag: the path was reflected inside at the stone's surface.
const REFLECTED_INSIDE: u8 = 1;
/// Flag: a Bragg event came after an internal reflection.
const BRAGG_AFTER_REFLECTION: u8 = 2;
/// Flag: the body scattered the path.
const BODY: u8 = 4;
/// Flag: the path met a backing.
const BACKING: u8 = 8;

/// What a path has met so far: its Bragg events and the flags of its class.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct History {
    bragg: u8,
    flags: u8,
}

impl History {
    /// A Bragg event (a reflection by a domain's line).
    pub fn bragg(&mut self) {
        self.bragg = self.bragg.saturating_add(1);
        if self.flags & REFLECTED_INSIDE != 0 {
            self.flags |= BRAGG_AFTER_REFLECTION;
        }
    }

    /// An internal reflection at the stone's surface.
    pub fn reflected_inside(&mut self) {
        self.flags |= REFLECTED_INSIDE;
    }

    /// A scattering by the body (the potch or a milky domain's haze).
    pub fn scattered(&mut self) {
        self.flags |= BODY;
    }

    /// A reflection by a backing.
    pub fn backed(&mut self) {
        self.flags |= BACKING;
    }

    /// Bragg events so far.
    pub fn bragg_events(self) -> u8 {
        self.bragg
    }

    /// The class of the light the path adds now (below [`GLOSS`]).
    pub fn class(self) -> usize {
        let mut c = usize::from(self.bragg.min(3));
        if self.flags & BRAGG_AFTER_REFLECTION != 0 {
            c |= 4;
        }
        if self.flags & BODY != 0 {
            c |= 8;
        }
        if self.flags & BACKING != 0 {
            c |= 16;
        }
        c
    }
}

/// One camera sample's luminance per class.
pub type SampleTally = [f64; CLASSES];

/// The luminance per class summed over samples, in fixed point, per batch of samples.
#[derive(Clone, Debug, PartialEq)]
pub struct OrderSums {
    batches: [[i128; CLASSES]; BATCHES],
}

impl Default for OrderSums {
    fn default() -> Self {
        OrderSums {
            batches: [[0; CLASSES]; BATCHES],
        }
    }
}

impl OrderSums {
    /// Add sample `s`'s tally.
    pub fn add_sample(&mut self, s: u32, tally: &SampleTally) {
        let batch = &mut self.batches[s as usize % BATCHES];
        for (sum, &y) in batch.iter_mut().zip(tally) {
            if y != 0.0 {
                *sum += (y * FIXED_PER_UNIT).round() as i128;
            }
        }
    }

    /// Add `other`'s sums.
    pub fn merge(&mut self, other: &OrderSums) {
        for (a, b) in self.batches.iter_mut().zip(&other.batches) {
            for (x, y) in a.iter_mut().zip(b) {
                *x += y;
            }
        }
    }

    /// The luminance summed over the samples of the classes `picked` in each batch.
    fn batch_sums(&self, picked: &dyn Fn(usize) -> bool) -> [f64; BATCHES] {
        self.batches.map(|b| {
            let sum: i128 = (0..CLASSES).filter(|&c| picked(c)).map(|c| b[c]).sum();
            sum as f64 / FIXED_PER_UNIT
        })
    }

    /// The share of the luminance in the classes `picked`, and its jackknife standard error
    /// over the batches that hold samples (`None` with fewer than two, or no luminance).
    pub fn share(&self, batches_used: usize, picked: &dyn Fn(usize) -> bool) -> (f64, Option<f64>) {
        let part = self.batch_sums(picked);
        let total = self.batch_sums(&|_| true);
        let (p, t): (f64, f64) = (part.iter().sum(), total.iter().sum());
        if t <= 0.0 {
            return (0.0, None);
        }
        let k = batches_used.min(BATCHES);
        if k < 2 {
            return (p / t, None);
        }
        // Leave each batch out in turn.
        let left: Vec<f64> = (0..k)
            .map(|b| {
                let rest = t - total[b];
                if rest > 0.0 {
                    (p - part[b]) / rest
                } else {
                    p / t
                }
            })
            .collect();
        let mean = left.iter().sum::<f64>() / k as f64;
        let kf = k as f64;
        let var = (kf - 1.0) / kf * left.iter().map(|r| (r - mean).powi(2)).sum::<f64>();
        (p / t, Some(var.sqrt()))
    }

    /// The report of a render of `spp` samples per pixel over `pixels` stone pixels.
    pub fn report(&self, spp: u32, pixels: usize) -> BraggOrders {
        let used = (spp as usize).min(BATCHES);
        let total: f64 = self.batch_sums(&|_| true).iter().sum();
        let samples = f64::from(spp) * pixels as f64;
        BraggOrders {
            spp,
            pixels,
            mean_luminance: if samples > 0.0 { total / samples } else { 0.0 },
            classes: std::array::from_fn(|c| self.share(used, &|k| k == c)),
            summary: SUMMARY.map(|(_, picked)| self.share(used, &picked)),
        }
    }
}

/// Whether class `c` is a path's (not the gloss nor the background).
fn on_path(c: usize) -> bool {
    c < GLOSS
}

/// Bragg events of class `c` (3: three or more).
fn bragg_of(c: usize) -> usize {
    c & 3
}

/// A share of the summary: its name and which classes it sums.
type SummaryShare = (&'static str, fn(usize) -> bool);

/// The summary's shares.
const SUMMARY: [SummaryShare; 11] = [
    ("background", |c| c == BACKGROUND),
    ("gloss", |c| c == GLOSS),
    ("bragg_0", |c| on_path(c) && bragg_of(c) == 0),
    ("bragg_1", |c| on_path(c) && bragg_of(c) == 1),
    ("bragg_2", |c| on_path(c) && bragg_of(c) == 2),
    ("bragg_3_or_more", |c| on_path(c) && bragg_of(c) == 3),
    ("bragg_after_internal_reflection", |c| {
        on_path(c) && c & 4 != 0
    }),
    ("body", |c| on_path(c) && c & 8 != 0),
    ("backing", |c| on_path(c) && c & 16 != 0),
    ("bragg_with_body_or_backing", |c| {
        on_path(c) && bragg_of(c) > 0 && c & 24 != 0
    }),
    // What the lobe integrator leaves out (`crate::lobe`): a third Bragg event, or a Bragg
    // event on a path through the body's scattering or off a backing.
    ("beyond_lobe", |c| {
        on_path(c) && bragg_of(c) > 0 && (bragg_of(c) == 3 || c & 24 != 0)
    }),
];

/// The share of the stone's luminance per class of path (see the module's notes), each with
/// its standard error (`None` below two samples per pixel).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct BraggOrders {
    /// Samples per pixel.
    pub spp: u32,
    /// Pixels the shares are over (those whose centre sees the stone).
    pub pixels: usize,
    /// Their mean luminance Y (a white diffuser under the light: 1).
    pub mean_luminance: f64,
    /// Share and standard error per class (index: Bragg events 0–3, + 4 if one came after an
    /// internal reflection, + 8 with the body, + 16 with a backing; then [`GLOSS`] and
    /// [`BACKGROUND`]).
    pub classes: [(f64, Option<f64>); CLASSES],
    /// Share and standard error of the sums of classes named in the JSON's `summary`.
    pub summary: [(f64, Option<f64>); SUMMARY.len()],
}

impl BraggOrders {
    /// The `bragg_orders` section of the `--stats` JSON: the summary, then every class with
    /// light.
    pub fn to_json(&self) -> serde_json::Value {
        let entry = |(share, se): (f64, Option<f64>)| serde_json::json!({ "share": share, "standard_error": se });
        let summary: serde_json::Map<String, serde_json::Value> = SUMMARY
            .iter()
            .zip(self.summary)
            .map(|((name, _), v)| (name.to_string(), entry(v)))
            .collect();
        let classes: Vec<serde_json::Value> = (0..GLOSS)
            .filter(|&c| self.classes[c].0 > 0.0)
            .map(|c| {
                let (share, se) = self.classes[c];
                let bragg = ["0", "1", "2", "3+"][bragg_of(c)];
                serde_json::json!({
                    "bragg": bragg,
                    "bragg_after_internal_reflection": c & 4 != 0,
                    "body": c & 8 != 0,
                    "backing": c & 16 != 0,
                    "share": share,
                    "standard_error": se,
                })
            })
            .collect();
        serde_json::json!({
            "of": "the luminance over the pixels whose centre sees the stone, by what each path met before it added its light (docs/model.md)",
            "spp": self.spp,
            "pixels": self.pixels,
            "mean_luminance": self.mean_luminance,
            "standard_error_is": "the jackknife's over 8 batches of samples (s mod 8)",
            "summary": summary,
            "classes": classes,
        })
    }
}

impl Serialize for BraggOrders {
    fn serialize<S: Serializer>(&self, serializer: S) -> Result<S::Ok, S::Error> {
        self.to_json().serialize(serializer)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn history_classes_count_bragg_events_and_flags() {
        let mut h = History::default();
        assert_eq!(h.class(), 0);
        h.bragg();
        assert_eq!(h.class(), 1);
        h.reflected_inside();
        assert_eq!(
            h.class(),
            1,
            "a reflection alone is not a Bragg event after one"
        );
        h.bragg();
        assert_eq!(h.class(), 2 | 4);
        h.scattered();
        h.backed();
        for _ in 0..300 {
            h.bragg();
        }
        assert_eq!(h.class(), 3 | 4 | 8 | 16);
        assert_eq!(h.bragg_events(), 255);
    }

    #[test]
    fn jackknife_of_a_share_matches_the_batches_spread() {
        // Batch b holds 1 of class 1 and x_b of class 0, x_b = 1 + b/7: the share of class 1
        // per batch is 1/(1 + x_b); the whole's is 8 / (8 + Σ x_b) = 8/20 = 0.4. The
        // jackknife's leave-one-out ratios are (8 − 1)/(20 − 1 − x_b), computed here by hand.
        let mut sums = OrderSums::default();
        for b in 0..BATCHES {
            let mut t = [0.0; CLASSES];
            t[1] = 1.0;
            t[0] = 1.0 + b as f64 / 7.0;
            sums.add_sample(b as u32, &t);
        }
        let (share, se) = sums.share(BATCHES, &|c| c == 1);
        assert!((share - 0.4).abs() < 1e-9);
        let left: Vec<f64> = (0..8)
            .map(|b| 7.0 / (19.0 - (1.0 + b as f64 / 7.0)))
            .collect();
        let mean = left.iter().sum::<f64>() / 8.0;
        let expected = (7.0 / 8.0 * left.iter().map(|r| (r - mean).powi(2)).sum::<f64>()).sqrt();
        assert!(
            (se.unwrap() - expected).abs() < 1e-9,
            "{se:?} vs {expected}"
        );
        // The shares of all classes sum to 1, and one batch gives no error.
        let report = sums.report(8, 1);
        let total: f64 = report.classes.iter().map(|c| c.0).sum();
        assert!((total - 1.0).abs() < 1e-12);
        assert_eq!(sums.share(1, &|c| c == 1).1, None);
    }

    #[test]
    fn fixed_point_sums_do_not_depend_on_the_order() {
        let values = [1e-7, 3.25, 1234.5678, 0.1, 7e3, 2e-3];
        let (mut a, mut b) = (OrderSums::default(), OrderSums::default());
        for (i, v) in values.iter().enumerate() {
            let mut t = [0.0; CLASSES];
            t[GLOSS] = *v;
            a.add_sample(i as u32 * 8, &t);
        }
        for (i, v) in values.iter().enumerate().rev() {
            let mut t = [0.0; CLASSES];
            t[GLOSS] = *v;
            let mut one = OrderSums::default();
            one.add_sample(i as u32 * 8, &t);
            b.merge(&one);
        }
        assert_eq!(a, b);
    }
}
