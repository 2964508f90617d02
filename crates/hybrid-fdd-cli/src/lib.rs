//! The `hybrid-fdd` command as a library, so `cargo xtask diagnose`, `calibrate`, `close-loop`
//! and `simulate` run the very same code (xtask keeps only the CWRU batches, `--all-real`):
//! argument types, recording loading (CWRU `.mat` via `bearing-data`, one-column CSV), baseline
//! preparation (decimated with `bearing-data`'s anti-aliasing decimator when its rate is an
//! integer multiple of the recording's), the call into the `diagnosis` crate, and the reports
//! (JSON, Markdown, PNG figure); the closed loop and calibration on one recording
//! ([`close_loop`]), the 5-DOF simulation to CSV ([`simulate`]). No signal processing lives here.

/// `println!` that ignores a closed standard output (`hybrid-fdd simulate … | head`): the
/// files are written either way, and a reader that went away is not an error of the command.
#[macro_export]
macro_rules! say {
    ($($t:tt)*) => {{
        use std::io::Write as _;
        let _ = writeln!(std::io::stdout(), $($t)*);
    }};
}

pub mod close_loop;
pub mod diagnose;
pub mod figure;
pub mod simulate;
pub mod train;
