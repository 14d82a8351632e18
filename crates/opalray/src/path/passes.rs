//! The path integrator's pixel and sample loop, in passes: input a [`Stone`] and a
//! [`PathSetup`] (and the seam's [`Passes`]: a time limit, a report after each pass) →
//! output a [`PathImage`].
//!
//! A render is a sequence of passes of samples per pixel: the first pass 2 (1 if only one is
//! asked for), then each pass as many as all before it (doubling the total), cut so as not to
//! pass `spp`, [`Passes::max_pass_spp`] nor, by the passes' measured pace, the time limit.
//! Sample `s` of pixel `p` is point `s` of the pixel's Owen-scrambled Sobol sequence, laid
//! out by event ([`super::sampler`]: its jitter over the pixel, then its path), and every
//! pixel's sums take its samples in the order of `s`, whatever the passes; so the image for `n` samples per pixel is the same bytes however the
//! passes fall and at any thread count — a time-limited render is the render with the `spp`
//! it reached. Rows are rendered in parallel into pre-sized buffers.
//!
//! Each pixel's samples go to the film ([`crate::film`]): the sums of its even and of its odd
//! samples (for the noise estimate) and of the squares of the samples' XYZ (for its variance).

use std::sync::Mutex;
use std::time::Instant;

use rayon::prelude::*;

use super::orders::OrderSums;
use super::sampler::{PathSampler, MAX_SAMPLES};
use super::{PathImage, PathSetup, Tracer};
use crate::film::{Film, PixelSums};
use crate::integrator::{PassReport, Passes};
use crate::scene::MAX_SPP;
use crate::stone::Stone;

// Every sample of a pixel is a point of its sequence.
const _: () = assert!(MAX_SPP <= MAX_SAMPLES);
/// Samples per pixel of the first pass: two, so that the noise can be estimated from the first.
const FIRST_PASS_SPP: u32 = 2;

/// Render `stone` as `setup` says, in passes as `passes` says.
pub fn trace_passes(stone: &Stone, setup: &PathSetup, passes: &Passes) -> PathImage {
    let start = Instant::now();
    let (w, h) = (setup.width, setup.height);
    let target = setup.spp.clamp(1, MAX_SPP);
    let on_stone = stone_mask(stone, setup);
    let mut film = Film::new(w, h, setup.spectral.grid);
    let (mut done, mut count) = (0u32, 0u32);
    let mut orders = OrderSums::default();
    while done < target {
        // The pass: doubling the samples so far, within the target and the time left.
        let mut size = if done == 0 { FIRST_PASS_SPP } else { done };
        size = size
            .min(target - done)
            .min(passes.max_pass_spp.unwrap_or(u32::MAX).max(1));
        if let Some(limit) = passes.time_limit.filter(|_| done > 0) {
            let per_spp = start.elapsed().as_secs_f64() / f64::from(done);
            let left = limit.as_secs_f64() - start.elapsed().as_secs_f64();
            let fits = (left / per_spp.max(1e-9)).floor().max(1.0);
            size = size.min(fits.min(f64::from(u32::MAX)) as u32);
        }
        let pass_orders = trace_pass(
            stone,
            setup,
            done..done + size,
            &on_stone,
            &mut film.sums,
            &mut film.spectral.data,
        );
        orders.merge(&pass_orders);
        done += size;
        count += 1;
        let elapsed = start.elapsed();
        if let Some(report) = passes.on_pass {
            report(&PassReport {
                passes: count,
                spp: done,
                target_spp: target,
                elapsed_s: elapsed.as_secs_f64(),
                noise: film.noise(&on_stone, done),
            });
        }
        if passes.time_limit.is_some_and(|limit| elapsed >= limit) {
            break;
        }
    }
    let developed = film.develop(done);
    PathImage {
        xyz: developed.xyz,
        spectral: developed.spectral,
        spp: done,
        passes: count,
        half_difference: developed.half_difference,
        variance: developed.variance,
        bragg_orders: Some(orders.report(done, on_stone.iter().filter(|&&on| on).count())),
        on_stone,
    }
}

/// Samples `range` of every pixel, added to its sums and its spectral bins; returns the
/// luminance of the pixels `on_stone` per class of path ([`super::orders`]), summed per row.
fn trace_pass(
    stone: &Stone,
    setup: &PathSetup,
    range: std::ops::Range<u32>,
    on_stone: &[bool],
    sums: &mut [PixelSums],
    spectral: &mut [f32],
) -> OrderSums {
    let w = setup.width;
    let orders = Mutex::new(OrderSums::default());
    let bins = setup.spectral.grid.bins;
    // A stopped pass traces no more rows (its image is never shown).
    let cancel = crate::cancel::Cancel::current();
    sums.par_chunks_mut(w)
        .zip(spectral.par_chunks_mut(w * bins))
        .enumerate()
        .for_each(|(y, (row, row_bins))| {
            if cancel.is_cancelled() {
                return;
            }
            let mut tracer = Tracer::new(stone, setup);
            let mut row_orders = OrderSums::default();
            for (x, px) in row.iter_mut().enumerate() {
                let pixel = (y * w + x) as u64;
                let px_bins = &mut row_bins[x * bins..(x + 1) * bins];
                for s in range.clone() {
                    let mut sampler = PathSampler::new(setup.seed, pixel, s, setup.sampling);
                    let jx = sampler.uniform_f32();
                    let jy = sampler.uniform_f32();
                    let ray = setup.camera.ray(x as f32 + jx, y as f32 + jy);
                    let mut acc = [0.0f64; 3];
                    tracer.sample(ray, &mut sampler, &mut acc, px_bins);
                    px.add(s, &acc);
                    if on_stone[pixel as usize] {
                        row_orders.add_sample(s, &tracer.tally);
                    }
                }
            }
            // Integer sums: the same in any order.
            orders
                .lock()
                .unwrap_or_else(|e| e.into_inner())
                .merge(&row_orders);
        });
    orders.into_inner().unwrap_or_else(|e| e.into_inner())
}

/// Whether each pixel's centre sees the stone.
fn stone_mask(stone: &Stone, setup: &PathSetup) -> Vec<bool> {
    let (w, h) = (setup.width, setup.height);
    (0..w * h)
        .map(|i| {
            let ray = setup.camera.ray((i % w) as f32 + 0.5, (i / w) as f32 + 0.5);
            stone.shape.intersect(&ray).is_some_and(|(t0, _)| t0 > 0.0)
        })
        .collect()
}
