//! Evaluation protocols: which windows train and which test.
//!
//! Five named protocols (see the project references, "How honest is a CWRU accuracy?"):
//! 1. [`random_window_split`]: stratified random 75/25 split of windows over several seeds — the
//!    dissertation's protocol (windows of one recording land on both sides);
//! 2. [`time_blocked`]: each recording's first 75 % of windows train, its last 25 % test — still
//!    every recording on both sides, but no test window is interleaved with training windows;
//! 3. [`grouped_by_recording`]: stratified k-fold over recordings — no recording on both sides;
//! 4. [`leave_one_condition_out`] ([`leave_one_load_out`]): train on the other loads (or speeds),
//!    test on one;
//! 5. [`leave_one_fault_size_out`]: train on the other crack sizes, test on one — the split that
//!    shares no seeded bearing between training and test.
//!
//! Randomness is one generator, SplitMix64 (`rand_xoshiro`, the rust-random project's; chosen
//! because its stream is specified bit for bit and also drives the closed loop's noise), with an
//! explicit Fisher–Yates shuffle (`j = next_u64 mod (i + 1)`), so a split is reproducible from
//! its seed in any language.
//!
//! A class that cannot be held out under a grouped protocol (it has a single value of the grouping
//! key — e.g. CWRU's single normal recording 97, or the normal class under leave-one-fault-size-out,
//! whose fault size is `None`) is *degenerate*; what happens to it is chosen explicitly by
//! [`DegenerateClassPolicy`] and always written into [`SplitPlan::notes`], and the recordings it
//! puts on both sides are listed in [`SplitPlan::time_split_recordings`]. No protocol leaks silently.

use std::collections::{BTreeMap, BTreeSet};
use std::fmt;

use rand::{RngCore, SeedableRng};
use rand_xoshiro::SplitMix64;
use serde::{Deserialize, Serialize};

use crate::dataset::{Dataset, WindowMeta};
use crate::error::{ClassifyError, Result};

/// The protocol a [`SplitPlan`] was made with.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
pub enum Protocol {
    /// Stratified random split of windows (the dissertation's).
    RandomWindows,
    /// Stratified k-fold over recordings.
    GroupedByRecording,
    /// Leave one motor load out.
    LeaveOneLoadOut,
    /// Leave one fault size out.
    LeaveOneFaultSizeOut,
    /// Each recording's early windows train, its late windows test.
    TimeBlocked,
    /// Leave one shaft speed out.
    LeaveOneSpeedOut,
}

/// The operating condition [`leave_one_condition_out`] groups by.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
pub enum OperatingCondition {
    /// Motor load ([`WindowMeta::load_hp`]).
    Load,
    /// Shaft speed ([`WindowMeta::speed_rpm`]; every window must carry one).
    Speed,
}

/// The stream offset of [`random_window_split`]: seed `s` starts SplitMix64 at state
/// `RANDOM_SPLIT_STREAM + s`.
pub const RANDOM_SPLIT_STREAM: u64 = 0x5EED_0000;

/// Fisher–Yates shuffle with `j = next_u64 mod (i + 1)` (the bias of the modulo is below
/// 2⁻⁴⁰ for any dataset that fits in memory).
fn shuffle<T>(v: &mut [T], rng: &mut SplitMix64) {
    for i in (1..v.len()).rev() {
        let j = (rng.next_u64() % (i as u64 + 1)) as usize;
        v.swap(i, j);
    }
}

impl fmt::Display for Protocol {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(match self {
            Protocol::RandomWindows => "random window split (stratified, the dissertation's)",
            Protocol::GroupedByRecording => "grouped by recording",
            Protocol::LeaveOneLoadOut => "leave one load out",
            Protocol::LeaveOneFaultSizeOut => "leave one fault size out",
            Protocol::TimeBlocked => "time-blocked (early windows train, late windows test)",
            Protocol::LeaveOneSpeedOut => "leave one speed out",
        })
    }
}

/// One train/test split.
#[derive(Debug, Clone, PartialEq, Eq, Serialize, Deserialize)]
pub struct Fold {
    /// Human-readable name ("seed 3", "test load 2 hp", …).
    pub name: String,
    /// Training window indices, ascending.
    pub train: Vec<usize>,
    /// Test window indices, ascending.
    pub test: Vec<usize>,
}

