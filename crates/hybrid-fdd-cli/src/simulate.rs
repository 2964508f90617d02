//! `hybrid-fdd simulate` (and `cargo xtask simulate`): run the 5-DOF bearing model (crate `bearing-model`) and write a CSV
//! recording: one header row, `time_s,accel` (housing acceleration in m/s²), plus all ten
//! states with `--states`. A JSON sidecar (`<out>.json`) records every parameter used.

use anyhow::Context as _;
use bearing_model::{
    Bearing, FaultClass, FaultSet, Noise, ParamSet, Scenario, SimConfig, Slip, Spall,
    scenario::CWRU_DEPTH_M,
};
use std::io::Write;
use std::path::{Path, PathBuf};

/// Flags of this task.
#[derive(clap::Args, Debug)]
pub struct Args {
    /// Fault class: none|inner|outer|ball|inner+outer|inner+ball|outer+ball|inner+outer+ball.
    #[arg(long, default_value = "none")]
    pub fault: String,
    /// Shaft speed, rpm (> 0).
    #[arg(long, allow_negative_numbers = true, default_value_t = 1797.0)]
    pub rpm: f64,
    /// Output sampling rate, Hz.
    #[arg(long, allow_negative_numbers = true, default_value_t = 12_000.0)]
    pub fs: f64,
    /// Duration, s.
    #[arg(long, allow_negative_numbers = true, default_value_t = 1.0)]
    pub duration: f64,
    /// Seed of slip, parameter uncertainty and noise.
    #[arg(long, default_value_t = 0)]
    pub seed: u64,
    /// Parameter set: cwru (physically consistent CWRU rig) | table2.1 (dissertation, as printed).
    #[arg(long, default_value = "cwru")]
    pub params: String,
    /// Bearing: 6205 (CWRU drive end) | 6203 (fan end).
    #[arg(long, default_value = "6205")]
    pub bearing: String,
    /// Spall width (circumferential), mm. CWRU: 0.178 / 0.356 / 0.533 (0.007/0.014/0.021 in).
    #[arg(long, allow_negative_numbers = true, default_value_t = 0.1778)]
    pub fault_size: f64,
    /// Spall depth, mm (CWRU EDM depth 0.011 in = 0.2794 mm).
    #[arg(long, allow_negative_numbers = true, default_value_t = CWRU_DEPTH_M * 1e3)]
    pub fault_depth: f64,
    /// Random ball slip as a fraction of the ball spacing (0 = off).
    #[arg(long, allow_negative_numbers = true, default_value_t = 0.01)]
    pub slip: f64,
    /// Measurement noise as SNR in dB (omit for no noise).
    #[arg(long, allow_negative_numbers = true)]
    pub snr_db: Option<f64>,
    /// Constant radial load on the shaft, N (down).
    #[arg(long, allow_negative_numbers = true, default_value_t = 0.0)]
    pub radial_load: f64,
    /// Housing resonance, Hz (default: the parameter set's, 3300 Hz).
    #[arg(long, allow_negative_numbers = true)]
    pub resonance: Option<f64>,
    /// Fault onset time T_f, s (default: present from the start).
    #[arg(long, allow_negative_numbers = true)]
    pub onset: Option<f64>,
    /// Largest internal RK4 step, s.
    #[arg(long, allow_negative_numbers = true, default_value_t = SimConfig::DEFAULT_MAX_STEP)]
    pub max_step: f64,
    /// Also write all ten states (m, m/s) as columns.
    #[arg(long)]
    pub states: bool,
    /// Output CSV path.
    #[arg(long)]
    pub out: PathBuf,
}

const STATE_NAMES: [&str; 10] = [
    "xs_m", "ys_m", "xp_m", "yp_m", "yr_m", "vxs_m_s", "vys_m_s", "vxp_m_s", "vyp_m_s", "vyr_m_s",
];

/// Build the scenario the flags describe (all validation errors are `bearing-model`'s).
pub fn scenario(args: &Args) -> anyhow::Result<Scenario> {
    let class: FaultClass = args.fault.parse()?;
    let set: ParamSet = args.params.parse()?;
    let bearing: Bearing = args.bearing.parse()?;
    anyhow::ensure!(
        args.rpm.is_finite() && args.rpm > 0.0,
        "--rpm must be > 0 (got {})",
        args.rpm
    );
    anyhow::ensure!(
        args.slip.is_finite() && args.slip >= 0.0,
        "--slip must be >= 0 (got {})",
        args.slip
    );
    let mut sc = Scenario::new(set, bearing, args.rpm)
        .with_fs(args.fs)
        .with_duration(args.duration)
        .with_seed(args.seed)
        .with_radial_load(args.radial_load)
        .with_states(args.states)
        .with_slip(if args.slip > 0.0 {
            Slip::Random {
                fraction: args.slip,
            }
        } else {
            Slip::Off
        })
        .with_noise(args.snr_db.map_or(Noise::Off, Noise::SnrDb));
    sc.sim.max_step_s = args.max_step;
    if class != FaultClass::None {
        sc.spec.faults = FaultSet::of_class(
            class,
            Spall::new(args.fault_size * 1e-3).with_depth(args.fault_depth * 1e-3),
        );
    }
    if let Some(f) = args.resonance {
        sc.spec.housing.resonance_hz = f;
    }
    if let Some(t) = args.onset {
        sc = sc.with_fault_onset(t);
    }
    Ok(sc)
}

