//! light_pass stage (being built).
