//! The evaluation protocols of the chapter tables, over windows of one cell: the dissertation's
//! stratified random split (seeded SplitMix64, Fisher–Yates per class), the time-blocked split,
//! leave one fault size out and leave one condition out, and the evaluation of a list of folds
//! with a chapter classifier (confusions summed, spread over repetitions).

use crate::{ClassifierKind, Result};
use serde::Serialize;

/// Which evaluation protocol produced a table.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Protocol {
    /// The dissertation's: windows pooled, stratified random 75 / 25 split, repeated over seeds.
    RandomWindows,
    /// Each recording's first 75 % of windows train, its last 25 % test (no window is a
    /// neighbour of a test window except at the single cut).
    TimeBlocked,
    /// Train on the other crack sizes, test on this one (no seeded fault shared).
    LeaveOneSizeOut,
    /// Train on the other loads (or speeds), test on this one; with one recording per class and
    /// condition this is the grouped-by-recording protocol.
    LeaveOneConditionOut,
}

impl Protocol {
    /// Short name used in files.
    pub fn key(self) -> &'static str {
        match self {
            Protocol::RandomWindows => "random_windows",
            Protocol::TimeBlocked => "time_blocked",
            Protocol::LeaveOneSizeOut => "leave_one_size_out",
            Protocol::LeaveOneConditionOut => "leave_one_condition_out",
        }
    }
    /// Heading used in Markdown.
    pub fn title(self) -> &'static str {
        match self {
            Protocol::RandomWindows => "dissertation protocol (random 75/25 split of windows)",
            Protocol::TimeBlocked => "time-blocked split (first 75 % of each recording trains)",
            Protocol::LeaveOneSizeOut => "leave one fault size out",
            Protocol::LeaveOneConditionOut => "grouped by recording (leave one load/speed out)",
        }
    }
}

/// The outcome of one cell (one classification problem).
#[derive(Debug, Clone, Serialize)]
pub struct CellOutcome {
    /// Per-class accuracy in percent, in the table's row order (`None`: class absent from test).
    pub per_class: Vec<Option<f64>>,
    /// Average classification accuracy over all test windows (eq. 5.37), percent.
    pub average: f64,
    /// Standard deviation of the average over repetitions (seeds or folds), percent.
    pub spread: Option<f64>,
    /// Confusion matrix summed over repetitions: `confusion[true][predicted]`.
    pub confusion: Vec<Vec<u64>>,
    /// Training windows per repetition.
    pub n_train: usize,
    /// Test windows per repetition.
    pub n_test: usize,
}

/// One window of a cell's dataset: its label, where it sits, and its feature (the energy).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Win {
    /// Class index (the table's row order).
    pub class: usize,
    /// Window index within its recording.
    pub pos: usize,
    /// The recording's window count.
    pub count: usize,
    /// Condition index (load or speed).
    pub cond: usize,
    /// Crack (fault size) index; `None` for the normal class.
    pub crack: Option<usize>,
    /// The window energy (eq. 2.46 / 5.33).
    pub energy: f64,
}

/// Stratified random 75/25 split (per class, Fisher–Yates with a seeded SplitMix64).
pub fn random_split(wins: &[Win], nclass: usize, seed: u64) -> (Vec<Win>, Vec<Win>) {
    let mut rng = close_loop::scenario::SplitMix64::from_state(0x5EED_0000 + seed);
    let (mut train, mut test) = (Vec::new(), Vec::new());
    for c in 0..nclass {
        let mut idx: Vec<usize> = (0..wins.len()).filter(|&i| wins[i].class == c).collect();
        for i in (1..idx.len()).rev() {
            let j = (rng.next_u64() % (i as u64 + 1)) as usize;
            idx.swap(i, j);
        }
        let ntrain = (idx.len() * 3).div_ceil(4);
        for (k, &i) in idx.iter().enumerate() {
            if k < ntrain {
                train.push(wins[i])
            } else {
                test.push(wins[i])
            }
        }
    }
    (train, test)
}

/// First 75 % of each recording's windows train, the rest test.
pub fn time_split(wins: &[Win]) -> (Vec<Win>, Vec<Win>) {
    wins.iter().partition(|w| w.pos * 4 < w.count * 3)
}