/// Folds plus the caveats of applying the protocol to this dataset.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct SplitPlan {
    /// Which protocol.
    pub protocol: Protocol,
    /// The folds.
    pub folds: Vec<Fold>,
    /// Caveats, in plain words; print them with the results.
    pub notes: Vec<String>,
    /// Recordings deliberately split in time (train first, test last) because their class is
    /// degenerate under the protocol; always empty under [`DegenerateClassPolicy::TrainOnly`].
    pub time_split_recordings: Vec<String>,
}

/// What to do with a class that has a single value of the grouping key.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub enum DegenerateClassPolicy {
    /// In every fold, the first `1 − test_fraction` of each of its recordings' windows (in time)
    /// train and the rest test. The recording is then on both sides; the plan says so.
    SplitInTime {
        /// Fraction of each recording's windows (the last ones) used for testing, in (0, 1).
        test_fraction: f64,
    },
    /// Its windows always train and are never tested; its accuracy is not measured.
    TrainOnly,
}

impl Default for DegenerateClassPolicy {
    fn default() -> Self {
        Self::SplitInTime {
            test_fraction: 0.25,
        }
    }
}

/// Settings of [`random_window_split`].
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct RandomSplitConfig {
    /// Fraction of each class's windows used for testing, in (0, 1). Default 0.25.
    pub test_fraction: f64,
    /// One fold per seed (SplitMix64 from [`RANDOM_SPLIT_STREAM`] + seed). Default 0..10.
    pub seeds: Vec<u64>,
}

impl Default for RandomSplitConfig {
    fn default() -> Self {
        Self {
            test_fraction: 0.25,
            seeds: (0..10).collect(),
        }
    }
}

/// Settings of [`grouped_by_recording`].
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct GroupedConfig {
    /// Number of folds (≥ 2).
    pub folds: usize,
    /// Seed for assigning recordings to folds.
    pub seed: u64,
    /// Treatment of classes with a single recording.
    pub degenerate: DegenerateClassPolicy,
}

impl Default for GroupedConfig {
    fn default() -> Self {
        Self {
            folds: 4,
            seed: 0,
            degenerate: DegenerateClassPolicy::default(),
        }
    }
}

fn check_fraction(name: &'static str, f: f64) -> Result<()> {
    if f.is_finite() && f > 0.0 && f < 1.0 {
        Ok(())
    } else {
        Err(ClassifyError::InvalidParameter {
            name,
            value: f,
            reason: "must lie in (0, 1)",
        })
    }
}

/// Number of test items out of `n`: `n − ⌈(1 − fraction)·n⌉` (the training side gets the
/// rounding, as in the dissertation's 75/25 split), at least 1 and at most `n − 1` when `n ≥ 2`.
fn n_test(n: usize, fraction: f64) -> usize {
    if n < 2 {
        return 0;
    }
    // The tolerance keeps an exact product (0.75 · 400) from rounding up by one ulp.
    let n_train = ((1.0 - fraction) * n as f64 - 1e-9).ceil() as usize;
    n.saturating_sub(n_train).clamp(1, n - 1)
}

