//! The flags of `diagnose` (and those `train-classifier` shares) and the plan they give.

use std::path::PathBuf;

use anyhow::Context as _;

use super::{BaselineSource, Plan};

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
}

/// The flags `diagnose` and `train-classifier` share: channel, rate, speed, bearing, baseline.
#[derive(clap::Args, Debug, Clone, Default)]
pub struct RecordingFlags {
    /// Channel: of a CWRU `.mat` file DE, FE or BA; of another MAT-file a variable path
    /// (`bearing.gs`), a struct element's `Name` (`vibration_1`) or a last path component, by
    /// default its only vector of at least 1024 samples; of a text file a column name or number
    /// (1 = first; by default `accel`, the only column, or the second of `time,signal`).
    #[arg(long, default_value = "DE")]
    pub channel: String,
    /// Sampling rate, Hz, of recordings that store none (a text file without a time column, a
    /// MAT-file without a scalar rate beside its signal: `fs`, `sr`, `sample_rate`,
    /// `sampling_rate`, `SampleFrequency`, `SamplingFrequency`, `SampleRate`, `freq_sampling`, …,
    /// case and `_` ignored).
    /// A CWRU `.mat` file's rate, a stored rate and a time column's always win: for a single file, a `--fs` more than 0.1 % (`.mat`) or 1 % (time column)
    /// away from it is an error; in a directory batch (and `train-classifier`'s labelled list)
    /// `--fs` applies only to the files that store no rate.
    #[arg(long)]
    pub fs: Option<f64>,
    /// Shaft speed, rpm (when omitted: a CWRU file's stored speed, else its nominal one; the
    /// `rpm` of a `simulate` CSV's JSON sidecar, said on stderr).
    #[arg(long)]
    pub rpm: Option<f64>,
    /// Bearing: a designation from the built-in catalogue (`hybrid-fdd bearings` lists them;
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
        Ok(Plan {
            channel: self.channel.clone(),
            fs: self.fs,
            rpm: self.rpm,
            bearing: crate::parse_bearing(spec)?,
        })
    }

    /// The baseline, when `--baseline` is given.
    ///
    /// # Errors
    /// An unreadable baseline.
    pub fn baseline_source(&self) -> anyhow::Result<Option<BaselineSource>> {
        self.baseline
            .as_deref()
            .map(|p| BaselineSource::load(p, &self.channel, self.fs))
            .transpose()
    }
}
