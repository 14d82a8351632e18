//! A light branch's spectrum as `scale × shape` (paper §3.2): filters flat in wavelength
//! change the scale only, a Bragg line the bins of its window. These are the shape's
//! operations: filtering by a line's window, the shape of a Bragg-reflected branch, and the
//! sums a split needs over the window.

/// Divide a shape by its maximum and return the factor for its scale (a shape reflected
/// again and again by Bragg lines grows by the ratio of a line to its background each time).
fn normalise(shape: &mut [f32]) -> f32 {
    let max = shape.iter().fold(0.0f32, |m, &v| m.max(v));
    if max > 0.0 {
        let inv = 1.0 / max;
        shape.iter_mut().for_each(|v| *v *= inv);
        max
    } else {
        1.0
    }
}

/// Filter the shape of a `scale × shape` spectrum by a fraction that is `background` at every
/// bin but those of a Bragg line's window, from `lo` on, where it is `window`: returns the
/// factor for the scale. (Shape and scale keep their product; the shape changes only in the
/// window, unless the background is zero.)
#[inline(always)]
pub(super) fn filter_window(shape: &mut [f32], lo: usize, window: &[f32], background: f32) -> f32 {
    let hi = lo + window.len();
    if background > 0.0 {
        let inv = 1.0 / background;
        for (s, f) in shape[lo..hi].iter_mut().zip(window) {
            *s *= f * inv;
        }
        background
    } else {
        shape[..lo].fill(0.0);
        shape[hi..].fill(0.0);
        for (s, f) in shape[lo..hi].iter_mut().zip(window) {
            *s *= f;
        }
        1.0
    }
}

/// The shape of a Bragg-reflected branch, in a spectrum from `pool`: a copy of `shape`,
/// filtered by a Bragg line's window `(lo, fractions, background)` if given (see
/// [`filter_window`]) and then divided by its maximum if `renormalise`; returns it with the
/// factor for its scale. Out of line: a branch starts at one cluster crossing in twenty, and
/// the walk's loop is tighter without this code in it.
#[cold]
#[inline(never)]
pub(super) fn reflected_shape(
    pool: &mut Vec<Vec<f32>>,
    shape: &[f32],
    window: Option<(usize, &[f32], f32)>,
    renormalise: bool,
) -> (Vec<f32>, f32) {
    let mut v = pool.pop().unwrap_or_default();
    v.clear();
    v.extend_from_slice(shape);
    let mut k = 1.0;
    if let Some((lo, fractions, background)) = window {
        k = filter_window(&mut v, lo, fractions, background);
    }
    if renormalise {
        k *= normalise(&mut v);
    }
    (v, k)
}

/// The four sums of a Bragg line's window `s` (the shape's bins) with its fractions `r`, `d`,
/// `t`: `[Σ s, Σ s·r, Σ s·d, Σ s·t]`. Each sum runs in eight lanes, independent chains that
/// vectorise, added up at the end (one pass over the window; a sequential sum would wait on
/// each addition before the next).
#[inline(always)]
pub(super) fn window_sums(s: &[f32], r: &[f32], d: &[f32], t: &[f32]) -> [f32; 4] {
    const LANES: usize = 8;
    let mut lanes = [[0.0f32; LANES]; 4];
    let whole = s.len() / LANES * LANES;
    for (((s, r), d), t) in s
        .chunks_exact(LANES)
        .zip(r.chunks_exact(LANES))
        .zip(d.chunks_exact(LANES))
        .zip(t.chunks_exact(LANES))
    {
        for j in 0..LANES {
            lanes[0][j] += s[j];
            lanes[1][j] += s[j] * r[j];
            lanes[2][j] += s[j] * d[j];
            lanes[3][j] += s[j] * t[j];
        }
    }
    let mut sums = lanes.map(|l| l.iter().sum::<f32>());
    for (((&s, &r), &d), &t) in s[whole..]
        .iter()
        .zip(&r[whole..])
        .zip(&d[whole..])
        .zip(&t[whole..])
    {
        sums[0] += s;
        sums[1] += s * r;
        sums[2] += s * d;
        sums[3] += s * t;
    }
    sums
}
