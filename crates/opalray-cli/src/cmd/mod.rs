//! One module per subcommand, plus what they share.

pub mod bench;
pub mod color;
pub mod common;
pub mod deadline;
pub mod frames;
pub mod memory;
pub mod motion;
pub mod render;
pub mod scene;
pub mod spectrum;
pub mod stone_slice;
pub mod structure;
pub mod sweep;
pub mod video;
pub mod work;
