//! Small derivative-free optimisers for the few parameters each effect has: the golden-section
//! search of `laguerre-id` (the workspace's one copy).

pub use laguerre_id::optimize::{INV_PHI, golden_max, golden_min};
