//! A cluster's transmittance at one angle as a [`Transmission`]: its level away from the
//! Bragg line and each bin's ratio to it in the line's window, applied to a throughput kept
//! as `scale × shape` (the view pass's camera rays and the direct light cross cluster after
//! cluster at one angle).

use super::ClusterOptics;

/// A cluster's transmittance at one angle, ready to apply to any number of throughputs: its
/// level away from the Bragg line and, in the line's window `lo..hi`, each bin's ratio to
/// that level. (A camera ray crossing a patch meets cell after cell at the same angle.)
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Transmission {
    background: f32,
    lo: usize,
    hi: usize,
    ratio: Vec<f32>,
    /// The largest ratio: where it is at most 1, no bin of a shape can rise above its peak.
    ratio_max: f32,
}

impl Transmission {
    /// Apply to a throughput kept as `scale × shape`, the shape's maximum being 1, at bin
    /// `peak`: returns the factor for the scale, and changes the shape only in the window,
    /// renormalised so that its maximum stays 1 (and `peak` names where it is). The rest of
    /// the shape is scanned only when the window holds the peak: a line's window spans a few
    /// bins of forty.
    #[inline(always)]
    pub fn apply(&self, shape: &mut [f32], peak: &mut usize) -> f32 {
        let (lo, hi) = (self.lo, self.hi);
        if lo >= hi {
            return self.background;
        }
        for (s, r) in shape[lo..hi].iter_mut().zip(&self.ratio) {
            *s *= r;
        }
        let (max, arg) = if !(lo..hi).contains(peak) {
            // The peak, 1, lies outside the window and is unchanged; a window bin can rise
            // above it only if some ratio exceeds 1.
            if self.ratio_max <= 1.0 {
                return self.background;
            }
            let (window_max, window_arg) =
                shape[lo..hi]
                    .iter()
                    .enumerate()
                    .fold(
                        (0.0f32, lo),
                        |(m, a), (k, &v)| if v > m { (v, lo + k) } else { (m, a) },
                    );
            if window_max <= 1.0 {
                return self.background;
            }
            (window_max, window_arg)
        } else {
            shape.iter().enumerate().fold(
                (0.0f32, 0),
                |(m, a), (k, &v)| if v > m { (v, k) } else { (m, a) },
            )
        };
        if max <= 0.0 {
            return 0.0;
        }
        let k = 1.0 / max;
        shape.iter_mut().for_each(|s| *s *= k);
        shape[arg] = 1.0;
        *peak = arg;
        self.background * max
    }
}