/// Train and test each fold; sum the confusions.
pub fn evaluate(
    folds: &[(Vec<Win>, Vec<Win>)],
    nclass: usize,
    clf: ClassifierKind,
) -> Result<CellOutcome> {
    let mut conf = vec![vec![0u64; nclass]; nclass];
    let mut accs = Vec::new();
    let (mut n_train, mut n_test) = (0, 0);
    for (train, test) in folds {
        let xtr: Vec<f64> = train.iter().map(|w| w.energy).collect();
        let ytr: Vec<usize> = train.iter().map(|w| w.class).collect();
        let xte: Vec<f64> = test.iter().map(|w| w.energy).collect();
        let pred = crate::fit_predict(clf, &xtr, &ytr, &xte, nclass)?;
        let mut correct = 0usize;
        for (w, &p) in test.iter().zip(&pred) {
            conf[w.class][p.min(nclass - 1)] += 1;
            if w.class == p {
                correct += 1;
            }
        }
        accs.push(100.0 * correct as f64 / test.len().max(1) as f64);
        n_train = train.len();
        n_test = test.len();
    }
    let per_class = conf
        .iter()
        .enumerate()
        .map(|(i, row)| {
            let n: u64 = row.iter().sum();
            (n > 0).then(|| 100.0 * row[i] as f64 / n as f64)
        })
        .collect();
    let total: u64 = conf.iter().flatten().sum();
    let diag: u64 = (0..nclass).map(|i| conf[i][i]).sum();
    let average = 100.0 * diag as f64 / total.max(1) as f64;
    let spread = (accs.len() > 1).then(|| {
        let m = accs.iter().sum::<f64>() / accs.len() as f64;
        (accs.iter().map(|a| (a - m).powi(2)).sum::<f64>() / (accs.len() - 1) as f64).sqrt()
    });
    Ok(CellOutcome {
        per_class,
        average,
        spread,
        confusion: conf,
        n_train,
        n_test,
    })
}

/// Leave one fault size out: faults of crack `held` test, the other sizes train; the normal
/// class, which has no size, is split in time (its first 75 % of windows train).
pub fn leave_one_size_out(wins: &[Win], held: usize) -> (Vec<Win>, Vec<Win>) {
    let (mut train, mut test) = (Vec::new(), Vec::new());
    for &w in wins {
        match w.crack {
            None => {
                if w.pos * 4 < w.count * 3 {
                    train.push(w)
                } else {
                    test.push(w)
                }
            }
            Some(c) if c == held => test.push(w),
            Some(_) => train.push(w),
        }
    }
    (train, test)
}

/// Leave one condition (load or speed) out: one fold per condition, the held-out one tests.
pub fn leave_one_condition_out(wins: &[Win], nconds: usize) -> Vec<(Vec<Win>, Vec<Win>)> {
    (0..nconds)
        .map(|held| wins.iter().partition(|w| w.cond != held))
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    fn wins() -> Vec<Win> {
        let mut v = Vec::new();
        for class in 0..3 {
            for pos in 0..20 {
                v.push(Win {
                    class,
                    pos,
                    count: 20,
                    cond: pos % 2,
                    crack: (class > 0).then_some(pos % 3),
                    energy: class as f64 + pos as f64 * 0.01,
                });
            }
        }
        v
    }

    #[test]
    fn random_split_is_stratified_seeded_and_disjoint() {
        let w = wins();
        let (tr, te) = random_split(&w, 3, 1);
        assert_eq!(tr.len() + te.len(), w.len());
        for c in 0..3 {
            assert_eq!(tr.iter().filter(|x| x.class == c).count(), 15);
        }
        assert_eq!(random_split(&w, 3, 1), (tr.clone(), te.clone()));
        assert_ne!(random_split(&w, 3, 2).0, tr);
        assert!(te.iter().all(|x| !tr.contains(x)));
    }

    #[test]
    fn time_and_grouped_splits_keep_their_promises() {
        let w = wins();
        let (tr, te) = time_split(&w);
        assert!(tr.iter().all(|x| x.pos < 15) && te.iter().all(|x| x.pos >= 15));
        let (tr, te) = leave_one_size_out(&w, 1);
        assert!(
            te.iter()
                .all(|x| x.crack == Some(1) || (x.crack.is_none() && x.pos >= 15))
        );
        assert!(tr.iter().all(|x| x.crack != Some(1)));
        let folds = leave_one_condition_out(&w, 2);
        assert_eq!(folds.len(), 2);
        for (held, (tr, te)) in folds.iter().enumerate() {
            assert!(te.iter().all(|x| x.cond == held) && tr.iter().all(|x| x.cond != held));
        }
    }
}
