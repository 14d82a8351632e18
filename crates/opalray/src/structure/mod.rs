//! structure stage (being built).