impl ClusterOptics<'_> {
    /// The transmittance at `cos_theta`, written into `out` (see [`Transmission`]).
    #[inline(always)]
    pub fn transmission(&self, cos_theta: f32, out: &mut Transmission) {
        let (i, w) = self.row_at(cos_theta);
        let pair = &self.pairs[i];
        let background = pair.at(1, w);
        let (lo, hi) = (pair.lo, pair.hi);
        out.ratio.clear();
        if lo >= hi || background <= f32::MIN_POSITIVE {
            out.background = if lo >= hi { background } else { 0.0 };
            out.lo = 0;
            out.hi = 0;
            return;
        }
        let (ta, tb) = (self.tables.row(i).1, self.tables.row(i + 1).1);
        let inv = 1.0 / background;
        out.background = background;
        out.lo = lo;
        out.hi = hi;
        out.ratio.extend(
            ta[lo..hi]
                .iter()
                .zip(&tb[lo..hi])
                .map(|(ta, tb)| (ta + w * (tb - ta)) * inv),
        );
        out.ratio_max = out.ratio.iter().fold(0.0f32, |m, &r| m.max(r));
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::light_pass::Split;
    use crate::optics::build_optics;
    use crate::optics::OpticsTables;
    use crate::scene::CrystalConfig;
    use crate::spectrum::WavelengthGrid;

    fn tables() -> OpticsTables {
        let grid = WavelengthGrid::new(380.0, 780.0, 40).unwrap();
        build_optics(&CrystalConfig::default(), &grid).unwrap()
    }

    /// The transmittance `split` gives at `cos`, bin by bin.
    fn split_t(optics: &ClusterOptics, cos: f32) -> Vec<f32> {
        let bins = optics.tables().grid.bins;
        let (mut r, mut t, mut d) = (vec![0.0; bins], vec![0.0; bins], vec![0.0; bins]);
        match optics.split(cos, &mut r, &mut t, &mut d) {
            Split::Flat { t, .. } => vec![t; bins],
            Split::Window { lo, hi, t: tb, .. } => (0..bins)
                .map(|k| if (lo..hi).contains(&k) { t[k] } else { tb })
                .collect(),
        }
    }

    #[test]
    fn a_chain_of_transmissions_is_their_product_wherever_the_peak_is() {
        // A spectrum peaked inside the Bragg lines' range, through 60 clusters at angles that
        // put their windows over it and next to it: scale × shape must stay the start spectrum
        // times the product of the transmittances, with the shape's maximum 1 at `peak`.
        let tables = tables();
        let optics = ClusterOptics::new(&tables);
        let bins = tables.grid.bins;
        for centre in [8usize, 12, 16, 20] {
            let start: Vec<f32> = (0..bins)
                .map(|b| 1.0 / (1.0 + 0.05 * (b as f32 - centre as f32).powi(2)))
                .collect();
            let mut want: Vec<f64> = start.iter().map(|&v| f64::from(v)).collect();
            let mut shape = start.clone();
            let (mut scale, mut peak) = (1.0f32, centre);
            let mut scratch = Transmission::default();
            for k in 0..60 {
                let cos = 0.70 + 0.3 * ((k * 37) % 60) as f32 / 60.0;
                let t = split_t(&optics, cos);
                want.iter_mut()
                    .zip(&t)
                    .for_each(|(w, &t)| *w *= f64::from(t));
                optics.transmission(cos, &mut scratch);
                scale *= scratch.apply(&mut shape, &mut peak);
                let max = shape.iter().fold(0.0f32, |m, &v| m.max(v));
                assert_eq!(shape[peak], max, "step {k}: the peak moved without `peak`");
                assert!((max - 1.0).abs() < 1e-6, "step {k}: shape max {max}");
            }
            let top = want.iter().fold(0.0f64, |m, &v| m.max(v));
            for b in 0..bins {
                let got = f64::from(scale * shape[b]);
                assert!(
                    (got - want[b]).abs() <= 1e-4 * top,
                    "peak {centre}, bin {b}: {got} against {}",
                    want[b]
                );
            }
        }
    }

    #[test]
    fn a_transmission_applies_the_split_transmittance() {
        let tables = tables();
        let optics = ClusterOptics::new(&tables);
        let bins = tables.grid.bins;
        let mut windows = 0;
        for k in 0..=400 {
            let cos = k as f32 / 400.0;
            let expected = split_t(&optics, cos);
            windows += usize::from(expected.iter().any(|&t| t != expected[0]));
            // A non-uniform starting spectrum, so that a wrong bin would show.
            let start: Vec<f32> = (0..bins).map(|b| 0.5 + b as f32 / bins as f32).collect();
            let peak = start.iter().fold(0.0f32, |m, &v| m.max(v));
            let mut shape: Vec<f32> = start.iter().map(|v| v / peak).collect();
            let mut at = bins - 1;
            let mut scratch = Transmission::default();
            optics.transmission(cos, &mut scratch);
            let scale = peak * scratch.apply(&mut shape, &mut at);
            let max = shape.iter().fold(0.0f32, |m, &v| m.max(v));
            assert!(max == 0.0 || (max - 1.0).abs() < 1e-6, "shape max {max}");
            assert!(max == 0.0 || shape[at] == max, "the peak is at bin {at}");
            for b in 0..bins {
                let want = start[b] * expected[b];
                let got = scale * shape[b];
                assert!(
                    (got - want).abs() <= 1e-5 * want.max(1e-3),
                    "cos {cos}, bin {b}"
                );
            }
        }
        assert!(
            windows > 10,
            "the sweep must cross the Bragg line ({windows} rows)"
        );
    }
}
