//! The flags of `diagnose` (and those `train-classifier` shares) and the plan they give.

use std::path::PathBuf;

use anyhow::Context as _;

use super::{BaselineSource, Plan};
use crate::flags::SignalFlags;

/// Flags of `diagnose`.
#[derive(clap::Args, Debug, Clone, Default)]
// a negative --rpm or --fs gets the range error, not "unexpected argument"
#[command(allow_negative_numbers = true)]
pub struct Args {
    /// Recording: a CWRU `.mat` file (named by its number, e.g. `130.mat`), any other MAT-file
    /// (v5–v7, the signal at the top level or inside structs and cells: MFPT's `bearing.gs`,
    /// Paderborn's `X.Y(k).Data`), a delimited text file (`.csv`, `.tsv`, `.txt`, or any name
    /// whose content is text, such as IMS's date-named files), or a directory: every
    /// `.mat`/`.csv`/`.tsv` in it (and every MAT or text file named without an extension or with
    /// an all-digit one, as IMS's) is diagnosed, in parallel, one report per file (named by its
    /// stem; by stem and extension, `x_csv.json`, when two files share a stem)
    /// and `summary.csv` listing each file's report; the exit status is non-zero when any file
    /// failed (after all reports and the summary are written).
    #[arg(long)]
    pub input: Option<PathBuf>,
    /// How the recordings are read and what machine they come from.
    #[command(flatten)]
    pub recording: RecordingFlags,
    /// JSON report path (Markdown and PNG beside it); with a directory input, an output directory.
    #[arg(long)]
    pub report: Option<PathBuf>,
    /// Optional trained classifier (`hybrid-fdd train-classifier`'s JSON): its class is added
    /// to the report under `"classifier"` beside the training-free verdict.
    #[arg(long)]
    pub classifier: Option<PathBuf>,
    /// Tachometer channel recorded beside the vibration in the same file (a column name or
    /// number of a text file, a MAT-file variable): its pulses give the shaft's angle, and the
    /// recording is resampled at equal shaft angles (computed order tracking) before it is
    /// diagnosed at its mean speed — for a speed that changes during the recording (a run-up,
    /// a coast-down, a variable-speed drive), whose fault lines would otherwise smear. `--rpm`,
    /// `--rpm-range` and `--baseline` are then refused: the tachometer measures the speed, and a
    /// baseline would need the same tracking. Without `--tach` a self-referenced recording whose
    /// speed changes is tracked along its own shaft comb where it holds one.
    #[arg(long)]
    pub tach: Option<String>,
    /// Pulses per shaft turn of `--tach` (an encoder's lines; 1 for a once-per-turn key).
    #[arg(long, default_value_t = 1.0)]
    pub pulses_per_rev: f64,
}

