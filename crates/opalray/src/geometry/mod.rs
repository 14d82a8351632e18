//! geometry stage (being built).
