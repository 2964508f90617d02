//! A run does not depend on the number of threads: a round's candidate families are evaluated
//! in parallel (rayon) and collected in a fixed order, and the simulation memo they share only
//! saves work. The same record through the loop on one thread and on three gives the same
//! ledger and machine model, to the bit (their JSON compared).

use close_loop::physics::PhysicsModel;
use close_loop::scenario::{add_noise, add_tone};
use close_loop::{BearingSpec, DeclaredFault, DeclaredModel, LoopConfig, OperatingPoint};

#[test]
fn one_thread_and_three_give_the_same_run() {
    const FS: f64 = 12_000.0;
    let op = OperatingPoint::new(
        1772.0,
        BearingSpec::designated(bearing_model::Bearing::Skf6205),
        DeclaredFault::Outer,
    )
    .unwrap();
    // a record the declared model does not explain: another seed and spall, a tone, a mode-free
    // noise floor — so several families offer candidates in several rounds
    let truth = PhysicsModel {
        seed: 17,
        fault_size_in: 0.014,
        ..PhysicsModel::default()
    };
    let mut y = truth.simulate(&op, 36_000, FS).unwrap();
    let a = close_loop::metric::rms(&y);
    add_tone(&mut y, FS, 987.6, 0.3 * a, 0.4);
    add_noise(&mut y, 0.05 * a, 5);
    let cfg = LoopConfig {
        max_effects: 4,
        ..LoopConfig::default()
    }
    .check()
    .unwrap();
    let run = |threads: usize| {
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .unwrap();
        let o = pool
            .install(|| close_loop::close_loop(&PhysicsModel::default(), &sig(&y, FS), &op, &cfg))
            .unwrap();
        (
            serde_json::to_string(&o.ledger).unwrap(),
            serde_json::to_string(&o.machine).unwrap(),
            o.ledger.effects.len(),
        )
    };
    let (one, three) = (run(1), run(3));
    assert!(one.2 >= 1, "the record should make the loop add something");
    assert_eq!(one.0, three.0, "ledgers differ");
    assert_eq!(one.1, three.1, "machine models differ");
}

/// `y` at `fs` Hz as a checked signal (the recordings here are finite and non-empty).
fn sig(y: &[f64], fs: f64) -> close_loop::Signal<'_> {
    close_loop::Signal::new(y, fs).unwrap()
}