/// Write a recording as CSV: header `time_s,accel[,states…]`, one row per sample.
pub fn write_csv(path: &Path, rec: &bearing_model::Recording) -> anyhow::Result<()> {
    let f = std::fs::File::create(path).with_context(|| format!("creating {}", path.display()))?;
    let mut w = std::io::BufWriter::new(f);
    write!(w, "time_s,accel")?;
    if rec.states.is_some() {
        for n in STATE_NAMES {
            write!(w, ",{n}")?;
        }
    }
    writeln!(w)?;
    for (k, a) in rec.accel.iter().enumerate() {
        write!(w, "{:.9},{:e}", rec.time(k), a)?;
        if let Some(st) = &rec.states {
            for v in st[k].iter() {
                write!(w, ",{v:e}")?;
            }
        }
        writeln!(w)?;
    }
    w.flush()?;
    Ok(())
}

/// Run the task.
pub fn run(args: Args) -> anyhow::Result<()> {
    let sc = scenario(&args)?;
    let model = sc.model().context("invalid model parameters")?;
    let t = std::time::Instant::now();
    let rec = bearing_model::simulate(&model, &sc.sim).context("simulation failed")?;
    let wall = t.elapsed().as_secs_f64();
    if let Some(dir) = args.out.parent().filter(|d| !d.as_os_str().is_empty()) {
        std::fs::create_dir_all(dir).with_context(|| format!("creating {}", dir.display()))?;
    }
    write_csv(&args.out, &rec)?;
    let meta = serde_json::json!({
        "generator": "cargo xtask simulate (bearing-model)",
        "columns": { "time_s": "s", "accel": "housing (sprung-mass) acceleration, m/s^2" },
        "fs_hz": rec.fs_hz,
        "samples": rec.accel.len(),
        "step_s": rec.step_s,
        "noise_std_m_s2": rec.noise_std,
        "fault": args.fault,
        "params": args.params,
        "fault_orders": sc.spec.geometry.orders(),
        "shaft_hz": sc.spec.speed.hz(),
        "spec": sc.spec,
        "sim": sc.sim,
    });
    let side = args.out.with_extension("json");
    std::fs::write(&side, serde_json::to_string_pretty(&meta)?)
        .with_context(|| format!("writing {}", side.display()))?;
    let o = sc.spec.geometry.orders().at(sc.spec.speed.hz());
    println!(
        "wrote {} ({} samples at {} Hz, accel in m/s^2; step {:.3e} s; {:.1} simulated s per wall s)",
        args.out.display(),
        rec.accel.len(),
        rec.fs_hz,
        rec.step_s,
        (sc.sim.duration_s + sc.sim.settle_s) / wall.max(1e-9)
    );
    println!(
        "lines: fr {:.2} Hz, FTF {:.2}, BPFO {:.2}, BPFI {:.2}, ball defect (2xBSF) {:.2} Hz; metadata {}",
        sc.spec.speed.hz(),
        o.ftf,
        o.bpfo,
        o.bpfi,
        o.ball_defect,
        side.display()
    );
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;
    use clap::Parser;

    #[derive(clap::Parser)]
    struct Cli {
        #[command(flatten)]
        a: Args,
    }

    fn parse(extra: &[&str]) -> Args {
        let mut v = vec!["simulate"];
        v.extend_from_slice(extra);
        Cli::parse_from(v).a
    }

    #[test]
    fn csv_round_trips_through_the_data_crate() {
        let dir = std::env::temp_dir().join(format!("xtask-sim-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let out = dir.join("rec.csv");
        let args = parse(&[
            "--fault",
            "inner+outer",
            "--duration",
            "0.05",
            "--seed",
            "3",
            "--states",
            "--out",
            out.to_str().unwrap(),
        ]);
        let sc = scenario(&args).unwrap();
        let rec = sc.simulate().unwrap();
        write_csv(&out, &rec).unwrap();
        let sig = bearing_data::read_csv_file(
            &out,
            &bearing_data::CsvOptions::new(rec.fs_hz, bearing_data::Column::Name("accel".into())),
        )
        .unwrap();
        assert_eq!(sig.samples().len(), rec.accel.len());
        for (a, b) in sig.samples().iter().zip(&rec.accel) {
            assert!((a - b).abs() <= 1e-12 * b.abs().max(1e-30));
        }
        std::fs::remove_dir_all(&dir).ok();
    }

    #[test]
    fn bad_flags_are_errors() {
        let bad = |extra: &[&str]| {
            let mut v = extra.to_vec();
            v.extend_from_slice(&["--out", "/nonexistent/x.csv"]);
            let a = parse(&v);
            scenario(&a).and_then(|s| Ok(s.model()?)).and_then(|_| {
                let s = scenario(&a)?;
                Ok(s.simulate()?)
            })
        };
        assert!(bad(&["--rpm", "0"]).is_err());
        assert!(bad(&["--fault", "outer", "--fault-size", "-1"]).is_err());
        assert!(bad(&["--fault", "inner", "--fault-size", "20"]).is_err());
        assert!(bad(&["--fs", "2000"]).is_err());
        assert!(bad(&["--fault", "cage"]).is_err());
        assert!(bad(&["--params", "foo"]).is_err());
    }
}
