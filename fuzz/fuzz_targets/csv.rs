//! The spectrum CSV reader and the colour of what it reads: never a panic, and a spectrum
//! it accepts has a colour.

#![no_main]

use std::path::Path;

use libfuzzer_sys::fuzz_target;
use opalray::color::{parse_spectrum_csv, SpectrumColor};
use opalray::scene::Illuminant;

fuzz_target!(|data: &[u8]| {
    let Ok(text) = std::str::from_utf8(data) else {
        return;
    };
    if let Ok(samples) = parse_spectrum_csv(text, Path::new("fuzz.csv")) {
        let emission = SpectrumColor::of_emission(&samples);
        let _ = emission.hex();
        let reflectance = SpectrumColor::of_reflectance(&samples, Illuminant::D65);
        let _ = reflectance.hex();
    }
});
