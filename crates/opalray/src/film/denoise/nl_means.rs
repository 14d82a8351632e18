//! Non-local means over an image of three channels, its weights from a guide image and the
//! variance of the guide's pixels (Rousselle, Knaus & Zwicker 2012, "Adaptive rendering with
//! non-local means filtering", ACM TOG 31(6):195, eq. 4–6).
//!
//! For pixels `p`, `q` and a channel `i` of the guide `u` with pixel variances `v`:
//!
//! `d²ᵢ(p, q) = ((uᵢ(p) − uᵢ(q))² − α (vᵢ(p) + min(vᵢ(p), vᵢ(q)))) / (ε + k² (vᵢ(p) + vᵢ(q)))`
//!
//! the squared difference less what the noise alone would give, in units of the variance.
//! Averaged over the channels and over a patch of `(2f + 1)²` pixel pairs around `p` and `q`
//! it is the patch distance `D(p, q)`; `q`'s weight in `p` is `exp(−max(0, D))`, over the
//! pixels of the window around `p`, those within `r` of it (a disc: 149 pixels for r = 7, so
//! that a spread firefly is a round spot, not a square). A pixel of no variance takes weight only from
//! pixels alike to within `ε`, so a noiseless image passes unchanged.
//!
//! The image is filtered in bands of rows in parallel; within a band each offset `q − p` is
//! one pass (its distances, box-filtered over the patch), and every pixel sums its window in
//! the same order of offsets whatever the threads, so the result is the same bytes.

use rayon::prelude::*;

/// Rows per band of the parallel filter.
const BAND_ROWS: usize = 16;
/// How far the variance term cancels the noise's own part of a squared difference (α, the
/// paper's value).
const ALPHA: f32 = 1.0;
/// A pixel pair's distance is cut here (its weight is then nil already): far apart pixels of
/// no noise would otherwise swamp the patch sums' precision.
const MAX_DISTANCE: f32 = 1e3;
/// Keeps the distance finite where both pixels are noiseless (ε, the paper's value).
const EPSILON: f32 = 1e-10;

/// The filter's sizes and strength.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct NlMeans {
    /// Window radius `r`, pixels: a pixel averages over the pixels within `r` of it.
    pub window_radius: usize,
    /// Patch radius `f`, pixels: pixels are compared by `(2f + 1)²` pixel pairs.
    pub patch_radius: usize,
    /// Strength `k`: how many standard deviations of difference a pixel pair may show and
    /// still count as alike (the paper's 0.45 is conservative; larger smooths more).
    pub strength: f32,
}

/// Filter `target` (a `width × height` image, row-major) with the weights of `guide` and its
/// per-pixel variances `variance`.
pub fn filter(
    target: &[[f32; 3]],
    guide: &[[f32; 3]],
    variance: &[[f32; 3]],
    width: usize,
    height: usize,
    params: &NlMeans,
) -> Vec<[f32; 3]> {
    let mut out = vec![[0.0f32; 3]; width * height];
    out.par_chunks_mut(BAND_ROWS * width)
        .enumerate()
        .for_each(|(band, rows)| {
            let image = Guide {
                guide,
                variance,
                width,
                height,
            };
            filter_band(target, &image, band * BAND_ROWS, rows, params);
        });
    out
}

/// The guide image and its variances.
struct Guide<'a> {
    guide: &'a [[f32; 3]],
    variance: &'a [[f32; 3]],
    width: usize,
    height: usize,
}

impl Guide<'_> {
    /// `d²(p, q)` averaged over the channels.
    fn distance(&self, p: usize, q: usize, k2: f32) -> f32 {
        let (up, uq) = (self.guide[p], self.guide[q]);
        let (vp, vq) = (self.variance[p], self.variance[q]);
        let mut sum = 0.0;
        for i in 0..3 {
            let diff = up[i] - uq[i];
            let noise = ALPHA * (vp[i] + vp[i].min(vq[i]));
            sum += (diff * diff - noise) / (EPSILON + k2 * (vp[i] + vq[i]));
        }
        sum / 3.0
    }
}

/// Filter the rows from `y0` on into `out` (whole rows).
fn filter_band(
    target: &[[f32; 3]],
    image: &Guide,
    y0: usize,
    out: &mut [[f32; 3]],
    params: &NlMeans,
) {
    let (w, h) = (image.width, image.height);
    let rows = out.len() / w;
    let (f, r) = (params.patch_radius, params.window_radius as isize);
    let k2 = params.strength * params.strength;
    // The band's rows with the patch's margin, clipped to the image.
    let (e0, e1) = (y0.saturating_sub(f), (y0 + rows + f).min(h));
    let mut d2 = vec![0.0f32; (e1 - e0) * w];
    let mut across = vec![0.0f32; (e1 - e0) * w];
    let mut prefix = vec![0.0f64; w.max(e1 - e0) + 1];
    let mut sum = vec![[0.0f32; 3]; rows * w];
    let mut weights = vec![0.0f32; rows * w];
    for dy in -r..=r {
        for dx in -r..=r {
            // The window is a disc.
            if dx * dx + dy * dy > r * r {
                continue;
            }
            // Distances of every pixel of the band (and margin) to its partner at the offset,
            // partners beyond the edge clamped to it (they only fill patches).
            for y in e0..e1 {
                let qy = (y as isize + dy).clamp(0, h as isize - 1) as usize;
                for x in 0..w {
                    let qx = (x as isize + dx).clamp(0, w as isize - 1) as usize;
                    let d = image.distance(y * w + x, qy * w + qx, k2);
                    d2[(y - e0) * w + x] = d.min(MAX_DISTANCE);
                }
            }
            // The patch's mean: a box along the rows, then down the columns.
            for y in 0..e1 - e0 {
                let row = &d2[y * w..(y + 1) * w];
                box_mean(
                    w,
                    |x| row[x],
                    f,
                    &mut prefix,
                    0..w,
                    |x, v| {
                        across[y * w + x] = v;
                    },
                );
            }
            let band = y0 - e0..y0 - e0 + rows;
            for x in 0..w {
                let column = |y: usize| across[y * w + x];
                box_mean(e1 - e0, column, f, &mut prefix, band.clone(), |y, d| {
                    let (py, px) = (y0 + y, x);
                    let (qy, qx) = (py as isize + dy, px as isize + dx);
                    if qy < 0 || qx < 0 || qy >= h as isize || qx >= w as isize {
                        return;
                    }
                    let weight = (-d.max(0.0)).exp();
                    let t = target[qy as usize * w + qx as usize];
                    let i = y * w + x;
                    weights[i] += weight;
                    for c in 0..3 {
                        sum[i][c] += weight * t[c];
                    }
                });
            }
        }
    }
    for ((o, s), wt) in out.iter_mut().zip(&sum).zip(&weights) {
        *o = s.map(|v| v / wt);
    }
}

/// Box means of radius `f` over the `n` values `value(i)`, the box clipped to `0..n`, for
/// `i` in `range`: `emit(i − range.start, mean)`. `prefix` holds at least `n + 1` sums.
fn box_mean(
    n: usize,
    value: impl Fn(usize) -> f32,
    f: usize,
    prefix: &mut [f64],
    range: std::ops::Range<usize>,
    mut emit: impl FnMut(usize, f32),
) {
    prefix[0] = 0.0;
    for i in 0..n {
        prefix[i + 1] = prefix[i] + f64::from(value(i));
    }
    for i in range.clone() {
        let (a, b) = (i.saturating_sub(f), (i + f + 1).min(n));
        emit(
            i - range.start,
            ((prefix[b] - prefix[a]) / (b - a) as f64) as f32,
        );
    }
}