/// Protocol 1: stratified random split of windows, one fold per seed.
///
/// # Errors
/// Invalid fraction, no seeds.
pub fn random_window_split(data: &Dataset, config: &RandomSplitConfig) -> Result<SplitPlan> {
    check_fraction("test_fraction", config.test_fraction)?;
    if config.seeds.is_empty() {
        return Err(ClassifyError::Empty { what: "seeds" });
    }
    let mut by_class: Vec<Vec<usize>> = vec![Vec::new(); data.n_classes()];
    for (i, m) in data.meta().iter().enumerate() {
        by_class[m.class].push(i);
    }
    let mut notes = vec![
        "windows of the same recording fall on both sides of the split (the dissertation's \
         protocol); neighbouring windows are not independent, so this accuracy is optimistic"
            .to_string(),
    ];
    for (c, idx) in by_class.iter().enumerate() {
        if idx.len() == 1 {
            notes.push(format!(
                "class {} has a single window: it is only used for training",
                data.class_names()[c]
            ));
        }
    }
    let mut folds = Vec::new();
    for &seed in &config.seeds {
        let mut rng = SplitMix64::seed_from_u64(RANDOM_SPLIT_STREAM.wrapping_add(seed));
        let (mut train, mut test) = (Vec::new(), Vec::new());
        for idx in &by_class {
            let mut shuffled = idx.clone();
            shuffle(&mut shuffled, &mut rng);
            let k = n_test(idx.len(), config.test_fraction);
            let cut = idx.len() - k;
            train.extend_from_slice(&shuffled[..cut]);
            test.extend_from_slice(&shuffled[cut..]);
        }
        train.sort_unstable();
        test.sort_unstable();
        folds.push(Fold {
            name: format!("seed {seed}"),
            train,
            test,
        });
    }
    finish(data, Protocol::RandomWindows, folds, notes, Vec::new())
}

/// Generic grouped protocol: fold `v` tests the windows whose key equals `v`.
fn grouped<K: Ord + Clone>(
    data: &Dataset,
    protocol: Protocol,
    key: impl Fn(&WindowMeta) -> K,
    fold_keys: &[(K, String)],
    key_label: &str,
    policy: DegenerateClassPolicy,
    mut notes: Vec<String>,
) -> Result<SplitPlan> {
    if let DegenerateClassPolicy::SplitInTime { test_fraction } = policy {
        check_fraction("test_fraction", test_fraction)?;
    }
    let names = data.class_names();
    // Distinct key values per class.
    let mut class_keys: Vec<BTreeSet<K>> = vec![BTreeSet::new(); data.n_classes()];
    for m in data.meta() {
        class_keys[m.class].insert(key(m));
    }
    let degenerate: Vec<bool> = class_keys.iter().map(|s| s.len() == 1).collect();
    // Time split of degenerate classes' recordings.
    let mut time_test: BTreeSet<usize> = BTreeSet::new();
    let mut time_split_recordings = Vec::new();
    for (c, &deg) in degenerate.iter().enumerate() {
        if !deg {
            continue;
        }
        let mut recs: BTreeMap<&str, Vec<(usize, usize)>> = BTreeMap::new();
        for (i, m) in data.meta().iter().enumerate() {
            if m.class == c {
                recs.entry(&m.recording)
                    .or_default()
                    .push((m.index_in_recording, i));
            }
        }
        let rec_names: Vec<&str> = recs.keys().copied().collect();
        match policy {
            DegenerateClassPolicy::SplitInTime { test_fraction } => {
                for (rec, mut w) in recs {
                    w.sort_unstable();
                    let k = n_test(w.len(), test_fraction);
                    time_test.extend(w[w.len() - k..].iter().map(|&(_, i)| i));
                    time_split_recordings.push(rec.to_string());
                }
                notes.push(format!(
                    "class {} has a single {key_label} and cannot be held out: in every fold the \
                     last {:.0} % of the windows of recording(s) {} test and the earlier ones \
                     train (same recording on both sides; its accuracy is optimistic)",
                    names[c],
                    100.0 * test_fraction,
                    rec_names.join(", ")
                ));
            }
            DegenerateClassPolicy::TrainOnly => notes.push(format!(
                "class {} has a single {key_label} and cannot be held out: its windows \
                 (recording(s) {}) only train and its accuracy is not measured",
                names[c],
                rec_names.join(", ")
            )),
        }
    }
    let mut folds = Vec::new();
    for (v, label) in fold_keys {
        let (mut train, mut test) = (Vec::new(), Vec::new());
        for (i, m) in data.meta().iter().enumerate() {
            let to_test = if degenerate[m.class] {
                time_test.contains(&i)
            } else {
                key(m) == *v
            };
            if to_test {
                test.push(i);
            } else {
                train.push(i);
            }
        }
        for (c, keys) in class_keys.iter().enumerate() {
            if !degenerate[c] && !keys.contains(v) {
                notes.push(format!(
                    "{label}: class {} has no windows with this {key_label}; not tested in this fold",
                    names[c]
                ));
            }
        }
        folds.push(Fold {
            name: label.clone(),
            train,
            test,
        });
    }
    finish(data, protocol, folds, notes, time_split_recordings)
}

