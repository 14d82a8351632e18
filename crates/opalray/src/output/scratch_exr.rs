//! scratch EXR stand-ins (replaced by the real writers).
#![allow(missing_docs)]
use std::path::Path;
pub fn write_exr(_p: &Path, _i: &crate::color::RgbImage) -> crate::Result<()> {
    Err(crate::Error::argument("--output", "EXR not in this build"))
}
pub fn write_spectral_exr(_p: &Path, _i: &crate::spectrum::SpectralImage) -> crate::Result<()> {
    Err(crate::Error::argument(
        "--spectral",
        "EXR not in this build",
    ))
}
