//! Criterion bench: the whole loop on a 10 s, 12 kHz simulated recording.
fn main() {}
