//! What `--help` promises: the four-multiples form's `bsf` is CWRU's ball-defect rate (twice the
//! textbook ball spin frequency), `--outer-clock` lists every accepted position, the commands
//! are named as the user runs them, and a directory batch states its exit status and `--fs`
//! rule.

use clap::{Args, Command};

fn help<A: Args>(name: &'static str) -> String {
    A::augment_args(Command::new(name))
        .term_width(0)
        .render_long_help()
        .to_string()
}

fn flag<'a>(help: &'a str, flag: &str) -> &'a str {
    let i = help
        .find(&format!("--{flag} "))
        .unwrap_or_else(|| panic!("--{flag}"));
    let rest = &help[i + 2..];
    let end = rest.find("\n  -").map_or(rest.len(), |j| j);
    &rest[..end]
}

#[test]
fn the_bearing_help_says_bsf_is_twice_the_ball_spin() {
    for h in [
        help::<hybrid_fdd_cli::diagnose::Args>("diagnose"),
        help::<hybrid_fdd_cli::close_loop::Args>("close-loop"),
        help::<hybrid_fdd_cli::close_loop::CalibrateArgs>("calibrate"),
    ] {
        let b = flag(&h, "bearing");
        assert!(b.contains("2 × the ball spin frequency"), "{b}");
        assert!(b.contains("bsf=4.7135") && b.contains("2.3567"), "{b}");
    }
}

#[test]
fn outer_clock_help_lists_every_accepted_position() {
    let h = help::<hybrid_fdd_cli::simulate::Args>("simulate");
    let c = flag(&h, "outer-clock");
    for pos in ["3", "6", "9", "12"] {
        assert!(
            c.split(|ch: char| !ch.is_ascii_digit()).any(|w| w == pos),
            "{pos}: {c}"
        );
    }
}

#[test]
fn the_help_names_the_commands_as_the_user_runs_them_and_states_the_batch_rules() {
    let d = help::<hybrid_fdd_cli::diagnose::Args>("diagnose");
    assert!(flag(&d, "baseline").contains("hybrid-fdd calibrate"));
    assert!(flag(&d, "input").contains("non-zero"));
    let fs = flag(&d, "fs");
    assert!(fs.contains("batch") && fs.contains("store no rate"), "{fs}");
    let c = help::<hybrid_fdd_cli::close_loop::Args>("close-loop");
    assert!(flag(&c, "machine").contains("hybrid-fdd calibrate"));
    assert!(flag(&c, "input").contains("hybrid-fdd simulate"));
    let cal = help::<hybrid_fdd_cli::close_loop::CalibrateArgs>("calibrate");
    assert!(flag(&cal, "model").contains("arx-laguerre"));
}
