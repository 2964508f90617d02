//! The `hybrid-fdd` command as a library, so `cargo xtask diagnose` runs the very same code:
//! argument types, recording loading (CWRU `.mat` via `bearing-data`, one-column CSV), baseline
//! preparation (decimated with `bearing-data`'s anti-aliasing decimator when its rate is an
//! integer multiple of the recording's), the call into the `diagnosis` crate, and the reports
//! (JSON, Markdown, PNG figure). No signal processing lives here.

pub mod diagnose;
pub mod figure;
