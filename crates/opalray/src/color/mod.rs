//! color stage (being built).
