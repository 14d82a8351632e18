//! The environment-map readers (Radiance `.hdr`, OpenEXR `.exr`): never a panic, never an
//! allocation past the limit; a size read from the header alone is the size of the map read,
//! and a map read has finite, non-negative values, `width × height` of them.
//!
//! The first byte picks the reader (even: `.hdr`, odd: `.exr`); the rest is the file.

#![no_main]

use libfuzzer_sys::fuzz_target;
use opalray::lights::env_map::{map_size, read_map, MAX_MAP_PIXELS, MAX_MAP_SIDE};

fuzz_target!(|data: &[u8]| {
    let Some((&pick, file)) = data.split_first() else {
        return;
    };
    let ext = if pick % 2 == 0 { "hdr" } else { "exr" };
    let path = std::env::temp_dir().join(format!("opalray-fuzz-{}.{ext}", std::process::id()));
    std::fs::write(&path, file).unwrap();
    let size = map_size(&path);
    if let Ok(map) = read_map(&path) {
        assert_eq!(size, Ok((map.width, map.height)), "header and map disagree");
        assert!(map.width <= MAX_MAP_SIDE && map.height <= MAX_MAP_SIDE);
        assert!((map.width * map.height) as u64 <= MAX_MAP_PIXELS);
        assert_eq!(map.luminance.len(), map.width * map.height);
        assert!(map.luminance.iter().all(|y| y.is_finite() && *y >= 0.0));
    }
    let _ = std::fs::remove_file(&path);
});