/// Drop folds that cannot be scored, with a note; error if none is left.
fn finish(
    data: &Dataset,
    protocol: Protocol,
    folds: Vec<Fold>,
    mut notes: Vec<String>,
    time_split_recordings: Vec<String>,
) -> Result<SplitPlan> {
    let mut kept = Vec::new();
    for f in folds {
        let classes: BTreeSet<usize> = f.train.iter().map(|&i| data.label(i)).collect();
        if f.test.is_empty() {
            notes.push(format!("{}: no test windows; fold dropped", f.name));
        } else if classes.len() < 2 {
            notes.push(format!(
                "{}: fewer than two classes to train on; fold dropped",
                f.name
            ));
        } else {
            kept.push(f);
        }
    }
    if kept.is_empty() {
        return Err(ClassifyError::Empty {
            what: "folds (the protocol cannot be applied to this dataset)",
        });
    }
    Ok(SplitPlan {
        protocol,
        folds: kept,
        notes,
        time_split_recordings,
    })
}

/// Protocol 3: stratified k-fold over recordings. Each class's recordings (sorted by id, then
/// shuffled with `seed`) are dealt to the folds in turn, so no recording has windows in both the
/// training and the test side of a fold (except degenerate classes, see [`DegenerateClassPolicy`]).
///
/// # Errors
/// `folds < 2`, invalid policy fraction, no usable fold.
pub fn grouped_by_recording(data: &Dataset, config: &GroupedConfig) -> Result<SplitPlan> {
    if config.folds < 2 {
        return Err(ClassifyError::InvalidParameter {
            name: "folds",
            value: config.folds as f64,
            reason: "must be >= 2",
        });
    }
    let mut rng = SplitMix64::seed_from_u64(config.seed);
    let mut recs: Vec<BTreeSet<&str>> = vec![BTreeSet::new(); data.n_classes()];
    for m in data.meta() {
        recs[m.class].insert(&m.recording);
    }
    let mut fold_of: BTreeMap<(usize, String), usize> = BTreeMap::new();
    let mut notes = Vec::new();
    for (c, set) in recs.iter().enumerate() {
        let mut list: Vec<&str> = set.iter().copied().collect();
        shuffle(&mut list, &mut rng);
        for (k, r) in list.iter().enumerate() {
            fold_of.insert((c, (*r).to_string()), k % config.folds);
        }
        if list.len() >= 2 && list.len() < config.folds {
            notes.push(format!(
                "class {} has {} recordings for {} folds: it is tested in {} folds only",
                data.class_names()[c],
                list.len(),
                config.folds,
                list.len()
            ));
        }
    }
    let keys: Vec<(usize, String)> = (0..config.folds)
        .map(|k| (k, format!("fold {}/{}", k + 1, config.folds)))
        .collect();
    grouped(
        data,
        Protocol::GroupedByRecording,
        |m| fold_of[&(m.class, m.recording.clone())],
        &keys,
        "recording",
        config.degenerate,
        notes,
    )
}

/// Protocol 2: every recording's first `1 − test_fraction` of windows (in time, by
/// [`WindowMeta::index_in_recording`]) train and the rest test; one fold. Every recording is on
/// both sides, but only at the single cut is a test window a neighbour of a training window.
///
/// # Errors
/// Invalid fraction, no usable fold.
pub fn time_blocked(data: &Dataset, test_fraction: f64) -> Result<SplitPlan> {
    check_fraction("test_fraction", test_fraction)?;
    let mut recs: BTreeMap<(usize, &str), Vec<(usize, usize)>> = BTreeMap::new();
    for (i, m) in data.meta().iter().enumerate() {
        recs.entry((m.class, &m.recording))
            .or_default()
            .push((m.index_in_recording, i));
    }
    let (mut train, mut test) = (Vec::new(), Vec::new());
    for (_, mut w) in recs {
        w.sort_unstable();
        let cut = w.len() - n_test(w.len(), test_fraction);
        train.extend(w[..cut].iter().map(|&(_, i)| i));
        test.extend(w[cut..].iter().map(|&(_, i)| i));
    }
    train.sort_unstable();
    test.sort_unstable();
    let notes = vec![format!(
        "every recording is on both sides: its first {:.0} % of windows train and its last {:.0} % \
         test (not interleaved, but the same recording and bearing)",
        100.0 * (1.0 - test_fraction),
        100.0 * test_fraction
    )];
    finish(
        data,
        Protocol::TimeBlocked,
        vec![Fold {
            name: "time-blocked".into(),
            train,
            test,
        }],
        notes,
        Vec::new(),
    )
}

