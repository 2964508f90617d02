//! The README example: a recording with an undeclared 1234.5 Hz pick-up; the loop names it.
use close_loop::scenario::{PhenomenologicalModel, add_noise, add_tone};
use close_loop::{
    BearingSpec, DeclaredFault, DeclaredModel, LoopConfig, OperatingPoint, Signal, close_loop,
};

fn main() -> Result<(), close_loop::CloseLoopError> {
    let fs = 12_000.0;
    let op = OperatingPoint::new(
        1797.0,
        BearingSpec::designated(bearing_model::Bearing::Skf6205),
        DeclaredFault::Outer,
    )?;
    let model = PhenomenologicalModel::default();
    let mut y = model.with_seed(7).simulate(&op, 24_000, fs)?;
    add_tone(&mut y, fs, 1234.5, 0.05, 0.0);
    add_noise(&mut y, 0.01, 1);
    let recording = Signal::new(&y, fs)?; // checked: finite, non-empty, rate > 0
    let out = close_loop(&model, &recording, &op, &LoopConfig::default().check()?)?;
    assert_eq!(out.ledger.effects[0].kind, close_loop::EffectKind::Tone);
    println!("{}", out.ledger.to_markdown("undeclared tone"));
    Ok(())
}
