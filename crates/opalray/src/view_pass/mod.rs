//! view_pass stage (being built).
