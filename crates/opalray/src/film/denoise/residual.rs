//! What the denoiser cuts and gives back: the fireflies cut before the halves filter each
//! other ([`clamp_fireflies`]), and what the cut and the filter took or added returned about
//! each pixel after it ([`return_residual`]), so that the filtered image keeps the raw image's
//! X, Y and Z.

/// Half-side, pixels, of the square over which what the cut and the filter took or added is
/// returned ([`return_residual`]).
const RETURN_RADIUS: usize = 16;

/// Return to the filtered image `xyz` what the firefly cut and the filter took from the raw
/// image `raw` (or added to it), channel by channel: each pixel's residual `raw − xyz` goes to
/// the pixels of the square of half-side [`RETURN_RADIUS`] about it, in proportion to their
/// filtered value in that channel (the patch it belongs to, not the dark around it), or to
/// itself where they hold none. Non-local means is normalised per output pixel, not per input
/// pixel: a bright pixel of large variance averages with the dark ones about it while they
/// hardly take from it, so it moves light locally; a firefly's light belongs to the pixels about
/// it in expectation. Spread over the ~1000 pixels of the square, the residual's noise adds
/// about 1/30 of a raw pixel's, and the image keeps the raw image's X, Y and Z exactly (the
/// squares are symmetric: what pixel `i` sends, the pixels about it receive). Summed-area
/// tables in f64, filled in pixel order: the same bytes at any thread count.
pub(super) fn return_residual(xyz: &mut [[f32; 3]], raw: &[[f32; 3]], width: usize, height: usize) {
    for c in 0..3 {
        let weight: Vec<f64> = xyz.iter().map(|p| f64::from(p[c].max(0.0))).collect();
        let total = box_sums(&weight, width, height, RETURN_RADIUS);
        let mut own = vec![0.0f64; xyz.len()];
        let ratio: Vec<f64> = (0..xyz.len())
            .map(|i| {
                let residual = f64::from(raw[i][c]) - f64::from(xyz[i][c]);
                if total[i] > 0.0 {
                    residual / total[i]
                } else {
                    own[i] = residual;
                    0.0
                }
            })
            .collect();
        let spread = box_sums(&ratio, width, height, RETURN_RADIUS);
        for (i, p) in xyz.iter_mut().enumerate() {
            p[c] = (f64::from(p[c]) + weight[i] * spread[i] + own[i]) as f32;
        }
    }
}

/// Per pixel, the sum of `values` (`width × height`, row-major) over the square of half-side
/// `r` about it, clipped to the image.
fn box_sums(values: &[f64], width: usize, height: usize, r: usize) -> Vec<f64> {
    let stride = width + 1;
    let mut table = vec![0.0f64; stride * (height + 1)];
    for y in 0..height {
        let mut row = 0.0;
        for x in 0..width {
            row += values[y * width + x];
            table[(y + 1) * stride + x + 1] = table[y * stride + x + 1] + row;
        }
    }
    let at = |x: usize, y: usize| table[y * stride + x];
    (0..width * height)
        .map(|i| {
            let (x, y) = (i % width, i / width);
            let (x0, x1) = (x.saturating_sub(r), (x + r + 1).min(width));
            let (y0, y1) = (y.saturating_sub(r), (y + r + 1).min(height));
            at(x1, y1) - at(x0, y1) - at(x1, y0) + at(x0, y0)
        })
        .collect()
}

/// Sum of channel `c` over `image`, in f64 and in pixel order.
pub(super) fn channel_sum(image: &[[f32; 3]], c: usize) -> f64 {
    image.iter().map(|p| f64::from(p[c])).sum()
}

/// Per channel, `part`'s sum over `whole`'s (0 where `whole` sums to 0).
pub(super) fn share_of(part: &[[f32; 3]], whole: &[[f32; 3]]) -> [f64; 3] {
    std::array::from_fn(|c| {
        let w = channel_sum(whole, c);
        if w > 0.0 {
            channel_sum(part, c) / w
        } else {
            0.0
        }
    })
}

/// How much brighter than everything around it a pixel of one half may be before it counts as
/// a firefly ([`clamp_fireflies`]). Against the 128- and 256-sample references at 8 samples
/// per pixel, 4 took the denoised error from 15.4 to 14.1 % (ragged black opal) and from
/// 12.2 to 11.3 % (straight-edged), the mean falling 0.4–0.7 %; 2 took them to 14.0 and
/// 11.1 % for 1.1 % of the mean (`BENCHMARKS.md`).
pub(super) const FIREFLY_RATIO: f32 = 4.0;

/// Fireflies, before the halves filter each other: where a pixel of one half is brighter in
/// any of X, Y and Z than `ratio` times the brightest of that channel in the other half's same
/// pixel and both halves' eight neighbours, it is scaled down (all three channels alike, its
/// colour kept) until none is. A firefly is one rare sample of large weight: it shows in one
/// half, alone. Spread by the filter with its energy kept, it would leave a soft spot; cut
/// here, the energy it loses is returned after the filter over a wide disc about it
/// ([`return_residual`]), so the image keeps its mean and colour. A bright detail
/// shows in both halves and passes. Each channel is tested, not Y alone: a violet firefly on a
/// white body carries little Y but many times the body's Z, and spread it left round violet
/// spots on the white opal.
pub(super) fn clamp_fireflies(
    a: &mut [[f32; 3]],
    b: &mut [[f32; 3]],
    width: usize,
    height: usize,
    ratio: f32,
) {
    let (la, lb) = (a.to_vec(), b.to_vec());
    let around = |i: usize| {
        let (x, y) = (i % width, i / width);
        let mut m = [0.0f32; 3];
        for yy in y.saturating_sub(1)..(y + 2).min(height) {
            for xx in x.saturating_sub(1)..(x + 2).min(width) {
                let j = yy * width + xx;
                if j != i {
                    m = std::array::from_fn(|c| m[c].max(la[j][c]).max(lb[j][c]));
                }
            }
        }
        m
    };
    for i in 0..a.len() {
        let m = around(i);
        for (half, own, other) in [(&mut *a, &la, &lb), (&mut *b, &lb, &la)] {
            let mut k = 1.0f32;
            for c in 0..3 {
                let limit = ratio * m[c].max(other[i][c]);
                if own[i][c] > limit && own[i][c] > 0.0 {
                    k = k.min(limit / own[i][c]);
                }
            }
            if k < 1.0 {
                half[i] = half[i].map(|v| v * k);
            }
        }
    }
}