/// The flags `diagnose` and `train-classifier` share: channel and rate ([`SignalFlags`], which
/// `close-loop` and `calibrate` share too), speed, false-alarm level, bearing, baseline.
#[derive(clap::Args, Debug, Clone, Default)]
pub struct RecordingFlags {
    /// Channel and sampling rate (as `close-loop` and `calibrate` read them).
    #[command(flatten)]
    pub signal: SignalFlags,
    /// Shaft speed, rpm, as declared (a set point, a nameplate): the running speed is searched
    /// within ± 10 % of it in the recording's shaft comb (when omitted: a CWRU file's stored
    /// speed, else its nominal one; the `rpm` of a `simulate` CSV's JSON sidecar, said on
    /// stderr; or none, with `--rpm-range`).
    #[arg(long)]
    pub rpm: Option<f64>,
    /// Range the running speed is searched in, rpm, `LOW-HIGH` (e.g. `300-3600`): instead of
    /// ± 10 % of `--rpm`, or without any declared speed. A range wider than 1.25 : 1 needs the
    /// recording's own shaft comb to be found.
    #[arg(long, value_name = "LOW-HIGH")]
    pub rpm_range: Option<String>,
    /// False-alarm probability per recording (α): a healthy machine is called faulty at most
    /// this often (each of the three faults is tested at a third of it).
    #[arg(long, default_value_t = diagnosis::DEFAULT_FALSE_ALARM)]
    pub alpha: f64,
    /// Read the recording at one speed only: never order-track it along its own shaft comb
    /// (by default a self-referenced recording with no shaft comb over its whole length, whose
    /// comb frame by frame shows the speed changing, is order-tracked). For a machine known to
    /// run at one speed, or to compare the two readings.
    #[arg(long)]
    pub steady_speed: bool,
    /// Bearing: `unknown` (the fault's order is found from the envelope's non-integer combs and
    /// its kind from their sidebands; the report says it guessed), a designation from the
    /// built-in catalogue (`hybrid-fdd bearings` lists them;
    /// case-insensitive, a maker's name and seal or clearance suffixes ignored: `6205`, `SKF
    /// 6205-2RS`, `uc204`, `ZA-2115`, `ER-16K`), a geometry `n=9,d=0.3126in,D=1.537in,angle=0deg`
    /// or the four shaft-rate multiples `bpfo=3.5848,bpfi=5.4152,ftf=0.39828,bsf=4.7135` (the
    /// 6205's). There
    /// `bsf` is CWRU's ball-defect rate = 2 × the ball spin frequency: a textbook BSF must be
    /// doubled (the 6205's textbook BSF is 2.3567; CWRU's `bsf` is 4.7135).
    #[arg(long)]
    pub bearing: Option<String>,
    /// Healthy recording of the same machine (same formats; resampled by an integer factor
    /// with an anti-aliasing FIR when its rate is a multiple of the recording's; energy and
    /// kurtosis are then compared below the filter's passband edge), or a machine
    /// model JSON from `hybrid-fdd calibrate` (or `cargo xtask calibrate`; its whole model is the
    /// healthy model, and a recording synthesised from it at the recording's speed gives the
    /// healthy envelope lines; same sampling rate and units as the recording). A text baseline
    /// without a time column is taken at `--fs`; a `.mat` baseline or one with a time column at
    /// its own rate. Without a baseline the evidence is self-referenced.
    #[arg(long)]
    pub baseline: Option<PathBuf>,
}

impl RecordingFlags {
    /// The plan these flags give (the bearing is required).
    ///
    /// # Errors
    /// A missing or unparsable `--bearing`.
    pub fn plan(&self) -> anyhow::Result<Plan> {
        let spec = self
            .bearing
            .as_deref()
            .context(
                "--bearing is required (a designation such as 6205 or UC204, listed by `hybrid-fdd bearings`; a geometry n=…,d=…,D=…[,angle=…]; or the four multiples)",
            )?;
        let bearing = if spec.trim().eq_ignore_ascii_case(super::UNKNOWN_BEARING) {
            super::unknown_bearing()
        } else {
            crate::parse_bearing(spec)?
        };
        Ok(Plan {
            channel: self.signal.channel.clone(),
            fs: self.signal.fs,
            rpm: self.rpm,
            bearing,
        })
    }

    /// The speed range and false-alarm level these flags give.
    ///
    /// # Errors
    /// A `--rpm-range` that is not `LOW-HIGH` with two numbers.
    pub fn search(&self) -> anyhow::Result<super::Search> {
        let rpm_range = self
            .rpm_range
            .as_deref()
            .map(|r| {
                let (lo, hi) = r
                    .split_once('-')
                    .context("--rpm-range must be LOW-HIGH in rpm, e.g. 300-3600")?;
                let num = |v: &str| {
                    v.trim()
                        .parse::<f64>()
                        .with_context(|| format!("--rpm-range {r}: {v:?} is not a number"))
                };
                Ok::<_, anyhow::Error>([num(lo)?, num(hi)?])
            })
            .transpose()?;
        Ok(super::Search {
            rpm_range,
            false_alarm: self.alpha,
            steady_speed: self.steady_speed,
        })
    }

    /// The baseline, when `--baseline` is given.
    ///
    /// # Errors
    /// An unreadable baseline.
    pub fn baseline_source(&self) -> anyhow::Result<Option<BaselineSource>> {
        self.baseline
            .as_deref()
            .map(|p| BaselineSource::load(p, &self.signal.channel, self.signal.fs))
            .transpose()
    }
}
