//! The widest vector instructions the processor has, chosen at run time.
//!
//! The spectral loops of the light and view passes (40 bins and more: deposits, filters,
//! shading sums) vectorise, and AVX2 does each of them in half the instructions of the SSE2
//! that every x86-64 processor has. The portable build cannot assume AVX2, so the hot loops
//! run inside [`widest`], which compiles them a second time for AVX2 (x86-64-v3) and picks
//! that copy where the processor has it. The two copies compute the same numbers: no floating
//! point operation is fused or reordered (Rust never contracts `a * b + c` into an FMA), so
//! the image bytes do not depend on which one ran. `OPALRAY_SIMD=portable` in the
//! environment forces the portable copy (to compare the two, or on a processor that
//! misreports its features).
//!
//! The one exception in the crate to `unsafe_code = "forbid"`: calling a function compiled
//! for instructions the processor may lack is unsafe, and is done here only after the
//! processor was asked (`BENCHMARKS.md` has what it gains).
#![allow(unsafe_code)]

use std::sync::OnceLock;

/// The environment variable that forces the portable code path when set to `portable`.
pub const SIMD_ENV: &str = "OPALRAY_SIMD";

/// Which copy of the hot loops runs on this processor.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Level {
    /// SSE2 (every x86-64), or whatever the target is built for elsewhere.
    Portable,
    /// AVX2 with FMA, BMI and the rest of x86-64-v3.
    X86_64V3,
}

impl Level {
    /// A short name: `portable` or `avx2`.
    pub fn name(self) -> &'static str {
        match self {
            Level::Portable => "portable",
            Level::X86_64V3 => "avx2",
        }
    }
}

/// The level chosen for this process: the widest the processor has, unless
/// `OPALRAY_SIMD=portable`.
pub fn level() -> Level {
    static LEVEL: OnceLock<Level> = OnceLock::new();
    *LEVEL.get_or_init(|| {
        if std::env::var(SIMD_ENV).is_ok_and(|v| v == "portable") {
            return Level::Portable;
        }
        detect()
    })
}

#[cfg(target_arch = "x86_64")]
fn detect() -> Level {
    if is_x86_feature_detected!("avx2")
        && is_x86_feature_detected!("fma")
        && is_x86_feature_detected!("bmi1")
        && is_x86_feature_detected!("bmi2")
        && is_x86_feature_detected!("lzcnt")
        && is_x86_feature_detected!("movbe")
        && is_x86_feature_detected!("f16c")
    {
        Level::X86_64V3
    } else {
        Level::Portable
    }
}

#[cfg(not(target_arch = "x86_64"))]
fn detect() -> Level {
    Level::Portable
}

/// Run `f` compiled for the widest level this processor has. What `f` calls is compiled for
/// that level too only where it is inlined into `f`: the hot functions are `#[inline(always)]`,
/// and so are the closures passed here and to the cell traversal (`#[inline(always)] || …`).
/// Left to the optimiser, a closure that grew past its inlining threshold is compiled apart,
/// for the portable level, and the vector copy quietly runs the portable code.
#[inline(always)]
pub fn widest<R>(f: impl FnOnce() -> R) -> R {
    #[cfg(target_arch = "x86_64")]
    if level() == Level::X86_64V3 {
        // SAFETY: `level` returns `X86_64V3` only where the processor reported every feature
        // that `x86_64_v3` is compiled with.
        return unsafe { x86_64_v3(f) };
    }
    f()
}

/// `f()`, compiled with the x86-64-v3 features.
///
/// # Safety
/// The processor must have every feature enabled here.
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx,avx2,fma,bmi1,bmi2,lzcnt,movbe,f16c,popcnt")]
unsafe fn x86_64_v3<R>(f: impl FnOnce() -> R) -> R {
    f()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn both_copies_compute_the_same_numbers() {
        // A loop that vectorises (multiply-add over bins) and a sequential sum: the AVX2 copy
        // must give the portable copy's bits.
        let a: Vec<f32> = (0..40).map(|k| 0.37 + k as f32 * 0.013).collect();
        let b: Vec<f32> = (0..40).map(|k| 1.9 - k as f32 * 0.021).collect();
        let run = || {
            let mut out = vec![0.25f32; 40];
            for ((o, &x), &y) in out.iter_mut().zip(&a).zip(&b) {
                *o += x * y * 0.7;
            }
            let total: f32 = out.iter().sum();
            (out, total)
        };
        assert_eq!(widest(run), run());
    }
}