/// Protocol 4: one fold per value of the operating condition present (load or speed); train on
/// the other values, test on this one. A seeded bearing recorded at several conditions is on both
/// sides (CWRU uses one seeded bearing per fault at all loads), so this still shares the bearing.
///
/// # Errors
/// A window without a speed under [`OperatingCondition::Speed`], invalid policy fraction, fewer
/// than two values, no usable fold.
pub fn leave_one_condition_out(
    data: &Dataset,
    condition: OperatingCondition,
    policy: DegenerateClassPolicy,
) -> Result<SplitPlan> {
    let value = |m: &WindowMeta| match condition {
        OperatingCondition::Load => Some(m.load_hp),
        OperatingCondition::Speed => m.speed_rpm,
    };
    if let Some(i) = data.meta().iter().position(|m| value(m).is_none()) {
        return Err(ClassifyError::InvalidParameter {
            name: "speed_rpm",
            value: i as f64,
            reason: "leave-one-speed-out needs the speed of every window (this row has none)",
        });
    }
    let values: BTreeSet<u32> = data.meta().iter().filter_map(value).collect();
    let (label, unit, protocol) = match condition {
        OperatingCondition::Load => ("load", "hp", Protocol::LeaveOneLoadOut),
        OperatingCondition::Speed => ("speed", "rpm", Protocol::LeaveOneSpeedOut),
    };
    if values.len() < 2 {
        return Err(ClassifyError::InvalidParameter {
            name: label,
            value: values.len() as f64,
            reason: "leaving one condition out needs at least two values of it",
        });
    }
    let keys: Vec<(Option<u32>, String)> = values
        .iter()
        .map(|&v| (Some(v), format!("test {label} {v} {unit}")))
        .collect();
    let notes = vec![format!(
        "a seeded bearing recorded at several {label}s appears on both sides, so training and \
         test share bearings"
    )];
    grouped(data, protocol, value, &keys, label, policy, notes)
}

/// Protocol 4 on loads: [`leave_one_condition_out`] with [`OperatingCondition::Load`].
///
/// # Errors
/// As [`leave_one_condition_out`].
pub fn leave_one_load_out(data: &Dataset, policy: DegenerateClassPolicy) -> Result<SplitPlan> {
    leave_one_condition_out(data, OperatingCondition::Load, policy)
}

/// Protocol 5: one fold per fault size present among faulty windows; train on the other sizes,
/// test on this one. Normal windows (fault size `None`) form a degenerate class, handled by
/// `policy` (default: split in time, first 75 % train, last 25 % test, with a note).
///
/// # Errors
/// Invalid policy fraction, fewer than two fault sizes, no usable fold.
pub fn leave_one_fault_size_out(
    data: &Dataset,
    policy: DegenerateClassPolicy,
) -> Result<SplitPlan> {
    let sizes: BTreeSet<u32> = data
        .meta()
        .iter()
        .filter_map(|m| m.fault_size_mils)
        .collect();
    if sizes.len() < 2 {
        return Err(ClassifyError::InvalidParameter {
            name: "fault sizes",
            value: sizes.len() as f64,
            reason: "leave-one-fault-size-out needs at least two fault sizes",
        });
    }
    let keys: Vec<(Option<u32>, String)> = sizes
        .iter()
        .map(|&s| (Some(s), format!("test fault size 0.{s:03} in")))
        .collect();
    grouped(
        data,
        Protocol::LeaveOneFaultSizeOut,
        |m| m.fault_size_mils,
        &keys,
        "fault size",
        policy,
        Vec::new(),
    )
}
