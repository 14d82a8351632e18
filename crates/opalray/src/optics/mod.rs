//! optics stage (being built).
